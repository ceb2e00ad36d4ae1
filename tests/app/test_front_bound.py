"""app/front_bound.py: the open-hemisphere test on constructed normals (including sets whose mean
normal is no witness, so the linear program decides), and the front bound on scenes: never above
ours (ours culls only nodes whose normals lie in an open hemisphere), nothing kept on a flat
sheet, something kept on a sheet folded onto itself."""

import numpy as np
import pytest

from conecull.app.front_bound import front_bound, in_open_hemisphere
from conecull.datasets import generated, load
from shared_data import import_or_skip


@pytest.fixture(autouse=True)
def scipy():
    """Skipped without scipy, except in CI, where the test extra must have brought it."""
    import_or_skip("scipy.optimize", "the front bound's linear programs (pip install 'conecull[bench]'; also in [test])")


def unit(*rows):
    a = np.array(rows, dtype=float)
    return a / np.linalg.norm(a, axis=1, keepdims=True)


@pytest.mark.parametrize("normals,want", [
    (unit([0, 0, 1], [1, 0, 0]), True),
    (unit([0, 0, 1], [0, 0, -1]), False),                        # opposite
    (unit([1, 0, 0], [0, 1, 0], [-1, 0, 0]), False),             # x and -x: no v has both > 0
    (unit([1, 0, 0], [0, 1, 0], [0, 0, 1], [-1, -1, -1]), False),  # the origin inside their hull
    (unit(*([[1, 0, 0]] * 10), [-0.9, 0.1, 0]), True),           # the mean fails; v = (1, 10, 0) works
    (unit(*([[1, 0, 0]] * 10), [-1, 1e-3, 0], [-1, -1e-3, 0]), False),
])
def test_open_hemisphere_on_constructed_sets(normals, want):
    assert in_open_hemisphere(normals) is want


def test_open_hemisphere_agrees_with_sampled_witnesses():
    """Random small sets: where one of 20,000 directions is a witness, the answer is True; where
    the answer is False, none is."""
    rng = np.random.default_rng(7)
    k = np.arange(20000) + 0.5
    z = 1 - 2 * k / len(k)
    phi = np.pi * (1 + 5**0.5) * k
    dirs = np.c_[np.sqrt(1 - z * z) * np.cos(phi), np.sqrt(1 - z * z) * np.sin(phi), z]
    seen = {True: 0, False: 0}
    for _ in range(150):
        n = rng.normal(size=(rng.integers(2, 7), 3))
        n /= np.linalg.norm(n, axis=1, keepdims=True)
        sampled = bool(((n @ dirs.T) > 0).all(axis=0).any())
        got = in_open_hemisphere(n)
        if sampled:
            assert got, n
        seen[got] += 1
    assert seen[True] > 20 and seen[False] > 20  # both answers exercised


def test_the_linear_program_agrees_with_certified_cones():
    """Every node whose cone the core bounded (a certificate that its normals lie in an open
    hemisphere) passes the linear program alone, without the mean-normal shortcut; and on the
    crumpled sphere the program finds nodes beyond those, so the bound is below ours."""
    import conecull

    F, P = load("crumple")
    V = P[-1]
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=len(V)), method="nc", threads=1)
    col.dcd(P[0])
    col.dcd(V)
    b, cones = col.bvh_arrays(), col.cone_arrays()
    T = V[F]
    n = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    bounded = np.flatnonzero((cones["cos_bound"] > 0) & (b["right"] >= 0))
    assert len(bounded) > 20
    for x in bounded:
        assert in_open_hemisphere(n[b["order"][b["begin"][x]:b["end"][x]]], witness=False), x
    crumpled = front_bound(F, P[0], V)
    assert 0 < crumpled["bound"] < crumpled["ours"] <= crumpled["aabb_front"]


def test_the_front_is_counted_whole_after_a_jump():
    """A jump from the build pose to the last one makes sub-segments churn and rest (keeping no
    entries); the bound queries the pose again until none rests, so its `aabb+front` count is
    that of a front that keeps every node's entries."""
    import conecull

    F, P = load("crumple")
    got = front_bound(F, P[0], P[-1])
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=P.shape[1]), method="aabb+front", threads=1)
    col.dcd(P[0])
    for _ in range(8):
        col.dcd(P[-1])
    fr = col.front_arrays("dcd")
    assert not fr["resting"].any() and got["aabb_front"] == len(fr["entries"])


def test_front_bound_on_a_flat_and_a_folded_sheet():
    F, V = generated.grid_sheet(24, 24)
    flat = front_bound(F, V, V)
    assert flat["bound"] == 0 and flat["ours"] == 0 and flat["aabb_front"] > 0  # the root is culled
    F, P = load("fold")
    folded = front_bound(F, P[0], P[-1])  # folded onto itself: the root's normals span both sides
    assert 0 < folded["bound"] <= folded["ours"] <= folded["aabb_front"]
    assert folded["bound_nodes"] <= folded["ours_nodes"]
    assert folded["bound_ratio"] == pytest.approx(folded["bound"] / folded["aabb_front"])
