"""Record a generated scene headless, read the .rrd back and check it against the core."""

import dataclasses
import os

import numpy as np
import pyarrow as pa
import pytest
import rerun as rr
from rerun.chunk import RrdReader

from rrd_helpers import log_rows, rows_by_frame, rows_by_frame_static

import conecull
from conecull.normal_spread import Normals, node_spreads, normal_spread
from conecull.datasets.inputs import load_sequence
from conecull.viz.rerun_sink import record

ENTITIES = {"/scene/mesh", "/scene/contours/failed", "/scene/contours/kernel", "/scene/contours/ray", "/scene/cones",
            "/scene/bvh", "/stats/tests/cone", "/stats/verdict/culled", "/stats/collisions", "/stats/ms/refit", "/log"}


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    rr.set_strict_mode(True)  # bad shapes raise instead of warning
    F, frames = load_sequence("crumple")
    path = str(tmp_path_factory.mktemp("rrd") / "crumple.rrd")
    stats = record(path, F, frames, recording_id="test-crumple")
    return path, F, frames, stats


def test_entities_and_frames(recording):
    path, F, frames, stats = recording
    store = RrdReader(path).stream().collect()
    entities = set()
    for chunk in store.stream():
        md = chunk.to_record_batch().schema.metadata or {}
        entities.add(md.get(b"rerun:entity_path", b"").decode())
    assert ENTITIES <= entities, ENTITIES - entities
    collisions = rows_by_frame(path, "/stats/collisions", "Scalars:scalars")
    assert sorted(collisions) == list(range(len(frames)))
    assert [v[0] for _, v in sorted(collisions.items())] == [s["colliding_pairs"] for s in stats]


def test_failing_contour_strips_match_core(recording):
    path, F, frames, stats = recording
    strips = rows_by_frame(path, "/scene/contours/failed", "LineStrips3D:strips")
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=frames.shape[1]))
    col.dcd(frames[0])
    checked = 0
    for k in range(len(frames)):
        expect = col.dcd(frames[k]).stats["contour_failed"]
        assert len(strips.get(k) or []) == expect, f"frame {k}"
        checked += expect > 0
    assert checked >= 3  # the scene really has failing contours to draw


def test_front_growth_is_recorded(tmp_path):
    """With a front method the recording carries the front's size and its changes per frame,
    equal to the core's stats."""
    F, frames = load_sequence("fold")
    path = str(tmp_path / "front.rrd")
    stats = record(path, F, frames[-6:], method="nc+front", recording_id="test-front")  # folded: a front
    for key in ("entries", "added", "removed", "rested"):
        rows = rows_by_frame(path, f"/stats/front/{key}", "Scalars:scalars")
        assert [v[0] for _, v in sorted(rows.items())] == [s[f"front_{key}"] for s in stats]
    # A frame with a collision keeps a front (its root is not culled); the fold passes through
    # itself on the last two of these frames (the first may be culled whole).
    assert max(s["front_added"] for s in stats) > 0 and sum(s["colliding_pairs"] > 0 for s in stats) >= 2
    assert all(s["front_entries"] > 0 for s in stats if s["colliding_pairs"])
    contour_ms = rows_by_frame(path, "/stats/ms/contour", "Scalars:scalars")
    assert len(contour_ms) == 6


def test_front_drawn_on_the_mesh(tmp_path):
    """A front method's recording colours each face by the front entries reaching it
    (/front/mesh), frame by frame as a replay of the same queries computes them; other methods
    log no /front entity."""
    from conecull.viz.layers import front_colors

    F, frames = load_sequence("fold")
    frames = frames[-6:]
    path = str(tmp_path / "front.rrd")
    record(path, F, frames, method="nc+front", recording_id="test-front-mesh")
    colors = rows_by_frame(path, "/front/mesh", "Mesh3D:vertex_colors")
    assert sorted(colors) == list(range(len(frames)))
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=frames.shape[1]), method="nc+front")
    col.dcd(frames[0])
    distinct = 0
    for k, V in enumerate(frames):
        col.dcd(V)
        load = col.front_load()
        want = np.repeat(front_colors(load), 3, axis=0)
        got = np.array(colors[k], dtype=np.int64)  # packed 0xRRGGBBAA per vertex
        rgb = np.stack([(got >> 24) & 255, (got >> 16) & 255, (got >> 8) & 255], axis=1)
        assert np.array_equal(rgb, want), f"frame {k}"
        distinct = max(distinct, len(np.unique(load)))
    assert distinct > 3  # the front really varies over the mesh
    plain = str(tmp_path / "plain.rrd")
    record(plain, F, frames[:2], method="nc", recording_id="test-no-front")
    assert rows_by_frame(plain, "/front/mesh", "Mesh3D:vertex_colors") == {}


@pytest.fixture(scope="module")
def small():
    from conecull.datasets.generated import folding_sheet

    return folding_sheet(50, 6)


@pytest.mark.parametrize("kwargs,match", [
    ({"frames": lambda P: P[0]}, r"frames: expected a sequence of frames of shape \(T, n, 3\), got one pose"),
    ({"frames": lambda P: P[:0]}, r"frames: no frames \(shape \(0, "),
    ({"frames": lambda P: P[:, :5]}, "frames: 5 vertices per frame, but faces use vertex"),
    ({"frames": lambda P: np.where(np.arange(P.size).reshape(P.shape) == P[0].size * 3 + 16, np.nan, P)},
     "frames: frame 3 has a non-finite coordinate nan at row 5, column 1"),
    ({"frames": lambda P: np.concatenate([P[:2], P[2:] * 1e300])}, r"frames: coordinate \S+ in frame 2 at row \d+, column \d+ is outside the supported range"),
    ({"frame_range": range(0, 10)}, r"frame_range: range\(0, 10\) reaches frame 9, out of range: the input has "
                                    r"frames 0\.\.5"),
    ({"frame_range": [-1]}, "frame_range: frame -1 is out of range"),
    ({"frame_range": [2, 6]}, "frame_range: frame 6 is out of range"),
    ({"frame_range": [1.0]}, "frame_range: expected integer frame indices, got 1.0"),
    ({"frame_range": []}, "frame_range: selects no frame"),
    ({"bvh_depth": "a"}, r"bvh_depth: expected a BVH depth in \[0, 64\], got 'a'"),
    ({"bvh_depth": -1}, r"bvh_depth: expected a BVH depth in \[0, 64\], got -1"),
    ({"bvh_depth": 1000}, r"bvh_depth: expected a BVH depth in \[0, 64\], got 1000"),
    ({"arithmetic": "xx"}, "arithmetic: expected one of float, conservative, exact, got 'xx'"),
    ({"method": "xx"}, "method: expected one of"),
    ({"method": "sct", "ccd": True}, "method: 'sct' is a discrete"),
    ({"path": "/proc/conecull-test.rrd"}, "path: cannot write '/proc/conecull-test.rrd'"),
    ({"progress": 5}, "progress: expected None or a function"),
    ({"compare": "nc"}, "compare: expected a list of method names, got 'nc'"),
    ({"compare": ["nc", "sct", "nc"]}, "compare: 'nc' given twice"),
    ({"compare": ["nc", "xx"]}, "compare: expected one of .*, got 'xx'"),
    ({"compare": ["sct"], "ccd": True}, "compare: 'sct' is a discrete"),
])
def test_record_names_bad_arguments(small, tmp_path, kwargs, match):
    """Each bad argument is refused up front with its name: no IndexError or AttributeError
    from deep inside, no silently ignored option, no file written."""
    F, P = small
    kwargs = dict(kwargs)
    if callable(kwargs.get("frames")):
        kwargs["frames"] = kwargs["frames"](P)
    frames = kwargs.pop("frames", P)
    path = kwargs.pop("path", str(tmp_path / "r.rrd"))
    if path.startswith("/proc") and not os.path.isdir("/proc"):
        pytest.skip("no /proc")
    with pytest.raises(ValueError, match=match):
        record(path, F, frames, **kwargs)
    assert not (tmp_path / "r.rrd").exists()


def test_record_takes_nested_lists(small, tmp_path):
    F, P = small
    stats = record(str(tmp_path / "r.rrd"), F.tolist(), P.tolist(), frame_range=[0, 5])
    assert len(stats) == 2


def _replay(F, frames, method, ccd=False):
    """Untraced queries of `method` on a fresh collider fed frames[0], then each frame (or step)."""
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=frames.shape[1]), method=method)
    col.dcd(frames[0])
    if ccd:
        return [col.ccd(frames[k], frames[k + 1]).stats for k in range(len(frames) - 1)]
    return [col.dcd(V).stats for V in frames]


@pytest.mark.parametrize("ccd,methods", [(False, ("nc", "sct", "cbc", "nc+front")), (True, ("nc", "cbc", "aabb+front"))])
def test_compare_logs_each_method(tmp_path, ccd, methods):
    """record(compare=...) plots, per compared method and frame, its contour tests and
    elementary tests (equal to a replay of the same untraced queries: the counters are
    deterministic), its contour-test time (> 0 where it ran contour tests) and its query time."""
    F, frames = load_sequence("fold")
    frames = frames[24:30]  # folding through itself: contour tests fail and pass, contacts from frame 28
    path = str(tmp_path / "cmp.rrd")
    stats = record(path, F, frames, method="nc", ccd=ccd, compare=methods, recording_id="test-compare")
    assert stats[-1]["colliding_pairs"] > 0  # the methods' agreement is checked on real contacts
    n = len(frames) - 1 if ccd else len(frames)
    for m in methods:
        want = _replay(F, frames, m, ccd)
        base = f"/stats/compare/{m.replace('+', '_')}"
        got = {key: rows_by_frame(path, f"{base}/{key}", "Scalars:scalars")
               for key in ("contour_tests", "elementary_tests", "contour_ms", "query_ms")}
        for key in got:
            assert sorted(got[key]) == list(range(n)), (m, key)
        for key in ("contour_tests", "elementary_tests"):
            assert [got[key][k][0] for k in range(n)] == [s[key] for s in want], (m, key)
        assert all((got["contour_ms"][k][0] > 0) == (want[k]["contour_tests"] > 0) for k in range(n)), m
        assert all(got["query_ms"][k][0] > 0 for k in range(n)), m
        assert rows_by_frame_static(path, f"{base}/contour_ms", "SeriesLines:names") == [f"{m}: contour-test ms"]
    assert max(s["contour_tests"] for s in _replay(F, frames, "cbc", ccd)) > 0


def test_compare_refuses_a_method_that_disagrees(tmp_path, monkeypatch):
    """Methods must agree on the collisions: a compared method that answers otherwise (here made
    to drop one pair) stops the recording with a RuntimeError naming it and the frame, and
    leaves no recording behind."""
    F, frames = load_sequence("fold")
    frames = frames[27:30]  # the fold intersects itself from frame 28 on
    real = conecull.SelfCollider.dcd

    def lossy(self, V, *args, **kwargs):
        res = real(self, V, *args, **kwargs)
        if self.method == "sct" and len(res.pairs):
            return dataclasses.replace(res, pairs=res.pairs[1:])
        return res

    monkeypatch.setattr(conecull.SelfCollider, "dcd", lossy)
    path = tmp_path / "cmp.rrd"
    with pytest.raises(RuntimeError, match=r"compare: method 'sct' found other collisions than 'nc' at frame \d"):
        record(str(path), F, frames, method="nc", compare=["sct"], recording_id="test-disagree")
    assert not path.exists()


def test_a_failed_last_write_is_an_error_naming_the_file(tmp_path, monkeypatch):
    """A write that fails at the end (a disk filling up while recording; simulated: rerun's flush
    raising as it does for a full disk) is an OSError naming the file, and the cut-short file is
    removed, not left to pass for a whole run."""
    from conecull.datasets.generated import folding_sheet
    from conecull.viz.rerun_sink import record

    F, P = folding_sheet(200, 3)

    def full(self, *args, **kwargs):
        raise RuntimeError("Failed to write: No space left on device (os error 28)")

    monkeypatch.setattr(rr.RecordingStream, "flush", full)
    out = tmp_path / "run.rrd"
    with pytest.raises(OSError, match=r"cannot write the recording '.*run\.rrd' \(Failed to write: No space left"):
        record(str(out), F, P)
    assert not out.exists()


def test_every_contour_reason_has_a_colour():
    """Both sinks colour a failing contour by its reason: one without a colour crashed `record`
    and `view` with the sct and cbc baselines (KeyError 6 and 7) on the crumple scene."""
    from conecull.trace import REASONS
    from conecull.viz.layers import REASON_COLORS

    assert set(REASONS) <= set(REASON_COLORS)


@pytest.mark.parametrize("method,frames,code", [("sct", (0, 2), 6), ("cbc", (26, 27), 7)])
def test_baselines_own_failures_are_recorded(tmp_path, method, frames, code):
    """crumple's frames where the sct line search finds no kernel point (reason 6) and where cbc
    cannot prove two contour edges apart (reason 7): recorded, each strip labelled with it."""
    from conecull.trace import reason_name

    F, P = load_sequence("crumple")
    path = str(tmp_path / f"{method}.rrd")
    record(path, F, P, method=method, frame_range=range(*frames))
    labels = rows_by_frame(path, "/scene/contours/failed", "LineStrips3D:labels")
    assert any(label.endswith(": " + reason_name(code)) for v in labels.values() for label in v or []), labels
    # each strip names its node and reason, as the core's trace has them
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=P.shape[1]), method=method)
    col.dcd(P[0])
    for k in range(*frames):
        c = col.dcd(P[k], trace=True).trace.contour
        fail = (c["reason"] > 0) & (c["reason"] < 16)
        assert labels.get(k) == [f"node {n}: {reason_name(r)}" for n, r in zip(c["node"][fail].tolist(),
                                                                             c["reason"][fail].tolist())], k


def test_each_frame_has_its_story_as_one_page(recording):
    """The log view cuts long lines: /story holds each frame's log lines, whole, as one page."""
    path, F, frames, stats = recording
    story = rows_by_frame(path, "/story", "TextDocument:text")
    log = log_rows(path)
    assert sorted(story) == list(range(len(frames)))
    for k, rows in log.items():
        page = story[k][0] if isinstance(story[k], list) else story[k]
        assert page.splitlines()[2:] == [f"- {t}" for _, t in rows], k


def test_verdict_series_wear_the_mesh_colours(tmp_path):
    from conecull.viz import layers as L

    F, P = load_sequence("fold")
    path = str(tmp_path / "c.rrd")
    record(path, F, P, frame_range=[28])
    packed = lambda rgb: (rgb[0] << 24) | (rgb[1] << 16) | (rgb[2] << 8) | 255  # noqa: E731
    for entity, rgb in (("/stats/verdict/culled", L.STATUS_COLORS[L.CULLED]),
                        ("/stats/verdict/cone_too_wide", L.STATUS_COLORS[L.CONE_FAILED]),
                        ("/stats/collisions", L.STATUS_COLORS[L.COLLIDING])):
        got = rows_by_frame_static(path, entity, "SeriesLines:colors")
        assert got == [[packed([int(c) for c in rgb])]] or got == [packed([int(c) for c in rgb])], (entity, got)


def test_collisions_are_named_and_explained(recording):
    """Which triangles collide is in the recording, by id: a labelled point per colliding pair,
    and the log's first lines (warnings) say, per pair, why the smallest node holding both was not
    culled, as explain.collision_sentences does; the failing nodes follow."""
    from conecull.viz.explain import collision_sentences

    path, F, frames, stats = recording
    labels = rows_by_frame(path, "/scene/collisions", "Points3D:labels")
    log = log_rows(path)
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=frames.shape[1]))
    col.dcd(frames[0])
    seen = 0
    for k in range(len(frames)):
        res = col.dcd(frames[k], trace=True)
        assert (labels.get(k) or []) == [f"{i} x {j}" for i, j in res.pairs.tolist()], k
        want = collision_sentences(col, res, 100)
        lines = log.get(k, [])
        assert [t for _, t in lines[: len(want)]] == want, k
        assert all(level == "WARN" for level, _ in lines[: len(want)])
        assert all(level == "INFO" for level, _ in lines[len(want) + (len(res.pairs) > 100):])
        seen += len(want)
    assert seen > 100


def test_ccd_contacts_are_labelled_with_ids(tmp_path):
    F, frames = load_sequence("fold")
    path = str(tmp_path / "ccd.rrd")
    record(path, F, frames, frame_range=[27], ccd=True)
    col = conecull.SelfCollider(conecull.Mesh(F))
    col.dcd(frames[0])
    res = col.ccd(frames[27], frames[28], toi=True)
    vf = rows_by_frame(path, "/scene/contacts/vf", "Points3D:labels")[27]
    ee = rows_by_frame(path, "/scene/contacts/ee", "LineStrips3D:labels")[27]
    assert [s.rsplit(" ", 1)[0] for s in vf] == [f"v{v} f{f}" for v, f in res.vf.tolist()]
    assert [s.rsplit(" ", 1)[0] for s in ee] == [f"e{a} e{b}" for a, b in res.ee.tolist()]
    for label, t in zip(vf, res.toi):  # the certified bound rounded down, never up
        shown = float(label.rsplit("t>=", 1)[1])
        assert shown <= t < shown + 1e-3


def test_only_the_methods_own_verdicts_are_plotted(tmp_path):
    """The baselines' own contour verdicts (sct's, cbc's) are not plotted, always 0, for the others."""
    F, frames = load_sequence("fold")
    got = {}
    for method in ("nc", "cbc"):
        path = str(tmp_path / f"{method}.rrd")
        record(path, F, frames, method=method, frame_range=[0])
        got[method] = {(chunk.to_record_batch().schema.metadata or {}).get(b"rerun:entity_path", b"").decode()
                       for chunk in RrdReader(path).stream().collect().stream()}
    assert "/stats/verdict/contour_edges_may_overlap" in got["cbc"] - got["nc"]
    assert not any(e.endswith("no_kernel_on_search_line") for e in got["nc"] | got["cbc"])
    assert "/stats/verdict/contour_not_star_shaped" in got["nc"]
    # cbc's edge-pair test gives only its own verdict, never Alg. 1's
    assert not any(e.startswith("/stats/verdict/contour_") and not e.endswith("edges_may_overlap") for e in got["cbc"])


def test_sct_draws_no_kernel_point_where_it_found_none():
    """sct's line search may find no kernel point (reason 6): the trace's kernel and ray there are
    fillers, not drawn; its other failures (a kernel point found, the star test failed) would be
    (on the generated scenes sct fails only so; nc's drawn kernels: test_cbc_failures_draw_no_kernel_point)."""
    import conecull
    from conecull.viz import layers as L

    F, P = load_sequence("crumple")
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=P.shape[1]), method="sct")
    col.dcd(P[0])
    seen = set()
    for k in (0, 1, 26):
        lay = L.compute(col, F, P[k], col.dcd(P[k], trace=True))
        drawn = np.isfinite(lay.kernels).all(axis=1)
        assert np.array_equal(drawn, lay.contour_reasons != L.KERNEL_NOT_FOUND), k
        assert np.isnan(lay.rays[~drawn]).all() and np.isfinite(lay.rays[drawn]).all()
        seen |= set(drawn.tolist())
    assert False in seen  # the line search failed somewhere here


def _entities(path):
    return {(chunk.to_record_batch().schema.metadata or {}).get(b"rerun:entity_path", b"").decode()
            for chunk in RrdReader(path).stream().collect().stream()}


def test_culled_patches_and_failed_nodes_are_drawn(tmp_path):
    """Per frame: one outline per culled node (the contour its test passed, labelled with its
    id), one labelled box per node not culled (cone too wide, contour failed, or no single simple
    contour), and cone arrows only where a cone was bounded (a cone too wide has no axis)."""
    import conecull
    from conecull.trace import reason_name
    from conecull.viz import layers as L

    F, P = load_sequence("fold")
    path = str(tmp_path / "fold.rrd")
    record(path, F, P, frame_range=range(24, 30))
    culled = rows_by_frame(path, "/scene/culled", "LineStrips3D:labels")
    strips = rows_by_frame(path, "/scene/culled", "LineStrips3D:strips")
    boxes = rows_by_frame(path, "/scene/failed_nodes", "Boxes3D:labels")
    arrows = rows_by_frame(path, "/scene/cones", "Arrows3D:vectors")
    log = log_rows(path)
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=P.shape[1]))
    col.dcd(P[0])
    ct, bvh = col.contour_arrays(), col.bvh_arrays()
    n_boxes = shades = 0
    for k in range(24, 30):
        res = col.dcd(P[k], trace=True)
        s, tr = res.stats, res.trace
        passed = tr.contour["node"][tr.contour["reason"] == 0]
        assert len(passed) == s["contour_passed"] > 0
        assert culled[k] == [f"node {n}: culled" for n in passed.tolist()], k
        for n, strip in zip(passed.tolist(), strips[k]):  # the node's own boundary loop, closed
            loop = ct["vertices"][ct["offsets"][n] : ct["offsets"][n + 1]]
            assert np.allclose(np.asarray(strip), P[k][np.append(loop, loop[0])])
        bad_cones = tr.cone["node"][~tr.cone["bounded"]].tolist()
        failed = [f"node {n}: {reason_name(r)}" for n, r in zip(tr.contour["node"].tolist(), tr.contour["reason"].tolist())
                  if r != 0]
        # a failed cone's label says whether its normals fit in a hemisphere (normal_spread)
        normals = Normals(F, *tr.positions)
        cones = [f"node {n}: cone_too_wide, {L.SPREAD_WORDS[normal_spread(normals, bvh['order'][bvh['begin'][n] : bvh['end'][n]]).kind]}"
                 for n in bad_cones]
        assert sorted(boxes.get(k) or []) == sorted(cones + failed), k
        # the log: the failed cones counted by spread, and each one's sentence says its own
        spreads = node_spreads(normals, bvh, bad_cones)  # the witnesses the recording names
        kinds = [spreads[n] for n in bad_cones]
        assert [sp.kind for sp in kinds] == [normal_spread(normals, bvh["order"][bvh["begin"][n] : bvh["end"][n]]).kind
                                             for n in bad_cones]
        lines = [t for _, t in log.get(k, [])]
        if bad_cones:
            within = sum(sp.kind == "within" for sp in kinds)
            assert any(t.startswith(f"{len(bad_cones)} node") and f"; {within} have their normals within" in t
                       for t in lines), (k, lines)
        for n, sp in zip(bad_cones, kinds):
            assert any(t.startswith(f"node {n} (") and sp.sentence() in t for t in lines), (k, n)
        assert len(boxes.get(k) or []) == s["cone_tests"] - s["cone_passed"] + s["contour_failed"] + s["contour_ineligible"]
        n_boxes += len(boxes.get(k) or [])
        vecs = np.asarray(arrows.get(k) or np.zeros((0, 3)), float).reshape(-1, 3)
        assert (np.linalg.norm(vecs, axis=1) > 0).all(), k  # no zero-length arrow for a cone too wide
        assert len(vecs) == s["cone_passed"] == s["contour_tests"], k  # one per bounded cone
        # the faces: culled ones green, shaded by the depth of the culled node that holds them
        lay = L.compute(col, F, P[k], res)
        green = lay.face_status == L.CULLED
        node = lay.face_node[green]
        assert np.isin(node, passed).all()
        t = L.CULLED_PALE * bvh["depth"][node] / bvh["depth"].max()
        want = np.round(L.STATUS_COLORS[L.CULLED] + t[:, None] * (255.0 - L.STATUS_COLORS[L.CULLED]))
        assert np.array_equal(lay.face_colors[green], want.astype(np.uint8))
        shades = max(shades, len(np.unique(lay.face_colors[green], axis=0)))
    assert n_boxes > 20 and shades > 2  # nodes culled at several depths: several greens


def test_the_recording_says_what_it_is(tmp_path):
    """/about names the method, DCD or CCD (and its arithmetic), the input and the frames, and
    how the timeline reads; each plotted series carries a name in words."""
    from conecull.viz.rerun_sink import SERIES_NAMES

    F, P = load_sequence("fold")
    for ccd, method in ((False, "nc+front"), (True, "cbc")):
        path = str(tmp_path / f"{ccd}.rrd")
        record(path, F, P, method=method, frame_range=range(26, 28), ccd=ccd, source="fold scene",
               arithmetic="conservative" if ccd else "exact")
        about = next(iter(rows_by_frame_static(path, "/about", "TextDocument:text")))
        assert f"Method **{method}**" in about and "fold scene" in about and "2048 triangles" in about
        if ccd:
            assert "**CCD** (conservative arithmetic)" in about and "step from frame k to frame k + 1" in about
            assert "26..27" in about
        else:
            assert "**DCD**" in about and "The front (Alg. 4) is kept between queries" in about
        names = rows_by_frame_static(path, "/stats/tests/box", "SeriesLines:names")
        assert names == [SERIES_NAMES["/stats/tests/box"]]


def test_methods_without_cones_record_no_cone_layers(tmp_path):
    """aabb has no cones nor contours: no empty layers nor always-zero series for them; its own
    counter, the box tests, is plotted (as for every method), and the log says why nothing is culled."""
    F, P = load_sequence("fold")
    path = str(tmp_path / "aabb.rrd")
    stats = record(path, F, P, method="aabb", frame_range=[28])
    got = _entities(path)
    assert not any(e.startswith(("/scene/cones", "/scene/contours", "/scene/culled", "/scene/failed_nodes",
                                 "/stats/verdict", "/stats/tests/cone", "/stats/tests/contour")) for e in got), got
    assert rows_by_frame(path, "/stats/tests/box", "Scalars:scalars")[28] == [stats[0]["bv_tests"]]
    assert any("no normal cones" in t for _, t in log_rows(path)[28])


def test_the_log_says_what_culling_proved_and_whence_the_front(tmp_path):
    F, P = load_sequence("fold")
    path = str(tmp_path / "front.rrd")
    record(path, F, P, method="nc+front", frame_range=range(23, 27))
    log = {k: [t for _, t in rows] for k, rows in log_rows(path).items()}
    assert any(t.startswith("the root (all 2048 triangles) was culled") for t in log[23])
    assert any(t.startswith("front: 0 entries") and "since the previous query (frame 0)" in t for t in log[23])
    assert any("since the previous query (frame 25)" in t for t in log[26])
    assert any(" nodes culled, " in t and "the largest: node " in t for t in log[26])


def test_a_small_mesh_records_with_the_default_depth(tmp_path):
    """The boxes drawn default to depth 4, or the BVH's deepest level when it is shallower (a
    bug-report mesh of two triangles); only a depth asked for explicitly is refused."""
    F = np.array([[0, 1, 2], [1, 3, 2]])
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    path = str(tmp_path / "tiny.rrd")
    record(path, F, np.stack([V, V + 0.1]))
    boxes = rows_by_frame(path, "/scene/bvh", "Boxes3D:half_sizes")
    assert len(boxes[0]) == 1  # the root: depth 0 is this BVH's deepest
    one = str(tmp_path / "one.rrd")  # a single triangle: the log says why nothing was tested
    record(one, F[:1], np.stack([V, V + 0.1]))
    assert [t for _, t in log_rows(one)[0]] == ["the mesh is a single triangle: nothing to collide with, so nothing "
                                                "was tested"]
    record(one, F[:1], np.stack([V, V + 0.1]), method="aabb")  # one line: the method's (the cone lines
    assert [t for _, t in log_rows(one)[0]] == [                  # once broke this chain: both were logged)
        "method aabb: no normal cones, so no node is culled: every pair of overlapping boxes is descended to its "
        "triangles"]
    with pytest.raises(ValueError, match=r"bvh_depth: 1 is deeper than this mesh's BVH, whose nodes are at depths 0\.\.0"):
        record(path, F, np.stack([V, V]), bvh_depth=1)


def test_record_refuses_what_a_dcd_recording_cannot_use(tmp_path):
    F, P = load_sequence("fold")
    with pytest.raises(ValueError, match=r"arithmetic: 'float' is a CCD mode"):
        record(str(tmp_path / "x.rrd"), F, P, arithmetic="float")
    with pytest.raises(ValueError, match=r"frames: CCD records the step from each frame k to k \+ 1, and the input has one frame"):
        record(str(tmp_path / "x.rrd"), F, P[:1], ccd=True)


def test_a_bvh_depth_deeper_than_the_bvh_is_refused(tmp_path):
    F, frames = load_sequence("fold")
    with pytest.raises(ValueError, match=r"bvh_depth: 30 is deeper than this mesh's BVH, whose nodes are at depths 0\.\.\d+"):
        record(str(tmp_path / "x.rrd"), F, frames, bvh_depth=30)
    assert not os.path.exists(tmp_path / "x.rrd")


def test_cbc_failures_draw_no_kernel_point():
    """cbc's edge-pair test has no kernel point and no ray (its trace fills them with the contour's
    mean and a zero ray): its failing contours are drawn without them, nc's with them."""
    import conecull
    from conecull.viz import layers as L

    F, P = load_sequence("crumple")
    for method in ("cbc", "nc"):
        col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=P.shape[1]), method=method)
        col.dcd(P[0])
        lay = L.compute(col, F, P[26], col.dcd(P[26], trace=True))
        assert len(lay.kernels) > 0
        drawn = np.isfinite(lay.kernels).all(axis=1)
        assert (not drawn.any()) if method == "cbc" else drawn.any(), method
