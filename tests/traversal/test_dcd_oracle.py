"""Both methods return exactly the brute-force oracle's colliding pairs (sets, not counts) on
every generated case, for leaf sizes 1 and 4; and "nc" really culls."""

import numpy as np
import pytest

import conecull
import meshcases
from conecull.datasets.generated import bending_sheet

CASES = meshcases.all_cases()


def test_enough_cases():
    assert len(CASES) >= 40
    colliding = sum(1 for name, _, _ in CASES if meshcases.oracle_pairs(name))
    assert colliding >= 25 and len(CASES) - colliding >= 5


@pytest.mark.parametrize("name", [c[0] for c in CASES])
def test_methods_equal_oracle(name):
    _, F, V = meshcases.case(name)
    expect = meshcases.oracle_pairs(name)
    mesh = conecull.Mesh(F, n_vertices=len(V))
    for method in conecull.METHODS:
        for leaf_size in (1, 4):
            res = conecull.SelfCollider(mesh, method=method, leaf_size=leaf_size).dcd(V)
            got = {tuple(p) for p in res.pairs.tolist()}
            missing, extra = expect - got, got - expect
            assert not missing and not extra, (
                f"{name} {method} leaf={leaf_size}: missing {sorted(missing)[:5]} extra {sorted(extra)[:5]}")
            assert res.stats["colliding_pairs"] == len(expect)


def test_nc_really_culls_a_smooth_sheet():
    """On a smooth, gently bent sheet without self-intersections, >= 90% of the internal nodes
    pass the cone and contour tests (culled there or below an ancestor that was culled), and
    nc does fewer elementary tests than aabb."""
    F, frames = bending_sheet(n_triangles=5000, n_frames=3, amplitude=0.1)
    mesh = conecull.Mesh(F)
    for V in frames:
        nc = conecull.SelfCollider(mesh, method="nc")
        res = nc.dcd(V)
        aabb = conecull.SelfCollider(mesh, method="aabb").dcd(V)
        assert len(res.pairs) == 0 and len(aabb.pairs) == 0
        bvh, cones, ct = nc.bvh_arrays(), nc.cone_arrays(), nc.contour_arrays()
        from conecull._core import contour as CT

        internal = np.flatnonzero(bvh["right"] >= 0)
        passing = 0
        for i in internal:
            if cones["cos_bound"][i] <= 0 or ct["status"][i] != 0:
                continue
            loop = ct["vertices"][ct["offsets"][i] : ct["offsets"][i + 1]]
            passing += CT.contour_test(loop.astype(np.int32), V, cones["axis"][i])["passed"]
        assert passing >= 0.9 * len(internal), f"only {passing}/{len(internal)} internal nodes pass"
        assert res.stats["elementary_tests"] < aabb.stats["elementary_tests"]
        assert res.stats["contour_passed"] >= 1


def test_nc_culls_a_contour_that_comes_within_1e10_of_itself():
    """Certified is not timid: a flat spiral strip whose arms pass 1e-10 apart has a simple
    boundary, and the root's contour test proves it, so
    the whole mesh is culled with one contour test and no elementary test; with the arms
    touching, the same test fails and the collisions are found (test_methods_equal_oracle)."""
    _, F, V = meshcases.case("spiral_arms_1e-10_apart")
    res = conecull.SelfCollider(conecull.Mesh(F, n_vertices=len(V)), method="nc").dcd(V)
    assert len(res.pairs) == 0 and not meshcases.oracle_pairs("spiral_arms_1e-10_apart")
    assert res.stats["contour_tests"] == 1 and res.stats["contour_passed"] == 1
    assert res.stats["elementary_tests"] == 0
    _, F, V = meshcases.case("spiral_arms_touching")
    res = conecull.SelfCollider(conecull.Mesh(F, n_vertices=len(V)), method="nc").dcd(V)
    assert res.stats["contour_failed"] >= 1 and len(res.pairs) == len(meshcases.oracle_pairs("spiral_arms_touching")) > 0
