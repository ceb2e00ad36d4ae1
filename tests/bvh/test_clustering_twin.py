"""The BVH build against a Python twin of the algorithm it documents (core/src/bvh.cpp): bottom-up
clustering along the mesh (most compact merge first, ties by cluster ids; stragglers absorbed;
a stalled level or separate components joined top-down by median split), then the pre-order
layout. The core sorts with radix sorts whose order must equal the comparators written here;
the twin sorts with Python's sorted() on those comparators. Same IEEE double operations in the
same order, so the trees must be identical, node for node."""

import math

import numpy as np
import pytest

import conecull
from conecull.datasets.generated import sheet_for_triangles, uv_sphere


def twin_tree(F, V, edges, edge_face_offsets, edge_face_ids):
    """(left, right, root) of the merge tree over faces 0..m-1 and clusters m.., as the core
    builds it."""
    m = len(F)
    V = [tuple(float(x) for x in row) for row in V]

    def sub(p, q):
        return (p[0] - q[0], p[1] - q[1], p[2] - q[2])

    def norm(p):
        return math.sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2])

    def cross(p, q):
        return (p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0])

    area, perimeter, size, center = [], [0.0] * m, [1.0] * m, []
    for a, b, c in F:
        A, B, C = V[a], V[b], V[c]
        area.append(0.5 * norm(cross(sub(B, A), sub(C, A))))
        center.append(tuple((A[k] + B[k] + C[k]) / 3.0 for k in range(3)))
    cuts = []
    for e in range(len(edges)):
        length = norm(sub(V[edges[e][1]], V[edges[e][0]]))
        ids = edge_face_ids[edge_face_offsets[e]:edge_face_offsets[e + 1]]
        for i, f in enumerate(ids):
            perimeter[f] += length
            if i + 1 < len(ids):
                cuts.append((f, ids[i + 1], length))
    left, right = [-1] * m, [-1] * m
    parent, cluster_of_root = list(range(m)), list(range(m))

    def root(f):
        while parent[f] != f:
            f = parent[f]
        return f

    def cluster(f):
        return cluster_of_root[root(f)]

    active, representative = list(range(m)), list(range(m))

    def add(x, y):
        left.append(x)
        right.append(y)
        return len(left) - 1

    def merge(x, y, shared):
        i = add(x, y)
        area.append(area[x] + area[y])
        perimeter.append(max(0.0, perimeter[x] + perimeter[y] - 2.0 * shared))
        size.append(size[x] + size[y])
        center.append(tuple((size[x] / size[i]) * center[x][k] + (size[y] / size[i]) * center[y][k]
                            for k in range(3)))
        rx, ry = root(representative[x]), root(representative[y])
        parent[ry] = rx
        cluster_of_root[rx] = i
        representative.append(rx)

    while len(active) > 1:
        keyed, kept = [], []
        for fa, fb, length in cuts:
            a, b = cluster(fa), cluster(fb)
            if a != b:
                kept.append((fa, fb, length))
                keyed.append(((min(a, b), max(a, b)), length))
        cuts = kept
        if not cuts:
            break
        keyed.sort()  # by cluster pair, then length: each pair's shared length summed shortest first
        cand = []
        s = 0
        while s < len(keyed):
            e, shared = s, 0.0
            while e < len(keyed) and keyed[e][0] == keyed[s][0]:
                shared += keyed[e][1]
                e += 1
            a, b = keyed[s][0]
            P = max(0.0, perimeter[a] + perimeter[b] - 2.0 * shared)
            S = max(area[a] + area[b], 1e-300)
            balance = 1.0 + 0.5 * abs(math.log2(size[a] / size[b]))
            cand.append((P * P / S * balance, a, b, shared))
            s = e
        cand.sort(key=lambda c: (c[0], c[1], c[2]))  # most compact first, ties by ids
        n_ids = len(left)
        matched = [False] * n_ids
        for _, a, b, shared in cand:
            if not (matched[a] or matched[b]):
                matched[a] = matched[b] = True
                merge(a, b, shared)
        absorbed = [0] * n_ids
        for _, a, b, shared in cand:
            for lone, other in ((a, b), (b, a)):
                if matched[lone] or not matched[other] or absorbed[other] >= 2:
                    continue
                matched[lone] = True
                absorbed[other] += 1
                merge(cluster(representative[other]), lone, shared)
        nxt, seen = [], set()
        for a in active:
            now = cluster(representative[a]) if matched[a] else a
            if now not in seen:
                nxt.append(now)
                seen.add(now)
        stalled = 4 * len(nxt) > 3 * len(active)
        active = nxt
        if stalled:
            break
    if len(active) == 1:
        return left, right, active[0]

    def median_join(ids):
        if len(ids) == 1:
            return ids[0]
        ext = [max(center[i][k] for i in ids) - min(center[i][k] for i in ids) for k in range(3)]
        axis = 0 if ext[0] >= ext[1] and ext[0] >= ext[2] else (1 if ext[1] >= ext[2] else 2)
        ids = sorted(ids, key=lambda i: (center[i][axis], i))
        mid = len(ids) // 2
        lo = median_join(ids[:mid])
        hi = median_join(ids[mid:])
        return add(lo, hi)

    return left, right, median_join(sorted(active))


def twin_layout(left, right, root, m, leaf_size):
    """The pre-order layout: per node (begin, end, depth, right child or -1), and the face order."""
    count = [1] * len(left)
    for t in range(m, len(left)):
        count[t] = count[left[t]] + count[right[t]]
    nodes, order = [], []

    def collect(t):
        if left[t] < 0:
            order.append(t)
        else:
            collect(left[t])
            collect(right[t])

    def emit(t, depth):
        i = len(nodes)
        nodes.append([len(order), -1, depth, -1])
        if count[t] <= leaf_size:
            collect(t)
        else:
            emit(left[t], depth + 1)
            nodes[i][3] = len(nodes)
            emit(right[t], depth + 1)
        nodes[i][1] = len(order)

    emit(root, 0)
    return np.array(nodes, dtype=np.int64).reshape(-1, 4), np.array(order)


def bent(F, V, k=2.0):
    """The sheet curled about the y axis (distinct scores) but the grid's ties kept along y."""
    V = np.asarray(V, float).copy()
    x = V[:, 0] - V[:, 0].min()
    V[:, 0], V[:, 2] = np.sin(k * x) / k, (1 - np.cos(k * x)) / k
    return F, V


def two_sheets():
    F, V = sheet_for_triangles(300)
    F2, V2 = F + len(V), V + [0.1, 0.2, 0.7]
    return np.vstack([F, F2]), np.vstack([V, V2])


def fin_book(k):
    ang = np.linspace(0, np.pi, k)
    V = np.vstack([[[0, 0, 0], [0, 0, 1]], np.c_[np.cos(ang), np.sin(ang), np.full(k, 0.5)]])
    return np.array([[0, 1, 2 + i] for i in range(k)]), V


def soup(n=400, seed=3):
    rng = np.random.default_rng(seed)
    F = rng.integers(0, 150, (n, 3))
    F = F[(F[:, 0] != F[:, 1]) & (F[:, 1] != F[:, 2]) & (F[:, 0] != F[:, 2])]
    return F, rng.random((150, 3))


def loose_triangles(n=8, sheet=0):
    """n x n separate triangles on a grid (equal centre coordinates: the median split's ties by
    id), beside a sheet of `sheet` triangles: levels that stall once the sheet has merged."""
    F, V = [], []
    for i in range(n):
        for j in range(n):
            F.append([len(V), len(V) + 1, len(V) + 2])
            V += [[i, j, 0.0], [i + 0.5, j, 0.0], [i, j + 0.5, 0.3 * ((i + j) % 2)]]
    F, V = np.array(F), np.array(V)
    if sheet:
        F2, V2 = sheet_for_triangles(sheet)
        F, V = np.vstack([F, F2 + len(V)]), np.vstack([V, np.asarray(V2, float) + [0.0, 0.0, 2.0]])
    return F, V


CASES = {
    "flat sheet (equal scores everywhere)": sheet_for_triangles(600),
    "bent sheet": bent(*sheet_for_triangles(800)),
    "sphere": uv_sphere(12, 24),
    "two sheets (median join)": two_sheets(),
    "fin book (stalled levels)": fin_book(60),
    "triangle soup": soup(),
    "loose triangles (median join ties)": loose_triangles(),
    "sheet and loose triangles (a stalled level)": loose_triangles(8, 100),
}


@pytest.mark.parametrize("leaf_size", [1, 2, 3])
@pytest.mark.parametrize("name", list(CASES))
def test_bvh_equals_the_python_twin(name, leaf_size):
    F, V = CASES[name]
    F, V = np.asarray(F), np.asarray(V, float)
    mesh = conecull.Mesh(F, n_vertices=len(V))
    col = conecull.SelfCollider(mesh, method="nc", leaf_size=leaf_size, threads=1)
    col.dcd(V)
    got = col.bvh_arrays()
    topo = mesh._topo
    left, right, root = twin_tree(F.tolist(), V, np.asarray(topo.edges).tolist(),
                                  np.asarray(topo.edge_face_offsets).tolist(), np.asarray(topo.edge_face_ids).tolist())
    nodes, order = twin_layout(left, right, root, len(F), leaf_size)
    assert len(got["begin"]) == len(nodes)
    np.testing.assert_array_equal(got["order"], order)
    np.testing.assert_array_equal(got["begin"], nodes[:, 0])
    np.testing.assert_array_equal(got["end"], nodes[:, 1])
    np.testing.assert_array_equal(got["depth"], nodes[:, 2])
    inner = got["left"] >= 0
    np.testing.assert_array_equal(got["right"][inner], nodes[inner, 3])
    assert (nodes[~inner, 3] == -1).all()
