"""Mesh topology against straightforward Python implementations."""

import numpy as np

import conecull
from conecull.datasets.generated import grid_sheet, uv_sphere


def py_edges(F):
    return sorted({(min(a, b), max(a, b)) for f in F.tolist() for a, b in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0]))})


def check(F, n=None):
    m = conecull.Mesh(F, n_vertices=n)
    E = py_edges(F)
    assert m.edges.dtype == np.int64 and m.edges.tolist() == [list(e) for e in E]
    eid = {e: i for i, e in enumerate(E)}
    fe = m.face_edges
    for f, row in enumerate(F.tolist()):
        for k in range(3):
            a, b = row[k], row[(k + 1) % 3]
            assert fe[f, k] == eid[(min(a, b), max(a, b))]
    off, ids = m.edge_faces
    for e, (a, b) in enumerate(E):
        expect = sorted(f for f, row in enumerate(F.tolist()) if a in row and b in row)
        assert sorted(ids[off[e] : off[e + 1]].tolist()) == expect
    boundary = [e for e in range(len(E)) if off[e + 1] - off[e] == 1]
    assert m.boundary_edges.tolist() == boundary
    voff, vids = m.vertex_faces
    for v in range(m.n_vertices):
        assert sorted(vids[voff[v] : voff[v + 1]].tolist()) == [f for f, row in enumerate(F.tolist()) if v in row]
    return m


def test_grid():
    F, _ = grid_sheet(6, 5)
    m = check(F)
    assert len(m.boundary_edges) == 2 * (5 + 4)
    assert len(m.nonmanifold_edges) == 0 and len(m.nonmanifold_vertices) == 0
    assert m.n_components == 1


def test_sphere_closed():
    F, _ = uv_sphere(6, 8)
    m = check(F)
    assert len(m.boundary_edges) == 0 and m.n_components == 1


def test_components_fins_bowties_isolated():
    F, _ = grid_sheet(3, 3)
    two = np.vstack([F, F + 9])
    m = check(two)
    assert m.n_components == 2 and sorted(set(m.face_component.tolist())) == [0, 1]
    fin = np.vstack([F, [[0, 1, 9]], [[1, 0, 10]]])  # edge (0, 1) gets three faces
    m = check(fin)
    assert (m.edges[m.nonmanifold_edges] == [0, 1]).all(axis=1).any()
    bowtie = np.array([[0, 1, 2], [0, 3, 4]])  # two triangles touching at vertex 0 only
    m = check(bowtie)
    assert m.nonmanifold_vertices.tolist() == [0] and m.n_components == 1
    m = check(F, n=12)  # trailing isolated vertices
    assert m.n_vertices == 12
