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
    assert "CCD" in ccd["target"] and ccd["verdict"] == "not met" and "(not: b 1.000x)" in ccd["measured"]
    assert dcd["measured"].startswith("on 2 scenes: a, b; vs nc ")  # what "every scene" covered
    slower_than_aabb = judge({"scenes": [_scene("a", (4, 5, 4.5), (10, 5, 4))]})[0]
    assert slower_than_aabb["verdict"] == "not met" and "vs aabb 0.889x (not: a 0.889x)" in slower_than_aabb["measured"]
    assert slower_than_aabb["measured"].startswith("on 1 scene: a;")


def test_front_faster_judges_the_paired_ratios_when_a_row_has_them():
    """A `bench all` row carries nc+front's paired speed-ups (evaluation.paired_ratios); they, not
    the ratio of the ms medians, are judged. Rows without them (an older paper.json) fall back."""
    paired = _scene("a", (10, 5, 4), (10, 5, 4)) | {"dcd_paired": {"aabb": 2.0, "nc": 0.99, "nc+front": 1.0},
                                                    "ccd_paired": {"aabb": 2.0, "nc": 1.01, "nc+front": 1.0}}
    dcd, ccd = judge({"scenes": [paired]})[:2]
    assert dcd["verdict"] == "not met" and dcd["values"]["vs_nc"] == {"a": 0.99} and "vs nc (paired) " in dcd["measured"]
    assert ccd["verdict"] == "met" and ccd["values"]["vs_aabb"] == {"a": 2.0}
    mixed = judge({"scenes": [paired, _scene("b", (10, 5, 4), (10, 5, 4))]})[0]
    assert mixed["values"]["vs_nc"] == {"a": 0.99, "b": 1.25} and "(paired)" not in mixed["measured"]


def test_front_faster_says_which_scenes_the_interval_can_order():
    """With the sign test's intervals (evaluation.median_interval), the row says per scene whether
    nc+front is faster than nc beyond this run's noise (interval above 1.00x), slower (below) or a
    tie (it holds 1.00x); the verdict is still the paired median's."""
    def row(name, nc, interval):
        return _scene(name, (10, 5, 4), (10, 5, 4)) | {"dcd_paired": {"aabb": 2.0, "nc": nc, "nc+front": 1.0},
                                                       "dcd_paired_interval": {"aabb": [1.9, 2.1], "nc": interval}}
    scenes = [row("a", 1.05, [1.02, 1.09]), row("b", 0.98, [0.95, 1.07]), row("c", 0.90, [0.85, 0.97]),
              row("d", 1.01, None)]  # d: too few pairs for an interval
    dcd = judge({"scenes": scenes})[0]
    assert dcd["verdict"] == "not met"
    assert dcd["values"]["vs_nc_by_interval"] == {"faster": ["a"], "tie": ["b"], "slower": ["c"]}
    assert "(by the 95% interval of the paired median: faster on a; tie on b; slower on c)" in dcd["measured"]
    ties = judge({"scenes": [row("a", 1.01, [0.99, 1.04]), row("b", 1.02, [1.0, 1.05])]})[0]
    assert ties["verdict"] == "met" and ties["values"]["vs_nc_by_interval"]["tie"] == ["a", "b"]
    assert "faster on none; tie on a, b; slower on none" in ties["measured"]
    old = judge({"scenes": [_scene("a", (10, 5, 4), (10, 5, 4))]})[0]  # a paper.json from before intervals
    assert "95% interval" not in old["measured"] and old["values"]["vs_nc_by_interval"] == {}


@pytest.mark.parametrize("ratio, verdict", [(0.40, "met"), (0.4001, "not met"), (0.05, "met")])
def test_front_share_threshold_is_inclusive(ratio, verdict):
    rows = judge({"scenes": [_scene("a", (3, 2, 1), (3, 2, 1), front=0.1), _scene("b", (3, 2, 1), (3, 2, 1), front=ratio)]})
    assert rows[2]["verdict"] == verdict
    assert rows[2]["measured"].startswith(f"{1 + (verdict == 'met')} of 2 scenes")
    assert rows[3]["verdict"] == "met"  # the CCD column, 0.3 on both


def test_front_share_ignores_scenes_without_a_front():
    rows = judge({"scenes": [_scene("a", (3, 2, 1), (3, 2, 1), front=float("nan"), ccd_front=float("nan"))]})
    assert rows[2]["verdict"] == rows[3]["verdict"] == "not measured"
    assert "not measured on a (aabb+front kept no front)" in rows[2]["measured"]


def test_front_share_names_a_scene_it_could_not_judge():
    """A scene without a front (NaN ratio) is said to be unmeasured, not silently dropped."""
    rows = judge({"scenes": [_scene("a", (3, 2, 1), (3, 2, 1), front=0.2), _scene("b", (3, 2, 1), (3, 2, 1),
                                                                                   front=float("nan"))]})
    assert rows[2]["verdict"] == "met" and rows[2]["measured"] == \
        "1 of 1 scenes: a 20%; not measured on b (aabb+front kept no front)"
    assert rows[2]["values"]["not_measured"] == ["b"]
    assert rows[3]["measured"] == "2 of 2 scenes: a 30%, b 30%"


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
    assert row["verdict"] == "not shown" and "n-body >= 2.200x (a lower bound" in row["measured"]
    assert row["measured"].startswith("300x on 1 step: a;")
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
    (((64000, 1.0), (900000, 1.2)), "met"),  # near enough to 1M
    (((16000, 1.0), (64000, 1.0), (256000, 0.95)), "partial"),  # within 30%, but only up to 256K
    (((64000, 1.0), (256000, 1.5)), "not met"),  # out of range already at 256K
])
def test_scaling_within_thirty_percent_of_64k(rows, verdict):
    assert judge({"scaling": _scaling(*rows)})[7]["verdict"] == verdict


def test_scaling_says_which_sizes_it_judged():
    row = judge({"scaling": _scaling((16000, 1.0), (64000, 1.0), (256000, 0.95))})[7]
    assert row["measured"] == "relative to 64K: 64K 1.00x, 256K 0.95x; measured up to 256K only, none near 1M"
    row = judge({"scaling": _scaling((1000, 1.0), (2000, 1.1))})[7]
    assert row["verdict"] == "not measured"
    assert row["measured"] == "sizes measured: 1.0K, 2.0K; the target needs 64K and a larger one"


def test_threads_every_query_at_least_1_7x():
    rows = lambda s: {"rows": [{"query": "nc", "threads": 1, "speedup": 1.0},  # noqa: E731
                               {"query": "nc", "threads": 2, "speedup": s},
                               {"query": "ccd exact", "threads": 2, "speedup": 1.9}]}
    assert judge({"threads_bench": rows(1.7)})[8]["verdict"] == "met"
    row = judge({"threads_bench": rows(1.69)})[8]
    assert row["verdict"] == "not met" and "(not: nc 1.690x)" in row["measured"]


def test_accuracy_counts_the_real_steps_only():
    def rows(exact):
        return {"rows": [{"step": "rod-twist (79K)", "mode": "float", "ms": 100.0},
                         {"step": "rod-twist (79K)", "mode": "exact", "ms": exact},
                         {"step": "generated fold (64K, exact grid)", "mode": "float", "ms": 1.0},
                         {"step": "generated fold (64K, exact grid)", "mode": "exact", "ms": 5.0},
                         {"step": "ccd-queries", "mode": "float", "ms": 1.0, "queries": 3}]}
    assert judge({"ccd": rows(130.0)})[9]["verdict"] == "met"
    assert judge({"ccd": rows(131.0)})[9]["verdict"] == "not met"


@pytest.mark.parametrize("results, text", [
    ({"threads_bench": {"rows": [{"query": "nc", "threads": 2, "speedup": 1.699}]}}, "1.699x over 1 queries (not: nc 1.699x)"),
    ({"threads_bench": {"rows": [{"query": "nc", "threads": 2, "speedup": 1.6999}]}}, "(not: nc 1.6999x)"),
    ({"threads_bench": {"rows": [{"query": "nc", "threads": 2, "speedup": 1.705}]}}, "1.705x over 1 queries"),  # near: met
    ({"contour": _contour(2.999, 50, 50)}, "DCD sct 2.999x, DCD cbc 50.00x"),
    ({"scenes": [_scene("a", (3, 2, 1), (3, 2, 1), front=0.4001)]}, "0 of 1 scenes: a 40.01%"),
    ({"scenes": [_scene("a", (3, 2, 1), (3, 2, 1), front=0.404)]}, "0 of 1 scenes: a 40.4%"),
    ({"scaling": [{"triangles": 64000, "dcd_per_triangle_vs_64k": 1.0},
                  {"triangles": 1000000, "dcd_per_triangle_vs_64k": 1.3004}]}, "1000K 1.3004x"),
    ({"ccd": {"rows": [{"step": "s", "mode": "float", "ms": 1.0}, {"step": "s", "mode": "exact", "ms": 1.3049}]}},
     "1.305x on 1 step: s (not: s 1.305x)"),
])
def test_failing_values_never_round_onto_the_threshold(results, text):
    """1.699 next to ">= 1.7x" printed as "1.70x" read as a pass: a failing figure, or one within
    0.01 of its threshold, has 3 decimals (more if it would still print as the threshold)."""
    measured = " | ".join(r["measured"] for r in judge(results))
    assert text in measured
