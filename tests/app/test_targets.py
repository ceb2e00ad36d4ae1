"""The targets table of `bench all` (app/targets.py): each verdict follows its threshold, on
made-up results whose figures sit on either side of it."""

import pytest

from conecull.app.targets import judge


def _scene(name, dcd, ccd, front=0.3, ccd_front=0.3):
    """dcd / ccd: ms of (aabb, nc, nc+front)."""
    ms = lambda t: {"aabb": t[0], "nc": t[1], "nc+front": t[2]}  # noqa: E731
    return {"scene": name, "dcd_ms": ms(dcd), "ccd_ms": ms(ccd), "front_ratio": front, "ccd_front_ratio": ccd_front}


def _verdicts(results):
    return [r["verdict"] for r in judge(results)]


def test_nothing_run_is_nothing_measured():
    assert set(_verdicts({})) == {"not measured"}


def test_front_faster_needs_every_scene_strictly_faster():
    scenes = [_scene("a", (10, 5, 4), (10, 5, 4)), _scene("b", (10, 5, 4.9), (10, 5, 5.0))]
    rows = judge({"scenes": scenes})
    dcd, ccd = rows[0], rows[1]
    assert "DCD" in dcd["target"] and dcd["verdict"] == "met"
    assert dcd["values"]["vs_nc"] == {"a": 1.25, "b": 5 / 4.9}
    # a tie (1.00x) on one scene is not "faster"; the failing scene is named
    assert "CCD" in ccd["target"] and ccd["verdict"] == "not met" and "(not: b 1.00x)" in ccd["measured"]
    slower_than_aabb = judge({"scenes": [_scene("a", (4, 5, 4.5), (10, 5, 4))]})[0]
    assert slower_than_aabb["verdict"] == "not met" and "vs aabb 0.89x (not: a 0.89x)" in slower_than_aabb["measured"]


@pytest.mark.parametrize("ratio, verdict", [(0.40, "met"), (0.4001, "not met"), (0.05, "met")])
def test_front_share_threshold_is_inclusive(ratio, verdict):
    rows = judge({"scenes": [_scene("a", (3, 2, 1), (3, 2, 1), front=0.1), _scene("b", (3, 2, 1), (3, 2, 1), front=ratio)]})
    assert rows[2]["verdict"] == verdict
    assert rows[2]["measured"].startswith(f"{1 + (verdict == 'met')} of 2 scenes")
    assert rows[3]["verdict"] == "met"  # the CCD column, 0.3 on both


def test_front_share_ignores_scenes_without_a_front():
    rows = judge({"scenes": [_scene("a", (3, 2, 1), (3, 2, 1), front=float("nan"), ccd_front=float("nan"))]})
    assert rows[2]["verdict"] == rows[3]["verdict"] == "not measured"


def _contour(sct, cbc_dcd, cbc_ccd):
    return {"rows": [{"query": "DCD", "method": "nc", "contour_ms_vs_nc": 1.0},
                     {"query": "DCD", "method": "sct", "contour_ms_vs_nc": sct},
                     {"query": "DCD", "method": "cbc", "contour_ms_vs_nc": cbc_dcd},
                     {"query": "CCD", "method": "nc", "contour_ms_vs_nc": 1.0},
                     {"query": "CCD", "method": "cbc", "contour_ms_vs_nc": cbc_ccd}]}


@pytest.mark.parametrize("figures, verdict", [((3.0, 10.0, 10.0), "met"), ((2.99, 50, 50), "not met"),
                                              ((4, 9.9, 50), "not met"), ((4, 50, 9.9), "not met")])
def test_contour_ratios(figures, verdict):
    assert judge({"contour": _contour(*figures)})[4]["verdict"] == verdict


def _ipctk(step, ccd=None, bound=None, first=6.0, listing=4.0):
    r = {"step": step, "first_hit_speedup": first, "dcd_speedup": listing, "ours_ms": 1.0,
         "ipctk_broad_ms": 0.0, "ipctk_stepsize_ms": 0.0}
    if ccd is not None:
        r["ccd_speedup"] = ccd
    else:
        r["ipctk_broad_ms"], r["ipctk_stepsize_ms"] = bound / 2, bound / 2
    return r


def test_ipctk_ccd_full_figures_and_lower_bounds():
    v = lambda rows: judge({"ipctk": rows})[5]  # noqa: E731
    assert v([_ipctk("a", ccd=20.0), _ipctk("b", ccd=300.0)])["verdict"] == "met"
    assert v([_ipctk("a", ccd=19.9), _ipctk("b", ccd=300.0)])["verdict"] == "not met"
    # only a lower bound below the threshold: neither met nor refuted
    row = v([_ipctk("a", ccd=300.0), _ipctk("n-body", bound=2.2)])
    assert row["verdict"] == "not shown" and "n-body >= 2.2x (a lower bound" in row["measured"]
    assert v([_ipctk("a", ccd=300.0), _ipctk("n-body", bound=25.0)])["verdict"] == "met"
    assert v([_ipctk("a", ccd=3.0), _ipctk("n-body", bound=2.2)])["verdict"] == "not met"


def test_ipctk_ccd_on_a_sample_is_judged_on_its_lower_bound():
    """A narrow phase run on a sample gives a lower bound (its calls alone), judged like any
    bound; the estimate scaled to every candidate is printed, never judged."""
    v = lambda rows: judge({"ipctk": rows})[5]  # noqa: E731

    def sampled(lower, estimate):
        r = _ipctk("n-body", bound=2.0)
        r.update(candidates=31763290, ipctk_sampled=10000000, ipctk_sample_why="more than 10000000 candidates",
                 ccd_speedup_lower=lower, ccd_speedup_estimate=estimate)
        return r

    row = v([_ipctk("a", ccd=300.0), sampled(49.6, 157.0)])
    assert row["verdict"] == "met" and row["values"]["lower_bounds"] == {"n-body": 49.6}
    assert ("n-body >= 49.6x (a lower bound: narrow phase timed on a random sample of 10000000 of the 31763290 "
            "candidates; about 157x scaled to all)") in row["measured"]
    r = sampled(49.6, 157.0)
    r["ipctk_sample_why"] = "all 31763290 would need about 15.1 GiB, more than this machine's 8 GiB"
    assert "31763290 candidates (all 31763290 would need about 15.1 GiB, more than this machine's 8 GiB); about 157x" \
        in v([r])["measured"]
    assert v([_ipctk("a", ccd=300.0), sampled(19.9, 157.0)])["verdict"] == "not shown"  # the estimate is not judged


def test_ipctk_dcd_is_judged_on_the_first_hit_query():
    dcd = lambda rows: judge({"ipctk": rows})[6]  # noqa: E731
    row = dcd([_ipctk("a", ccd=30, first=5.0, listing=4.3), _ipctk("b", ccd=30, first=28.0, listing=15.8)])
    assert row["verdict"] == "met" and "listing every pair: 4.3–15.8x" in row["measured"]
    assert dcd([_ipctk("a", ccd=30, first=4.9, listing=40)])["verdict"] == "not met"


def _scaling(*pairs):
    return [{"triangles": n, "dcd_per_triangle_vs_64k": v} for n, v in pairs]


@pytest.mark.parametrize("rows, verdict", [
    (((16000, 3.0), (64000, 1.0), (256000, 0.95), (1000000, 0.7)), "met"),  # 16K is outside the target's range
    (((64000, 1.0), (1000000, 1.31)), "not met"),
    (((64000, 1.0), (1000000, 0.69)), "not met"),
    (((16000, 1.0), (32000, 1.0)), "not measured"),  # no 64K
    (((64000, 1.0),), "not measured"),
])
def test_scaling_within_thirty_percent_of_64k(rows, verdict):
    assert judge({"scaling": _scaling(*rows)})[7]["verdict"] == verdict


def test_threads_every_query_at_least_1_7x():
    rows = lambda s: {"rows": [{"query": "nc", "threads": 1, "speedup": 1.0},  # noqa: E731
                               {"query": "nc", "threads": 2, "speedup": s},
                               {"query": "ccd exact", "threads": 2, "speedup": 1.9}]}
    assert judge({"threads_bench": rows(1.7)})[8]["verdict"] == "met"
    row = judge({"threads_bench": rows(1.69)})[8]
    assert row["verdict"] == "not met" and "(not: nc 1.69x)" in row["measured"]


def test_accuracy_counts_the_real_steps_only():
    def rows(exact):
        return {"rows": [{"step": "rod-twist (79K)", "mode": "float", "ms": 100.0},
                         {"step": "rod-twist (79K)", "mode": "exact", "ms": exact},
                         {"step": "generated fold (64K, exact grid)", "mode": "float", "ms": 1.0},
                         {"step": "generated fold (64K, exact grid)", "mode": "exact", "ms": 5.0},
                         {"step": "ccd-queries", "mode": "float", "ms": 1.0, "queries": 3}]}
    assert judge({"ccd": rows(130.0)})[9]["verdict"] == "met"
    assert judge({"ccd": rows(131.0)})[9]["verdict"] == "not met"
