"""app/front_bound.py: the front bound on scenes: never above ours (ours culls only nodes whose
normals lie in an open hemisphere), below it where normals fit in a hemisphere that the merged
cones miss, nothing kept on a flat sheet, something kept on a sheet folded onto itself. (The
hemisphere test itself, normal_spread, is tested in tests/cone/test_normal_spread.py.)"""

import pytest

from conecull.app.front_bound import front_bound
from conecull.datasets import generated, load


def test_the_bound_culls_beyond_our_cones_on_the_crumpled_sphere():
    """On the crumpled sphere some nodes' normals fit in an open hemisphere although their
    merged cone is full, so the ideal test culls more than ours: the bound is below ours."""
    F, P = load("crumple")
    crumpled = front_bound(F, P[0], P[-1])
    assert 0 < crumpled["bound"] < crumpled["ours"] <= crumpled["aabb_front"]
    assert crumpled["bound_nodes"] < crumpled["ours_nodes"]


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
