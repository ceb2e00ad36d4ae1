"""threads=: CCD in every arithmetic mode gives identical results - the same vf and ee arrays in
the same order, the same time-of-impact bounds, the same counters (exact paths included) - for
1, 2, 3 and 7 threads, for every method, over generated sequences; and equals the brute force."""

import numpy as np
import pytest

import conecull
from conecull.datasets.generated import fold, grid_sheet
from ccd_brute_force import brute_force_ccd
from thread_cases import THREADS, counters, sequences


def ccd_runs(F, frames, method, arithmetic, threads, toi):
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=frames.shape[1]), method=method)
    col.dcd(frames[0], threads=1)
    # Per-query override of the collider's default (all cores).
    return [col.ccd(V0, V1, arithmetic=arithmetic, toi=toi, threads=threads) for V0, V1 in zip(frames[:-1], frames[1:])]


@pytest.mark.parametrize("scene", ["folding_sheet", "crumpling_sphere"])
@pytest.mark.parametrize("arithmetic", ["float", "conservative", "exact"])
@pytest.mark.parametrize("method", conecull.CCD_METHODS)
def test_ccd_identical_for_any_thread_count(scene, arithmetic, method):
    F, frames = sequences()[scene]
    # Steps where contacts happen; time-of-impact bounds on the sheet (slow on the crumpled sphere).
    toi = scene == "folding_sheet"
    frames = frames[-3:] if toi else frames[-2:]
    ref = ccd_runs(F, frames, method, arithmetic, 1, toi)
    assert sum(len(r.vf) + len(r.ee) for r in ref) > 0
    for threads in THREADS[1:]:
        for k, (a, b) in enumerate(zip(ref, ccd_runs(F, frames, method, arithmetic, threads, toi))):
            where = f"{scene} {method} {arithmetic} threads={threads} step {k}"
            assert np.array_equal(a.vf, b.vf), f"{where}: vf differ"
            assert np.array_equal(a.ee, b.ee), f"{where}: ee differ"
            assert (a.toi is None) == (not toi) and (b.toi is None or np.array_equal(a.toi, b.toi)), f"{where}: toi"
            assert counters(a.stats) == counters(b.stats), f"{where}: stats differ"


def test_ccd_equals_brute_force_on_many_threads():
    F, V = grid_sheet(9, 9)
    V = V.copy()
    V[:, 2] = 0.01 * np.sin(9.0 * V[:, 0]) * np.sin(7.0 * V[:, 1])
    V0, V1 = fold(V, 0.9 * np.pi, radius=0.05), fold(V, 1.15 * np.pi, radius=0.05)
    vf_ref, ee_ref = brute_force_ccd(F, V0, V1, "exact")
    assert vf_ref and ee_ref
    mesh = conecull.Mesh(F, n_vertices=len(V0))
    for method in conecull.CCD_METHODS:
        res = conecull.SelfCollider(mesh, method=method, leaf_size=1).ccd(V0, V1, threads=3)
        assert {tuple(r) for r in res.vf.tolist()} == vf_ref, method
        assert {tuple(r) for r in res.ee.tolist()} == ee_ref, method
