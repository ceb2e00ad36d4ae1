"""BVH structure: ranges, a permutation of the faces, boxes that contain their triangles, and
bounded depth on adversarial inputs (depth is what recursion and traversal cost depend on)."""

import numpy as np
import pytest

import conecull
from conecull.datasets.generated import sheet_for_triangles, uv_sphere


def needle_strip(n):
    """A strip of quads with a long needle triangle on every top and bottom edge."""
    V = [[i, 0, 0] for i in range(n + 1)] + [[i, 1, 0] for i in range(n + 1)]
    F = []
    t = lambda i: n + 1 + i  # noqa: E731
    for i in range(n):
        F += [[i, i + 1, t(i + 1)], [i, t(i + 1), t(i)]]
    for i in range(n):
        V.append([i + 0.5, -50.0, 0.3 * (i % 2)])
        F.append([i + 1, i, len(V) - 1])
        V.append([i + 0.5, 51.0, 0.3 * (i % 2)])
        F.append([t(i), t(i + 1), len(V) - 1])
    return np.array(F), np.array(V, float)


def fin_book(k):
    """k faces on one edge (a non-manifold 'book')."""
    ang = np.linspace(0, np.pi, k)
    V = np.vstack([[[0, 0, 0], [0, 0, 1]], np.c_[np.cos(ang), np.sin(ang), np.full(k, 0.5)]])
    F = np.array([[0, 1, 2 + i] for i in range(k)])
    return F, V


CASES = {
    "sheet": sheet_for_triangles(20000),
    "sphere": uv_sphere(60, 120),
    "needle_strip": needle_strip(3000),
    "fin_book": fin_book(3000),
}


@pytest.mark.parametrize("name", list(CASES))
@pytest.mark.parametrize("leaf_size", [1, 3])
def test_structure_and_depth(name, leaf_size):
    F, V = CASES[name]
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=len(V)), method="aabb", leaf_size=leaf_size)
    col.dcd(V)
    b = col.bvh_arrays()
    m = len(F)
    assert b["leaf_size"] == leaf_size
    assert sorted(b["order"].tolist()) == list(range(m))
    assert b["begin"][0] == 0 and b["end"][0] == m
    inner = np.flatnonzero(b["right"] >= 0)
    l, r = b["left"][inner], b["right"][inner]
    assert (b["begin"][l] == b["begin"][inner]).all() and (b["end"][l] == b["begin"][r]).all()
    assert (b["end"][r] == b["end"][inner]).all()
    leaves = np.flatnonzero(b["right"] < 0)
    assert (b["end"][leaves] - b["begin"][leaves] <= leaf_size).all()
    tri = V[F[b["order"]]]  # (m, 3, 3) in leaf order
    for i in np.random.default_rng(0).choice(len(b["begin"]), 200):
        t = tri[b["begin"][i] : b["end"][i]].reshape(-1, 3)
        assert (t.min(axis=0) >= b["box"][i, 0]).all() and (t.max(axis=0) <= b["box"][i, 1]).all()
    assert b["depth"].max() <= 3 * np.log2(m) + 10, f"{name}: depth {b['depth'].max()} for {m} triangles"
