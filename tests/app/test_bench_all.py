"""`conecull bench` (the paper's evaluation) at toy sizes: it runs headless, writes report.md,
JSON and plots, and its counters are those of the core (the timings are not tested)."""

import json
import os

import numpy as np
import pytest

import conecull
from conecull.app.cli import main
from conecull.app.evaluation import run_ipctk, run_steps, time_sequence
from conecull.datasets import load


def test_bench_all_small(tmp_path, capsys):
    out = tmp_path / "b"
    rc = main(["bench", "--scenes", "fold,crumple", "--sizes", "1000,2000", "--frames", "3", "--repeats", "1",
               "--triangles", "2000", "--skip", "steps,ipctk,ccd,threads", "--out", str(out)])
    assert rc == 0
    report = (out / "report.md").read_text()
    for title in ("Query time per method (Fig. 10)", "Front size (Fig. 11)", "Culling efficiency (Fig. 1)",
                  "Contour tests (Fig. 9)", "Scaling"):
        assert title in report
    assert "--scenes fold,crumple" in report  # the command that made it
    res = json.loads((out / "paper.json").read_text())
    fold = res["scenes"][0]
    assert fold["scene"] == "fold" and fold["window"] == 3
    # Fig. 11 / Fig. 1 counters over every frame equal a fresh replay of the same queries.
    F, P = load("fold")
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=P.shape[1]), method="nc+front", threads=1)
    col.dcd(P[0])
    want = [col.dcd(V).stats["front_entries"] for V in P]
    assert [s["front_entries"] for s in fold["all_frames"]["nc+front"]] == want
    assert len(res["scaling"]) == 2
    # The targets table is judged from this run's own figures: here the scenes and the contour
    # test ran, while ipctk, threads and the sizes around 64K did not.
    targets = {t["target"]: t for t in res["targets"]}
    front = next(t for name, t in targets.items() if name.startswith("front entries") and "DCD" in name)
    assert front["values"]["ratios"] == {r["scene"]: r["front_ratio"] for r in res["scenes"]}
    faster = next(t for name, t in targets.items() if name.startswith("nc+front faster") and "DCD" in name)
    assert faster["values"]["vs_nc"]["fold"] == fold["dcd_paired"]["nc"]  # paired (paired_ratios)
    assert faster["values"]["vs_aabb"]["crumple"] == res["scenes"][1]["dcd_paired"]["aabb"]
    assert "vs nc (paired)" in faster["measured"] and "| nc+front vs nc (paired) |" in report
    # 2 timed frames x 1 pass: too few pairs for an interval on both scenes, and the report says so
    assert "(DCD nc+front vs nc: too few pairs on every row for a 95% interval" in report
    contour = next(t for name, t in targets.items() if name.startswith("contour test"))
    assert contour["verdict"] in ("met", "not met") and set(contour["values"]["ratios"]) == {"DCD sct", "DCD cbc", "CCD cbc"}
    for name, t in targets.items():
        if "ipctk" in name or "threads" in name or "per triangle" in name or "float" in name:
            assert t["verdict"] == "not measured", name
    assert "## The targets, from this run" in report
    # Re-rendering from the JSON gives the same scene tables, without timing anything.
    capsys.readouterr()
    assert main(["bench", "--from-json", str(out / "paper.json"), "--out", str(tmp_path / "re")]) == 0
    again = capsys.readouterr().out
    for title in ("Front size (Fig. 11)", "Culling efficiency (Fig. 1)", "The targets, from this run"):
        section = report[report.index(title):].split("\n\n")[1]
        assert section in again
    from shared_data import in_ci

    if _has("matplotlib") or in_ci():  # in CI the plots must be there
        for png in ("fig10_dcd.png", "fig10_ccd.png", "fig11_front.png", "fig1_efficiency.png", "scaling.png",
                    "fig9_contour.png"):
            assert (out / png).stat().st_size > 5000


def _has(module):
    try:
        __import__(module)
        return True
    except ImportError:
        return False


def test_bench_all_rejects_bad_options(capsys):
    assert main(["bench", "--scenes", "nope", "--skip", "steps"]) == 2
    assert "--scenes: unknown scene 'nope'" in capsys.readouterr().err
    assert main(["bench", "--skip", "everything"]) == 2
    assert "--skip: all can leave out 'scenes', 'steps', 'ipctk', 'contour', 'ccd', 'scaling', 'threads', got " \
           "['everything']" in capsys.readouterr().err


def test_time_sequence_times_every_method_and_frame():
    F, P = load("crumple")
    med, per_frame, stats, (paired, intervals) = time_sequence(F, P[-4:], ("aabb", "nc", "nc+front"), 1)
    assert set(med) == {"aabb", "nc", "nc+front"} and len(per_frame["nc"]) == 4
    assert all(len(stats[m]) == 4 and all(s is not None for s in stats[m]) for m in med)
    assert set(paired) == set(med) and paired["nc+front"] == 1.0 and all(v > 0 for v in paired.values())
    assert set(intervals) == set(med) and all(v is None for v in intervals.values())  # 3 pairs: too few
    assert time_sequence(F, P[-3:], ("aabb", "nc"), 1)[3] == ({}, {})  # nothing to pair with


def test_median_interval_is_the_sign_tests():
    """Order statistics k and n + 1 - k, k the largest with P(Binomial(n, 1/2) < k) <= 2.5%,
    checked in rational arithmetic for every n up to 60; None below 6 values."""
    from fractions import Fraction
    from math import comb

    from conecull.app.evaluation import median_interval

    for n in range(1, 61):
        tail = lambda k: sum(Fraction(comb(n, i), 2**n) for i in range(k))  # noqa: E731  P(X < k)
        k = max((k for k in range(n + 1) if tail(k) <= Fraction(1, 40)), default=0)
        values = [10 * i + 3 for i in range(n)][::-1]  # given in any order
        got = median_interval(values)
        assert got == ((10 * (k - 1) + 3, 10 * (n - k) + 3) if k > 0 else None), n
        if k > 0:  # it holds the median, with coverage >= 95%
            assert got[0] <= sorted(values)[n // 2] <= got[1] and 1 - 2 * tail(k) >= Fraction(95, 100)
    assert median_interval([1.0] * 5) is None and median_interval([1.0] * 6) == (1.0, 1.0)


def test_fig10_says_where_the_interval_holds_one(capsys):
    from conecull.app.evaluation import _interval_lines

    rows = [{"scene": "a", "dcd_paired_interval": {"nc": [1.02, 1.09]}, "ccd_paired_interval": {"nc": [0.97, 1.04]}},
            {"scene": "b", "dcd_paired_interval": {"nc": [0.95, 1.0]}, "ccd_paired_interval": {"nc": None}}]
    _interval_lines(rows, "scene")
    out = capsys.readouterr().out
    assert "(DCD nc+front vs nc, 95% interval of the paired median (sign test): a 1.020-1.090, b 0.950-1.000; " \
           "holding 1.00x (this run cannot tell which is faster): b)" in out
    assert "(CCD nc+front vs nc, 95% interval of the paired median (sign test): a 0.970-1.040; holding 1.00x " \
           "(this run cannot tell which is faster): a; too few pairs for one: b)" in out
    _interval_lines([{"scene": "old"}], "scene")  # a paper.json from before: nothing to print
    assert capsys.readouterr().out == ""


def test_paired_ratios_pair_each_frame_and_pass():
    """The median of the per-(frame, pass) ratios over the frames given, not the ratio of the
    medians."""
    from conecull.app.evaluation import paired_ratios

    # ms[m][frame][pass]; frame 0 is not among those given. Frame 1: pass 2 slow for nc, pass 1
    # slow for nc+front; frame 2: both slow in pass 3.
    ms = {"nc": [[50.0] * 3, [1.0, 3.0, 1.2], [1.1, 1.1, 2.2]],
          "nc+front": [[1.0] * 3, [2.0, 1.0, 1.0], [1.0, 1.0, 2.0]]}
    got = paired_ratios(ms, ("nc", "nc+front"), range(1, 3))
    # ratios 0.5, 3.0, 1.2 and 1.1, 1.1, 1.1: median 1.1
    assert got == {"nc": pytest.approx(1.1), "nc+front": 1.0}
    # the ratio of the medians (per frame over passes, then over frames) is (1.2 + 1.1) / 2 / 1.0
    assert float(np.median([np.median(f) for f in ms["nc"][1:]])) / 1.0 == pytest.approx(1.15)
    assert paired_ratios(ms, ("nc", "nc+front"), range(3))["nc"] == pytest.approx(1.2)  # frame 0 counts if given
    assert paired_ratios(ms, ("nc",), range(1, 3)) == {}  # nothing to pair with


@pytest.mark.parametrize("ccd", [False, True])
def test_the_harness_refuses_to_time_methods_that_disagree(ccd):
    """Every pass compares each method's answer with the first's, pair for pair: a method that
    drops one pair (or contact) stops the benchmark."""
    from conecull.app.evaluation import _colliders, _timed_pass

    F, P = load("crumple")
    frames = P[-3:]
    cols = _colliders(F, frames, ("aabb", "nc"), 1)

    class DropsOnePair:  # "nc", but the last pair of every answer is lost
        def __init__(self, col):
            self.col = col

        def dcd(self, V):
            res = self.col.dcd(V)
            res.pairs = res.pairs[:-1]
            return res

        def ccd(self, V0, V1, arithmetic):
            res = self.col.ccd(V0, V1, arithmetic=arithmetic)
            res.vf, res.ee = res.vf[:-1], res.ee[:-1]
            return res

    ms = {m: [[] for _ in frames] for m in cols}
    stats = {m: [None] * len(frames) for m in cols}
    _timed_pass(cols, frames, ms, stats, ccd=ccd)  # the real methods agree
    n = sum(len(cols["aabb"].ccd(a, b).vf) + len(cols["aabb"].ccd(a, b).ee) if ccd else len(cols["aabb"].dcd(a).pairs)
            for a, b in zip(frames, frames[1:]))
    assert n > 0  # there is a pair to drop
    cols["nc"] = DropsOnePair(cols["nc"])
    with pytest.raises(RuntimeError, match="bench all: nc disagrees with aabb at .*please report this as a bug"):
        _timed_pass(cols, frames, ms, stats, ccd=ccd)


def test_steps_and_ipctk_side_by_side_on_a_small_step(capsys):
    """Fig. 10 on a step and the ipctk comparison, on a small generated fold step with contacts:
    our CCD finds the exact set (FN = FP = 0 against the brute-force-checked exact answer), and
    ipctk's conservative Tight-Inclusion misses none of it."""
    from shared_data import import_or_skip

    import_or_skip("ipctk", "an optional extra (pip install 'conecull[bench]'; also in [test])")
    from conecull.app.bench import _generated_ccd_steps

    name, F, V0, V1, _, _ = _generated_ccd_steps(1500)[1]
    results = {}
    steps = run_steps(1, 1, results, steps=[(name, F, V0, V1, None, None)])
    row = results["steps"][0]
    assert row["contacts"] > 0 and set(row["ccd_ms"]) == set(conecull.CCD_METHODS)
    rows = run_ipctk(steps, 1, results)
    r = rows[0]
    # the generated step has no ground truth: ours is the reference, its FN / FP are not counted
    assert r["ours_fn"] is None and r["ours_fp"] is None and r["ipctk_fn"] == 0
    out = capsys.readouterr().out
    assert "both on one thread" in out and "| = ref |" in out
    # Fig. 1 on the step: its efficiency is its contacts per VF/EE test, from the same query's stats
    s = row["ccd_stats"]["nc"][0]
    assert s["colliding_pairs"] == row["contacts"] and row["efficiency"]["ccd_nc"] == row["contacts"] / s["elementary_tests"]
    assert f"| {name} | " in out.split("## Culling efficiency (Fig. 1), real steps")[1].split("##")[0]
    # the cold queries (BVH built inside the timed query, as ipctk's) are timed and tabled
    assert all(r[f"ours_cold_{k}_ms"] > 0 for k in ("ccd", "dcd", "first"))
    cold = out.split("Ours with the BVH built inside the query")[1].split("Is this step")[0]
    assert f"| {name} | {r['ours_cold_ccd_ms']:.1f} | {r['ipctk_ms'] / r['ours_cold_ccd_ms']:.1f}x |" in cold
    assert r["candidates"] > 0 and r["ipctk_intersecting"] == r["ours_intersecting"]
    assert r["ours_first_hit_ms"] > 0 and r["first_hit_speedup"] == r["has_intersections_ms"] / r["ours_first_hit_ms"]
    # is_step_collision_free against ccd(stop_at_first): the step has contacts, both say so
    assert r["ipctk_step_free"] is False and r["ours_step_free"] is False and r["ours_step_free_full"] is False
    assert r["step_free_speedup"] == r["ipctk_step_free_ms"] / r["ours_first_hit_ccd_ms"]
    rows = run_ipctk(steps, 1, {}, max_candidates=0)  # a limit of 0: narrow phase not run, stated
    assert "ipctk_narrow_ms" not in rows[0] and "not run" in capsys.readouterr().out
    assert rows[0]["ipctk_not_run"] == "more than 0 candidates"
    assert rows[0]["ccd_speedup_lower"] == (rows[0]["ipctk_broad_ms"] + rows[0]["ipctk_stepsize_ms"]) / rows[0]["ours_ms"]


def _fold_step():
    from conecull.app.bench import _generated_ccd_steps

    name, F, V0, V1, _, _ = _generated_ccd_steps(1500)[1]
    return name, F, V0, V1


def test_ipctk_sample_is_uniform_seeded_and_says_why():
    from conecull.app.evaluation import IPCTK_BYTES_PER_CANDIDATE, ipctk_sample

    idx, why = ipctk_sample(10, 10, 2**30)
    assert idx.tolist() == list(range(10)) and why == ""
    idx, why = ipctk_sample(1000, 100, 2**30)
    assert len(idx) == 100 and len(set(idx.tolist())) == 100 and (np.diff(idx) > 0).all() and idx.max() < 1000
    assert why == "more than 100 candidates" and (ipctk_sample(1000, 100, 2**30)[0] == idx).all()  # seeded
    assert 100 < idx.max() and idx.min() < 900  # drawn from all of them, not the first 100
    idx, why = ipctk_sample(1000, 500, 40 * IPCTK_BYTES_PER_CANDIDATE)  # memory holds 40
    assert len(idx) == 40 and why.startswith("all 1000 would need about")
    assert len(ipctk_sample(1000, 0, 2**30)[0]) == 0


def test_ipctk_narrow_phase_on_a_sample_agrees_with_the_full_one():
    """The sampled narrow phase fetches candidates by index: its colliding pairs must be exactly
    the full narrow phase's pairs among the sampled candidates."""
    from shared_data import import_or_skip

    ipctk = import_or_skip("ipctk", "an optional extra (pip install 'conecull[bench]'; also in [test])")
    from conecull.app.evaluation import ipctk_narrow_phase

    name, F, V0, V1 = _fold_step()
    mesh = conecull.Mesh(F, n_vertices=len(V0))
    E = np.asfortranarray(mesh.edges.astype(np.int32))
    cm = ipctk.CollisionMesh(np.asfortranarray(V0), E, np.asfortranarray(np.asarray(F, np.int32)))
    cand = ipctk.Candidates()
    cand.build(cm, np.asfortranarray(V0), np.asfortranarray(V1), broad_phase=ipctk.LBVH())
    ti = ipctk.TightInclusionCCD()
    n = len(cand)
    _, vf_all, ee_all = ipctk_narrow_phase(cand, F, E, V0, V1, ti, np.arange(n))
    assert vf_all or ee_all  # the step has contacts
    assert {(c.vertex_id, c.face_id) for c in cand.fv_candidates} >= vf_all  # ids as ipctk lists them
    half = np.arange(0, n, 2)
    _, vf_half, ee_half = ipctk_narrow_phase(cand, F, E, V0, V1, ti, half)
    in_half_fv, in_half_ee = set(), set()
    for i in half.tolist():
        c = cand[int(i)]
        if hasattr(c, "face_id"):
            in_half_fv.add((c.vertex_id, c.face_id))
        else:
            in_half_ee.add(tuple(sorted((c.edge0_id, c.edge1_id))))
    assert vf_half == vf_all & in_half_fv and ee_half == ee_all & in_half_ee


def test_ipctk_narrow_phase_refuses_a_candidate_it_cannot_time():
    """Only face-vertex and edge-edge candidates are timed; any other kind (a 2D mesh's) is an
    error naming the candidate, not an edge-edge call on the wrong ids."""
    from shared_data import import_or_skip

    ipctk = import_or_skip("ipctk", "an optional extra (pip install 'conecull[bench]'; also in [test])")
    from conecull.app.evaluation import ipctk_narrow_phase

    name, F, V0, V1 = _fold_step()
    E = conecull.Mesh(F, n_vertices=len(V0)).edges
    with pytest.raises(TypeError, match="ipctk candidate 0: expected a face-vertex or edge-edge candidate, got "
                                        "VertexVertexCandidate"):
        ipctk_narrow_phase([ipctk.VertexVertexCandidate(0, 1)], F, E, V0, V1, ipctk.TightInclusionCCD(),
                           np.arange(1))


def test_ipctk_beyond_the_limit_runs_on_a_sample_and_bounds_the_speedup(capsys):
    from shared_data import import_or_skip

    import_or_skip("ipctk", "an optional extra (pip install 'conecull[bench]'; also in [test])")
    name, F, V0, V1 = _fold_step()
    full = run_ipctk([(name, F, V0, V1, None, None)], 1, {})[0]
    cap = full["candidates"] // 3
    r = run_ipctk([(name, F, V0, V1, None, None)], 1, {}, max_candidates=cap)[0]
    assert "ccd_speedup" not in r and "ipctk_fn" not in r and r["candidates"] == full["candidates"]
    assert r["ipctk_sampled"] == cap and r["ipctk_sample_why"] == f"more than {cap} candidates"
    assert r["ipctk_narrow_estimate_ms"] == r["ipctk_narrow_sample_ms"] * r["candidates"] / cap
    b, o = r["ipctk_broad_ms"], r["ours_ms"]
    assert r["ccd_speedup_lower"] == max(b + r["ipctk_narrow_sample_ms"], b + r["ipctk_stepsize_ms"]) / o
    assert r["ccd_speedup_estimate"] == (b + r["ipctk_narrow_estimate_ms"]) / o >= (b + r["ipctk_narrow_sample_ms"]) / o
    assert f"on a sample of {cap}" in capsys.readouterr().out


def test_ipctk_narrow_phase_is_sampled_beyond_the_machines_memory(monkeypatch, capsys):
    """Under the candidate limit, but on a machine too small for every candidate: a sample of
    what fits, and the row says why (a loop that swapped, or was killed, would be no benchmark)."""
    from shared_data import import_or_skip

    import_or_skip("ipctk", "an optional extra (pip install 'conecull[bench]'; also in [test])")
    from conecull.app import evaluation

    name, F, V0, V1 = _fold_step()
    monkeypatch.setattr(evaluation, "memory_bytes", lambda: 2**20)  # 1 MiB
    r = run_ipctk([(name, F, V0, V1, None, None)], 1, {})[0]
    fits = 2**20 // evaluation.IPCTK_BYTES_PER_CANDIDATE
    assert "ipctk_narrow_ms" not in r and r["candidates"] > fits and r["ipctk_sampled"] == fits
    assert r["ipctk_sample_why"].startswith("all ") and "more than this machine's 0.000977" in r["ipctk_sample_why"]
    assert f"on a sample of {fits}" in capsys.readouterr().out


def test_ipctk_candidates_option_reaches_the_ipctk_section(tmp_path, monkeypatch):
    """--ipctk-candidates sets the narrow phase's candidate limit; without it, the default."""
    from conecull.app import evaluation

    seen = []
    monkeypatch.setattr(evaluation, "run_ipctk", lambda *a, max_candidates, **k: seen.append(max_candidates))
    monkeypatch.setattr(evaluation, "shared_steps", lambda: [])
    skip = ["--skip", "scenes,steps,contour,ccd,scaling,threads", "--triangles", "200"]
    assert main(["bench", "all", *skip, "--ipctk-candidates", "7", "--out", str(tmp_path / "a")]) == 0
    assert main(["bench", "all", *skip, "--out", str(tmp_path / "b")]) == 0
    assert seen == [7, evaluation.IPCTK_MAX_CANDIDATES]


def _threads_run_json(speedups):
    """One threads run's JSON with the given 2-thread speed-ups per query (1-thread rows at 1.0)."""
    rows = []
    for (kind, query), s in speedups.items():
        rows.append({"kind": kind, "query": query, "threads": 1, "query_ms": 10.0, "speedup": 1.0})
        rows.append({"kind": kind, "query": query, "threads": 2, "query_ms": 10.0 / s, "speedup": s})
    return {"triangles": 64000, "compute_ceiling": (1.95, 1.97), "rows": rows}


def test_threads_section_takes_the_median_of_its_runs(capsys):
    """One slow run among three does not decide the threads row: per query the median of the runs,
    each run's speed-up kept (in run order) and printed."""
    from conecull.app.evaluation import median_threads, print_threads

    runs = [_threads_run_json({("dcd", "nc"): 1.80, ("ccd", "ccd exact"): 1.90}),
            _threads_run_json({("dcd", "nc"): 1.46, ("ccd", "ccd exact"): 1.95}),
            _threads_run_json({("dcd", "nc"): 1.76, ("ccd", "ccd exact"): 1.20})]
    got = median_threads(runs)
    two = {r["query"]: r for r in got["rows"] if r["threads"] == 2}
    assert two["nc"]["speedup"] == 1.76 and two["nc"]["speedups"] == [1.80, 1.46, 1.76]
    assert two["ccd exact"]["speedup"] == 1.90 and two["ccd exact"]["query_ms"] == pytest.approx(10.0 / 1.90)
    assert got["runs"] == runs and len(got["compute_ceiling"]) == 3
    print_threads(got)
    out = capsys.readouterr().out
    assert "| dcd nc | 1.80 1.46 1.76 | 1.76x | 10.00 | 5.68 |" in out
    assert "| ccd exact | 1.90 1.95 1.20 | 1.90x |" in out
    # the target is judged from the medians, and says so
    from conecull.app.targets import judge

    row = next(t for t in judge({"threads_bench": got}) if t["target"].startswith("2 threads"))
    assert row["verdict"] == "met" and "each the median of 3 runs" in row["measured"]
    assert row["values"]["speedups"] == {"nc": 1.76, "ccd exact": 1.90}


def test_threads_runs_must_have_the_same_queries():
    from conecull.app.evaluation import median_threads

    with pytest.raises(ValueError, match="not in every run"):
        median_threads([_threads_run_json({("dcd", "nc"): 1.8}), _threads_run_json({("dcd", "aabb"): 1.8})])


def test_bench_all_runs_the_threads_section_five_times(tmp_path):
    """The threads section alone at a toy size: five runs, each with its own JSON, and paper.json's
    rows are their medians, with the results checked identical across thread counts in each run."""
    from conecull.app.evaluation import THREAD_RUNS

    out = tmp_path / "t"
    rc = main(["bench", "all", "--skip", "scenes,steps,ipctk,contour,ccd,scaling", "--triangles", "2000",
               "--repeats", "1", "--out", str(out)])
    assert rc == 0 and THREAD_RUNS == 5
    runs = [json.loads((out / "threads_runs" / str(k) / "threads.json").read_text()) for k in range(1, 6)]
    res = json.loads((out / "paper.json").read_text())
    # each run says when it ran: here every other section was skipped, so the runs the scenes and
    # the ccd section would have been followed by are made up at the end
    assert [r.pop("when") for r in res["threads_bench"]["runs"]] == [
        "at its start", "straight after the first (every section between was skipped)"] + ["at its end"] * 3
    assert res["threads_bench"]["runs"] == runs
    for row in res["threads_bench"]["rows"]:
        per_run = [next(r for r in run["rows"] if (r["kind"], r["query"], r["threads"]) ==
                        (row["kind"], row["query"], row["threads"]))["speedup"] for run in runs]
        assert row["speedups"] == per_run and row["speedup"] == sorted(per_run)[2]
    report = (out / "report.md").read_text()
    assert "## Threads" in report and "evaluation (at its start; straight after the first" in report
    assert "after the steps and ipctk" not in report  # they did not run


@pytest.mark.parametrize("argv, msg", [
    (["--scenes", ","], "--scenes: expected comma-separated scene names, got ','"),
    (["--scenes", ""], "--scenes: expected comma-separated scene names, got ''"),
    (["--scenes", "fold,crumple,fold"], "--scenes: 'fold' named more than once"),
    (["--skip", ""], "--skip: expected comma-separated sections to leave out"),
    (["--skip", ","], "--skip: expected comma-separated sections to leave out"),
    (["--scenes", "fold", "--resolution", "-5"], "--resolution: expected an integer >= 3, got -5"),
    (["--resolution", "2"], "--resolution: expected an integer >= 3, got 2"),  # the default scenes
    (["--sizes", "1000", "--skip", "scaling"], "--sizes: the scaling section is skipped (--skip scaling)"),
    (["--ipctk-candidates", "5", "--skip", "ipctk"], "--ipctk-candidates: the ipctk section is skipped (--skip ipctk)"),
    (["--scenes", "fold", "--skip", "scenes"], "--scenes: the scenes section is skipped (--skip scenes)"),
    (["--resolution", "8", "--skip", "scenes"], "--resolution: the scenes section is skipped (--skip scenes)"),
    (["--triangles", "2000", "--skip", "steps,ipctk,contour,ccd,threads"],
     "--triangles: the sections that use it (steps, ipctk, contour, ccd, threads) are all skipped"),
    (["--tri=2000", "--skip", "steps,ipctk,contour,ccd,threads"], "--triangles: the sections that use it"),
    (["--frames", "3", "--skip", "scenes,contour"], "--frames: the sections that use it (scenes, contour) are all skipped"),
])
def test_bench_all_refuses_options_it_would_ignore(tmp_path, monkeypatch, argv, msg, capsys):
    """Refused before any section runs (each used to be read as "nothing", ignored, or to fail
    minutes in); the sections are stubbed, so any work done would show."""
    from conecull.app import evaluation

    monkeypatch.setattr(evaluation, "_threads_run", lambda *a, **k: pytest.fail("a section ran"))
    monkeypatch.setattr(evaluation, "run_scenes", lambda *a, **k: pytest.fail("a section ran"))
    assert main(["bench", "all", *argv, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert msg in err and "Traceback" not in err, err
    assert not (tmp_path / "o" / "report.md").exists()


def test_bench_all_options_still_allowed_with_their_section(tmp_path, monkeypatch):
    """The same options pass when a section that reads them runs (--triangles: any one of them)."""
    from conecull.app import evaluation

    ran = []
    monkeypatch.setattr(evaluation, "run_ipctk", lambda *a, max_candidates, **k: ran.append(max_candidates))
    monkeypatch.setattr(evaluation, "shared_steps", lambda: [])
    assert main(["bench", "all", "--skip", "scenes,steps,contour,ccd,scaling,threads", "--triangles", "200",
                 "--ipctk-candidates", "3", "--out", str(tmp_path / "a")]) == 0
    assert ran == [3]


def test_size_labels():
    from conecull.app.bench import _generated_ccd_steps, _size_label

    assert [_size_label(n) for n in (50, 512, 1500, 9999, 64000, 1000000)] == \
        ["50", "0.5K", "1.5K", "10.0K", "64K", "1000K"]
    assert _generated_ccd_steps(512)[1][0] == "generated fold (0.5K, jittered)"  # was "(0K, jittered)"


def test_plots_say_the_thread_count_and_the_real_frames(tmp_path, monkeypatch):
    """Titles name the run's thread count (they said "one thread" under --threads 2); a scene under
    1000 triangles is not "0K"; Fig. 11 and Fig. 1 plot against the scene's own frame numbers."""
    from shared_data import import_or_skip

    matplotlib = import_or_skip("matplotlib", "the benchmark's plots")
    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    from conecull.app.evaluation import _plots

    seen = []

    def savefig(fig, path, **kw):
        axes = fig.get_axes()
        seen.append((os.path.basename(path), [a.get_title() for a in axes],
                     [[t.get_text() for t in a.get_xticklabels()] for a in axes],
                     [[list(line.get_xdata()) for line in a.get_lines()] for a in axes]))

    monkeypatch.setattr(Figure, "savefig", savefig)
    st = [{"front_entries": 3, "elementary_tests": 5, "colliding_pairs": 1}] * 3
    scene = {"scene": "tiny", "triangles": 512, "frames": 10, "dcd_ms": {"nc": 1.0}, "ccd_ms": {"nc": 2.0},
             "all_frames": {"nc+front": st, "aabb+front": st, "aabb": st, "nc": st}}
    scaling = [{"triangles": 1000, "dcd_nc_ms": 1.0, "dcd_nc_front_ms": 1.0, "ccd_nc_ms": 1.0}]
    _plots({"threads": 2, "scenes": [scene], "scaling": scaling}, str(tmp_path))
    plots = {name: (titles, ticks, xs) for name, titles, ticks, xs in seen}
    assert plots["fig10_dcd.png"][0] == ["Fig. 10: DCD query time per method, 2 threads"]
    assert plots["fig10_dcd.png"][1][0] == ["tiny\n0.5K"]
    assert plots["scaling.png"][0] == ["Scaling: folded sheet, 2 threads"]
    assert plots["fig1_efficiency.png"][0] == ["tiny (0.5K)"]
    assert plots["fig11_front.png"][2][0][0] == [7, 8, 9]  # the last 3 of 10 frames, not 0, 1, 2
    assert plots["fig1_efficiency.png"][2][0][0] == [7, 8, 9]
    seen.clear()
    _plots({"threads": 1, "scenes": [scene]}, str(tmp_path))
    assert seen[0][1] == ["Fig. 10: DCD query time per method, one thread"]
    # Fig. 9: one bar per method and query kind, in the section's order (a missing pair left out)
    bars = []
    from matplotlib.axes import Axes

    draw_bar = Axes.bar

    def bar(self, x, h, w, label):
        bars.append((label, list(h)))
        return draw_bar(self, x, h, w, label=label)

    monkeypatch.setattr(Axes, "bar", bar)
    seen.clear()
    rows = [{"query": q, "method": m, "contour_ms": v} for q, m, v in
            (("DCD", "nc", 0.1), ("DCD", "sct", 0.3), ("DCD", "cbc", 9.0), ("CCD", "nc", 0.5), ("CCD", "cbc", 50.0))]
    _plots({"contour": {"triangles": 64082, "rows": rows}}, str(tmp_path))
    assert [name for name, *_ in seen] == ["fig9_contour.png"]
    assert seen[0][1] == ["Fig. 9: contour tests, folded sheet (64K), one thread"] and seen[0][2][0] == ["DCD", "CCD"]
    assert bars[0] == ("nc", [0.1, 0.5]) and bars[2] == ("cbc", [9.0, 50.0])
    assert bars[1][0] == "sct" and bars[1][1][0] == 0.3 and np.isnan(bars[1][1][1])


@pytest.mark.parametrize("skip, when", [
    ("scenes,steps,contour,ccd,scaling", ["at its start", "after the ipctk"] + ["at its end"] * 3),
    ("scenes,ipctk,contour,scaling", ["at its start", "after the steps", "after the steps and ccd"] +
     ["at its end, after the ccd"] * 2),
    ("steps,ipctk,contour,ccd,scaling", ["at its start", "after the scenes", "after the scenes"] + ["at its end"] * 2),
])
def test_threads_runs_say_when_they_ran(tmp_path, monkeypatch, skip, when):
    """print_threads said "at its start, after the steps and ipctk, at its end" whatever ran."""
    from conecull.app import bench, evaluation

    monkeypatch.setattr(evaluation, "run_ipctk", lambda *a, **k: None)
    monkeypatch.setattr(evaluation, "run_steps", lambda *a, **k: [])
    monkeypatch.setattr(evaluation, "run_scenes", lambda *a, **k: [])
    monkeypatch.setattr(bench, "run_ccd_bench", lambda *a, **k: _write(a[3], "ccd.json", {"rows": []}))
    monkeypatch.setattr(bench, "run_threads_bench",
                        lambda n, f, r, folder, threads: _write(folder, "threads.json",
                                                                _threads_run_json({("dcd", "nc"): 1.8})))
    out = tmp_path / "w"
    assert main(["bench", "all", "--skip", skip, "--triangles", "200", "--repeats", "1", "--out", str(out)]) == 0
    res = json.loads((out / "paper.json").read_text())
    assert [r["when"] for r in res["threads_bench"]["runs"]] == when
    assert "; ".join(when) in (out / "report.md").read_text()


def _write(folder, name, data):
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, name), "w") as fh:
        json.dump(data, fh)
    return 0


def _contour_json(sct, tests=33):
    rows = [{"query": q, "method": m, "contour_tests": tests, "contour_passed": tests, "contour_edges": 100,
             "colliding_pairs": 1, "contour_ms": 0.1 * v, "us_per_test": 1.0, "traversal_ms": 1.0, "query_ms": 2.0,
             "contour_ms_vs_nc": v, "per_frame": []}
            for q, m, v in (("DCD", "nc", 1.0), ("DCD", "sct", sct), ("DCD", "cbc", 50.0), ("CCD", "nc", 1.0),
                            ("CCD", "cbc", 60.0))]
    return {"scene": "folded sheet", "triangles": 200, "frames": 2, "repeats": 1, "rows": rows}


def test_contour_runs_spread_and_the_median_judged(tmp_path, monkeypatch):
    """The contour section runs three times over the evaluation, and the targets judge the median
    of its runs' ratios (one slow run does not decide the row); every run's ratio is printed."""
    from conecull.app import bench

    ratios = iter([2.87, 3.73, 3.56])
    monkeypatch.setattr(bench, "run_contour_bench",
                        lambda n, f, r, folder: _write(folder, "contour.json", _contour_json(next(ratios))))
    out = tmp_path / "c"
    assert main(["bench", "all", "--skip", "scenes,steps,ipctk,ccd,threads", "--sizes", "1000",
                 "--triangles", "200", "--repeats", "1", "--out", str(out)]) == 0
    res = json.loads((out / "paper.json").read_text())
    assert [r["when"] for r in res["contour"]["runs"]] == ["at its start", "straight after the first (every section "
                                                           "between was skipped)", "at its end, after the scaling"]
    sct = next(r for r in res["contour"]["rows"] if r["method"] == "sct")
    assert sct["contour_ms_vs_nc_runs"] == [2.87, 3.73, 3.56] and sct["contour_ms_vs_nc"] == 3.56
    target = next(t for t in res["targets"] if t["target"].startswith("contour test"))
    assert target["verdict"] == "met" and target["values"]["ratios"]["DCD sct"] == 3.56
    assert "| DCD | sct | 0.287 0.373 0.356 | 2.87 3.73 3.56 | 3.56x |" in (out / "report.md").read_text()
    assert json.loads((out / "contour.json").read_text())["rows"] == res["contour"]["rows"]


def test_contour_runs_whose_counters_differ_stop_the_run(tmp_path, monkeypatch):
    from conecull.app import bench

    tests = iter([33, 33, 34])
    monkeypatch.setattr(bench, "run_contour_bench",
                        lambda n, f, r, folder: _write(folder, "contour.json", _contour_json(3.5, next(tests))))
    with pytest.raises(RuntimeError, match=r"bench all: contour run 3 disagrees with contour run 1 on DCD nc's "
                                           r"contour_tests"):
        main(["bench", "all", "--skip", "scenes,steps,ipctk,ccd,scaling,threads", "--triangles", "200",
              "--repeats", "1", "--out", str(tmp_path / "d")])


def test_timed_passes_rotate_the_methods_turns():
    """Each pass starts its turns one method later, so over as many passes as methods every method
    runs in every place of the turn once; answers are still checked against whichever ran first."""
    from conecull.app.evaluation import time_sequence

    F, P = load("fold")
    P = P[:4]
    calls = []
    real = conecull.SelfCollider.dcd

    def dcd(self, V, *a, **k):
        calls.append(self.method)
        return real(self, V, *a, **k)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(conecull.SelfCollider, "dcd", dcd)
        methods = ("aabb", "nc", "nc+front")
        time_sequence(F, P, methods, 3)
    calls = calls[len(methods):]  # each collider's warm-up query on frame 0
    per_frame = [tuple(calls[i:i + 3]) for i in range(0, len(calls), 3)]
    assert per_frame[0] == methods and per_frame[len(P)] == ("nc", "nc+front", "aabb")
    assert per_frame[2 * len(P)] == ("nc+front", "aabb", "nc")
