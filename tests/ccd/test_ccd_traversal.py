"""CCD queries of whole meshes: both methods return exactly the pairs of a brute force over
every VF and EE pair (same arithmetic; exact is the oracle), conservative contains exact, and
on the real steps of ../shared/data/scalable-ccd exact mode returns exactly the ground truth."""

import numpy as np
import pytest

import conecull
from conecull.datasets.generated import grid_sheet
from ccd_brute_force import brute_force_ccd, generated_steps
from shared_data import DATA, N_SCALABLE_STEPS, load_scalable_step, params, require, scalable_ccd_steps


STEPS = generated_steps()


@pytest.mark.parametrize("name,F,V0,V1", STEPS, ids=[s[0] for s in STEPS])
@pytest.mark.parametrize("arithmetic", ["exact", "conservative", "float"])
def test_methods_against_brute_force(name, F, V0, V1, arithmetic):
    """Exact: every method returns exactly the brute force's contacts. Conservative and float
    decide a pair only approximately, so which near-misses a method reports depends on which pairs
    its culling lets through (a culled region holds no contact, but may hold a conservative false
    positive): every method's answer is within the brute force's in the same mode, and
    conservative holds every exact contact."""
    vf_ref, ee_ref = brute_force_ccd(F, V0, V1, arithmetic)
    vf_ex, ee_ex = brute_force_ccd(F, V0, V1, "exact")
    if name in ("fold", "two-sheets"):
        assert vf_ex and ee_ex  # the step really has contacts
    mesh = conecull.Mesh(F, n_vertices=len(V0))
    for method in conecull.CCD_METHODS:
        col = conecull.SelfCollider(mesh, method=method)
        res = col.ccd(V0, V1, arithmetic=arithmetic)
        vf, ee = {tuple(r) for r in res.vf.tolist()}, {tuple(r) for r in res.ee.tolist()}
        if arithmetic == "exact":
            assert vf == vf_ref, f"{name} {method}: VF FN {sorted(vf_ref - vf)[:5]} FP {sorted(vf - vf_ref)[:5]}"
            assert ee == ee_ref, f"{name} {method}: EE FN {sorted(ee_ref - ee)[:5]} FP {sorted(ee - ee_ref)[:5]}"
        else:
            assert vf <= vf_ref and ee <= ee_ref, f"{name} {method}: a pair the same test rejects pair by pair"
        if arithmetic == "conservative":
            assert vf_ex <= vf and ee_ex <= ee, f"{name} {method}: conservative missed a contact"
        assert np.array_equal(res.vf, np.unique(res.vf, axis=0)) and np.array_equal(res.ee, np.unique(res.ee, axis=0))
        s = res.stats
        assert s["vf_tests"] + s["ee_tests"] + s["npf_culled"] == s["vf_candidates"] + s["ee_candidates"]


def test_bad_input():
    F, V = grid_sheet(4, 4)
    col = conecull.SelfCollider(conecull.Mesh(F))
    assert len(col.ccd(V, V).vf) == 0  # zero motion of a flat sheet: no contact
    with pytest.raises(ValueError, match=r"V1: has 3 rows but the mesh has 16 vertices"):
        col.ccd(V, V[:3], arithmetic="conservative")
    with pytest.raises(ValueError, match="arithmetic: expected one of"):
        col.ccd(V, V, arithmetic="fast")


REAL_ROOT = DATA / "scalable-ccd"
STEPS_REAL = scalable_ccd_steps()


def test_every_real_step_is_tested():
    require(REAL_ROOT)
    assert len(STEPS_REAL) == N_SCALABLE_STEPS, f"{REAL_ROOT}: steps {STEPS_REAL}, expected {N_SCALABLE_STEPS}"


@pytest.mark.parametrize("scene,step", params(STEPS_REAL, [f"{a}-{b}" for a, b in STEPS_REAL], REAL_ROOT, arity=2))
def test_real_steps_exact_equals_ground_truth(scene, step):
    require(REAL_ROOT)
    F, V0, V1, vf_true, ee_true = load_scalable_step(scene, step)
    mesh = conecull.Mesh(F, n_vertices=len(V0))
    for method in conecull.CCD_METHODS:
        res = conecull.SelfCollider(mesh, method=method).ccd(V0, V1, arithmetic="exact")
        vf = {tuple(r) for r in res.vf.tolist()}
        ee = {tuple(r) for r in res.ee.tolist()}
        assert vf == vf_true, f"{scene} {method}: VF FN {sorted(vf_true - vf)[:5]} FP {sorted(vf - vf_true)[:5]}"
        assert ee == ee_true, f"{scene} {method}: EE FN {sorted(ee_true - ee)[:5]} FP {sorted(ee - ee_true)[:5]}"
    res = conecull.SelfCollider(mesh, method="nc").ccd(V0, V1, arithmetic="conservative")
    assert vf_true <= {tuple(r) for r in res.vf.tolist()} and ee_true <= {tuple(r) for r in res.ee.tolist()}
