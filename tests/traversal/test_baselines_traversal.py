"""The baselines in the traversal (Sec. 6.1): "sct" and "cbc" really cull, report their contour
tests (counts, reasons, edges, seconds) like nc, and give exactly nc's results (the oracle
comparisons over all methods are in test_dcd_oracle.py and tests/ccd)."""

import numpy as np
import pytest

import conecull
from conecull.datasets.generated import bending_sheet, fold, grid_sheet
from conecull.trace import REASONS, explain

CONTOUR_METHODS = ("nc", "nc+front", "sct", "cbc")


def test_baselines_cull_a_smooth_sheet_and_report_contour_time():
    F, frames = bending_sheet(n_triangles=3000, n_frames=2, amplitude=0.1)
    mesh = conecull.Mesh(F)
    for V in frames:
        aabb = conecull.SelfCollider(mesh, method="aabb").dcd(V)
        assert aabb.stats["seconds_contour"] == 0 and aabb.stats["contour_tests"] == 0
        for m in CONTOUR_METHODS:
            res = conecull.SelfCollider(mesh, method=m).dcd(V)
            s = res.stats
            assert len(res.pairs) == 0
            assert s["contour_passed"] >= 1 and s["elementary_tests"] < aabb.stats["elementary_tests"], m
            assert s["contour_tests"] == s["contour_passed"] + s["contour_failed"]
            assert sum(s["contour_failed_by_reason"].values()) == s["contour_failed"]
            assert s["seconds_contour"] > 0, m  # the timer is wired (its size is the benchmark's business)
            assert s["contour_edges"] > 0


def test_cbc_visits_quadratically_many_edges():
    F, V = grid_sheet(12, 12)
    Vb = fold(V, 0.6 * np.pi, radius=0.05)
    mesh = conecull.Mesh(F)
    nc = conecull.SelfCollider(mesh, method="nc").dcd(Vb).stats
    cbc = conecull.SelfCollider(mesh, method="cbc").dcd(Vb).stats
    # the root's contour alone: ~44 edges, ~44^2 edge visits for cbc vs ~44 for nc
    assert cbc["contour_edges"] > 5 * nc["contour_edges"]


def test_baseline_reasons_are_explained_and_traced():
    assert REASONS[6][0] == "no_kernel_on_search_line" and REASONS[7][0] == "edges_may_overlap"
    assert "edge 3" in explain(7, edge=3)
    F, V = grid_sheet(12, 12)
    Vb = fold(V, 1.2 * np.pi, radius=0.02)  # folded through itself: some contours overlap
    mesh = conecull.Mesh(F)
    for m in ("sct", "cbc"):
        res = conecull.SelfCollider(mesh, method=m).dcd(Vb, trace=True)
        c = res.trace.counts()
        for k in ("contour_tests", "contour_passed", "contour_failed"):
            assert c[k] == res.stats[k], (m, k)
        codes = set(np.unique(res.trace.contour["reason"]).tolist())
        assert codes <= set(REASONS), codes
    res = conecull.SelfCollider(mesh, method="cbc").dcd(Vb)
    assert res.stats["contour_failed_by_reason"]["edges_may_overlap"] == res.stats["contour_failed"]  # its only reason


def test_cbc_ccd_culls_and_sct_ccd_is_refused():
    """cbc culls on a step that folds the sheet through itself, and finds exactly the contacts of
    the brute force over every VF and EE pair."""
    from ccd_brute_force import brute_force_ccd

    F, V = grid_sheet(10, 10)
    V0, V1 = fold(V, 0.9 * np.pi, radius=0.05), fold(V, 1.15 * np.pi, radius=0.05)
    mesh = conecull.Mesh(F)
    cbc = conecull.SelfCollider(mesh, method="cbc").ccd(V0, V1)
    vf, ee = brute_force_ccd(F, V0, V1, "exact")
    assert vf and ee
    assert {tuple(r) for r in cbc.vf.tolist()} == vf and {tuple(r) for r in cbc.ee.tolist()} == ee
    assert cbc.stats["contour_passed"] >= 1 and cbc.stats["seconds_contour"] > 0
    with pytest.raises(ValueError, match="method: 'sct' is a discrete"):
        conecull.SelfCollider(mesh, method="sct").ccd(V0, V1)
