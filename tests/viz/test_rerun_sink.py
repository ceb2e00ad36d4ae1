"""Record a generated scene headless, read the .rrd back and check it against the core."""

import numpy as np
import pyarrow as pa
import pytest
import rerun as rr
from rerun.chunk import RrdReader

from rrd_helpers import rows_by_frame

import conecull
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
    for key in ("entries", "added", "removed"):
        rows = rows_by_frame(path, f"/stats/front/{key}", "Scalars:scalars")
        assert [v[0] for _, v in sorted(rows.items())] == [s[f"front_{key}"] for s in stats]
    assert max(s["front_added"] for s in stats) > 0 and min(s["front_entries"] for s in stats) > 0
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
