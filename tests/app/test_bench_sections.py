"""The benchmark sections other than `bench all` (dcd, trace, contour, threads, first-hit, front) run headless at toy
sizes and write their JSON. Their timings are not tested; their counters are, against the
invariants of the methods (a front gives the candidates of a traversal from the root, cones only
remove candidates, every method finds the same pairs)."""

import json

import pytest

from conecull.app.cli import main


def run(tmp_path, section, *extra):
    out = tmp_path / section
    assert main(["bench", section, "--triangles", "2000", "--frames", "2", "--repeats", "1", "--out", str(out),
                 *extra]) == 0
    return json.loads((out / f"{section}.json").read_text())


def test_bench_dcd(tmp_path):
    res = run(tmp_path, "dcd")
    rows = {(r["method"], r["leaf_size"]): r for r in res["results"]}
    methods = {m for m, _ in rows}
    assert methods == {"aabb", "nc", "aabb+front", "nc+front", "sct", "cbc"}
    for leaf in {ls for _, ls in rows}:
        tests = {m: rows[m, leaf]["elementary_tests"] for m in methods}
        assert tests["aabb+front"] == tests["aabb"] and tests["nc+front"] == tests["nc"], leaf
        assert all(tests[m] <= tests["aabb"] for m in methods), (leaf, tests)
        assert tests["nc"] < tests["aabb"], (leaf, tests)  # the folded sheet has cullable regions


def test_bench_trace(tmp_path, capsys, monkeypatch):
    """It needs the hook-free build of the core, which `./dev.sh bench` adds (the test command
    does not): without it, the section says how to build it and fails. Then the section runs with
    the hooked core standing in for the hook-free one, so that its tables and JSON are tested
    wherever the tests run (the timings are not: benchmarks, not timed tests)."""
    import sys

    import conecull
    from conecull import _core

    try:
        from conecull import _core_nohooks  # noqa: F401
    except ImportError:
        assert main(["bench", "trace", "--triangles", "2000", "--frames", "2", "--repeats", "1",
                     "--out", str(tmp_path / "trace")]) != 0
        assert "conecull._core_nohooks is not built: reinstall with" in capsys.readouterr().out
        monkeypatch.setitem(sys.modules, "conecull._core_nohooks", _core)
        monkeypatch.setattr(conecull, "_core_nohooks", _core, raising=False)
    res = run(tmp_path, "trace")
    assert set(res["median_ms"]) == {"hook-free build", "trace off", "trace on"}
    assert all(len(v) == res["frames"] for v in res["per_frame_ms"].values())


def test_bench_contour(tmp_path):
    res = run(tmp_path, "contour")
    rows = {(r["query"], r["method"]): r for r in res["rows"]}
    assert set(rows) == {("DCD", "nc"), ("DCD", "sct"), ("DCD", "cbc"), ("CCD", "nc"), ("CCD", "cbc")}
    for q in ("DCD", "CCD"):
        pairs = {rows[k]["colliding_pairs"] for k in rows if k[0] == q}
        assert len(pairs) == 1, (q, pairs)
    assert all(r["contour_tests"] > 0 and r["contour_passed"] <= r["contour_tests"] for r in rows.values())


@pytest.mark.parametrize("threads", ["2", "3"])
def test_bench_threads(tmp_path, threads):
    res = run(tmp_path, "threads", "--threads", threads)
    got = {(r["kind"], r["query"], r["threads"]) for r in res["rows"]}
    queries = {(k, q) for k, q, _ in got}
    assert {("dcd", m) for m in ("aabb", "nc", "aabb+front", "nc+front")} <= queries
    assert {("ccd", f"ccd {a}") for a in ("float", "conservative", "exact")} <= queries
    assert got == {(k, q, t) for k, q in queries for t in (1, int(threads))}
    before, after = res["compute_ceiling"]  # the machine's ceiling, before and after the queries
    assert before > 0 and after > 0


def test_bench_first_hit(tmp_path):
    """stop_at_first against the full queries (here the generated step only): the first hit is
    one of the full query's collisions (the section checks it), made after fewer pairs and tests."""
    out = tmp_path / "first-hit"
    assert main(["bench", "first-hit", "--triangles", "2000", "--repeats", "1", "--skip", "steps",
                 "--out", str(out)]) == 0
    rows = json.loads((out / "first_hit.json").read_text())["rows"]
    assert [r["method"] for r in rows] == ["nc", "nc+front"]
    for r in rows:
        assert r["ccd_colliding"] and r["ccd_first_hit_tests"] <= r["ccd_tests"], r
        assert r["ccd_first_hit_pairs"] <= r["ccd_pairs"] and r["dcd_first_hit_tests"] <= r["dcd_tests"], r
    assert rows[0]["ccd_first_hit_pairs"] < rows[0]["ccd_pairs"] / 4  # nc stops making pairs early


def test_bench_first_hit_says_when_the_real_steps_are_missing(tmp_path, monkeypatch, capsys):
    """Without the shared data the real steps are left out saying why (they were dropped silently)."""
    monkeypatch.setenv("CONECULL_SHARED", str(tmp_path / "nowhere"))
    assert main(["bench", "first-hit", "--triangles", "2000", "--repeats", "1", "--out", str(tmp_path / "o")]) == 0
    text = capsys.readouterr().out
    assert "no data folder" in text and "only the generated step is measured" in text


def test_bench_first_hit_bad_skip(capsys):
    assert main(["bench", "first-hit", "--skip", "scenes"]) == 2
    assert "--skip: first-hit can leave out 'steps', got ['scenes']" in capsys.readouterr().err


def test_bench_front(tmp_path, capsys):
    """Fig. 11 alone: per scene and frame the front entries of both front methods, whose ratio
    (median over the frames with a front) is the table's, and nc+front keeps no more entries
    than aabb+front on any frame (a culled node keeps no front)."""
    import statistics

    out = tmp_path / "front"
    assert main(["bench", "front", "--scenes", "crumple,fold", "--out", str(out)]) == 0
    rows = json.loads((out / "front.json").read_text())
    assert [r["scene"] for r in rows] == ["crumple", "fold"]
    for r in rows:
        nc, ab = r["nc+front"], r["aabb+front"]
        assert len(nc) == len(ab) == r["frames"] and all(a <= b for a, b in zip(nc, ab))
        assert r["front_ratio"] == pytest.approx(statistics.median(a / b for a, b in zip(nc, ab) if b))
        cnc, cab = r["ccd_nc+front"], r["ccd_aabb+front"]  # Fig. 11's CCD row: the last 8 frames' steps
        assert len(cnc) == len(cab) == min(8, r["frames"]) - 1 and all(a <= b for a, b in zip(cnc, cab))
        assert r["ccd_front_ratio"] == pytest.approx(statistics.median(a / b for a, b in zip(cnc, cab) if b))
        bound = r["bound"]  # the last frame: no cone test keeps less than the bound, ours no less than it
        assert 0 <= bound["bound"] <= bound["ours"] <= bound["aabb_front"], bound
    out_text = capsys.readouterr().out
    assert "| crumple |" in out_text and "Could any cone test make the front smaller?" in out_text
    assert main(["bench", "front", "--scenes", "crumple,nope", "--out", str(out)]) == 2
    assert "--scenes: unknown scene 'nope'" in capsys.readouterr().err


def test_bench_front_leaf_size(tmp_path):
    """--leaf-size builds every collider of the table and of the bound with that many triangles per
    leaf: the counts are those of a collider made so, and differ from the default's."""
    import conecull
    from conecull.app.evaluation import COUNT_FRAMES, EVAL_FRAMES, _window
    from conecull.datasets import load

    counts = {}
    for leaf in (1, 2):
        out = tmp_path / f"leaf{leaf}"
        assert main(["bench", "front", "--scenes", "fold", "--leaf-size", str(leaf), "--out", str(out)]) == 0
        (row,) = json.loads((out / "front.json").read_text())
        assert row["leaf_size"] == leaf
        counts[leaf] = row["nc+front"]
    F, P = load("fold", None, EVAL_FRAMES.get("fold"))
    W = _window(P, COUNT_FRAMES)
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=P.shape[1]), method="nc+front", leaf_size=1, threads=1)
    col.dcd(W[0])  # the BVH from the window's first frame, as the bench builds it
    assert counts[1] == [col.dcd(V).stats["front_entries"] for V in W]
    assert counts[1] != counts[2]


def _tamper(monkeypatch, kind, when):
    """Wrap SelfCollider.dcd or .ccd so that, for the colliders `when(collider)` picks, an answer
    keeps its count but loses its order (two rows swapped): a count or a counter compares equal,
    only the arrays tell."""
    import conecull

    real = getattr(conecull.SelfCollider, kind)

    def swapped(rows):
        rows = rows.copy()
        if len(rows) >= 2:
            rows[[0, -1]] = rows[[-1, 0]]
        return rows

    def query(self, *a, **k):
        res = real(self, *a, **k)
        if when(self):  # the timed frames and steps have many contacts (the tests check an error is raised)
            if kind == "dcd":
                res.pairs = swapped(res.pairs)
            else:
                res.vf, res.ee = swapped(res.vf), swapped(res.ee)
        return res

    monkeypatch.setattr(conecull.SelfCollider, kind, query)


@pytest.mark.parametrize("section, kind, when, msg", [
    ("dcd", "dcd", lambda c: c.method == "cbc" and c.leaf_size == 4,
     r"bench dcd: cbc \(leaf 4, 1 thread\(s\)\) in run 1 disagrees with aabb \(leaf 1, 1 thread\(s\)\) in run 1 on "
     r"the colliding pairs of frame 1; please report this as a bug"),
    ("contour", "dcd", lambda c: c.method == "sct",
     r"bench contour: sct in run 1 disagrees with nc in run 1 on the DCD answer at frame 1; please report this as a bug"),
    ("contour", "ccd", lambda c: c.method == "cbc",
     r"bench contour: cbc in run 1 disagrees with nc in run 1 on the CCD answer at step 0 -> 1"),
    ("threads", "dcd", lambda c: c.threads == 2 and c.method == "nc+front",
     r"bench threads: nc\+front \(leaf 2, 2 thread\(s\)\) in run 1 disagrees with aabb \(leaf 2, 1 thread\(s\)\) in "
     r"run 1 on the colliding pairs of frame 1"),
    ("threads", "ccd", lambda c: c.threads == 2,
     r"bench threads: ccd float on 2 threads \(run 1\) disagrees with 1 thread \(run 1\) on the VF / EE contacts"),
])
def test_sections_compare_every_answer_pair_for_pair(tmp_path, monkeypatch, section, kind, when, msg):
    """A method (or thread count) whose answer has the right count but other rows stops the suite
    with an error naming it, the frame or step and the suite; an `assert` (stripped by python -O)
    on counts or counters let it through."""
    _tamper(monkeypatch, kind, when)
    with pytest.raises(RuntimeError, match=msg):
        main(["bench", section, "--triangles", "2000", "--frames", "2", "--repeats", "1", "--out",
              str(tmp_path / section)])


def test_sections_compare_every_run_not_only_the_first(tmp_path, monkeypatch):
    """The second run of a query answering otherwise than the first is caught too."""
    calls = {}

    def second_run(col):  # each collider's calls: its build (frame 0), then one per run
        calls[id(col)] = calls.get(id(col), 0) + 1
        return col.method == "nc" and calls[id(col)] == 3

    _tamper(monkeypatch, "dcd", second_run)
    with pytest.raises(RuntimeError, match=r"bench contour: nc in run 2 disagrees with nc in run 1 on the DCD answer at frame 1"):
        main(["bench", "contour", "--triangles", "2000", "--frames", "2", "--repeats", "2", "--out",
              str(tmp_path / "c")])


def test_bench_ccd_generated_steps_and_the_median(tmp_path, monkeypatch, capsys):
    """On the generated steps exact CCD is the reference, so its FN / FP are '= ref' (not a
    measured 0); 'us per test' is the median of the runs, as the header says (it was the last)."""
    import statistics

    import conecull
    from conecull.datasets import shared

    monkeypatch.setattr(shared, "shared_data_dir", lambda: None)  # the generated steps alone
    real = conecull.SelfCollider.ccd
    n = [0]

    def ccd(self, *a, **k):  # seconds in the elementary tests: 1, 4, 9, ... ms, call after call
        res = real(self, *a, **k)
        n[0] += 1
        res.stats["seconds_elementary"] = 1e-3 * n[0] ** 2
        return res

    monkeypatch.setattr(conecull.SelfCollider, "ccd", ccd)
    out = tmp_path / "ccd"
    assert main(["bench", "ccd", "--triangles", "2000", "--repeats", "3", "--out", str(out)]) == 0
    rows = json.loads((out / "ccd.json").read_text())["rows"]
    text = capsys.readouterr().out
    assert [r["step"] for r in rows] == ["generated fold (2.0K, exact grid)"] * 3 + ["generated fold (2.0K, jittered)"] * 3
    # FN / FP recounted here against exact mode, on the same steps with the same method
    from conecull.app.bench import _generated_ccd_steps

    want = {}
    for name, F, V0, V1, _, _ in _generated_ccd_steps(2000):
        c = conecull.SelfCollider(conecull.Mesh(F, n_vertices=len(V0)), method="nc")
        got = {m: real(c, V0, V1, arithmetic=m) for m in ("exact", "conservative", "float")}
        ref = {(k, tuple(x)) for k in ("vf", "ee") for x in getattr(got["exact"], k).tolist()}
        for m in ("conservative", "float"):
            mine = {(k, tuple(x)) for k in ("vf", "ee") for x in getattr(got[m], k).tolist()}
            want[name, m] = (len(ref - mine), len(mine - ref))
    assert all(want[k][0] == 0 for k in want if k[1] == "conservative")  # conservative never misses
    for r in rows:
        assert (r["fn"] is None and r["fp"] is None) == (r["mode"] == "exact"), r
        assert r["mode"] == "exact" or (r["fn"], r["fp"]) == want[r["step"], r["mode"]], r
        assert f"| {r['step']} | exact | " in text
    assert text.count("| = ref | = ref |") == 2 and "the reference is exact CCD itself" in text
    # per step 3 runs x 3 modes, the modes taking turns: float is call 1, 4, 7 of the first step
    first = rows[0]
    assert first["mode"] == "float"
    assert first["us_per_test"] == pytest.approx(statistics.median(1e3 * c ** 2 for c in (1, 4, 7)) / first["elementary_tests"])
