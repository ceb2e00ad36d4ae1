"""A CCD answer depends on the moving points only, not on the order they are stored in.

Float and conservative answers to a near miss used to depend on which corner of a face was the
base of the test (a review counted 1199 of 200,000 near-miss rows answered differently with a
face's corners rotated); the tests now order each primitive's corners by their coordinates
first (elementary_ccd.cpp, "canonical corner order"). Checked here on near misses built to sit
at the modes' tolerances (a vertex grazing a face's plane or passing just outside an edge, two
edges passing just beside an end), which the old code answered differently in about 2% of
the VF rows (float) and 5% (conservative), and on whole meshes: rotating every face's corners
or renumbering the vertices changes no query's contacts or times of impact in any mode."""

import itertools

import numpy as np
import pytest

import conecull
from ccd_brute_force import generated_steps
from conecull._core import ccd as C

MODES = ["float", "conservative", "exact"]


def _unit(x):
    return x / np.linalg.norm(x, axis=1)[:, None]


def near_miss_vf(rng, n):
    """A face moving almost rigidly; a vertex that, at a random time, is at distance 10^-16..10^-5
    from the face's plane, near its interior or just outside one of its edges."""
    a0 = rng.normal(size=(n, 3))
    b0, c0 = a0 + rng.normal(size=(n, 3)), a0 + rng.normal(size=(n, 3))
    move = rng.normal(scale=0.1, size=(n, 3))
    a1, b1, c1 = (x + move + rng.normal(scale=0.01, size=(n, 3)) for x in (a0, b0, c0))
    t = rng.uniform(0, 1, n)[:, None]
    at, bt, ct = (x0 + (x1 - x0) * t for x0, x1 in ((a0, a1), (b0, b1), (c0, c1)))
    which = rng.integers(0, 4, n)  # 0: anywhere near the face; 1-3: just beside one edge
    eps = 10.0 ** rng.uniform(-13, -5, n) * rng.choice([-1, 1], n)
    u, v = rng.uniform(-0.05, 0.6, n), rng.uniform(-0.05, 0.6, n)
    u = np.where(which == 1, eps, u)
    v = np.where(which == 2, eps, v)
    v = np.where(which == 3, 1 - u + eps, v)
    height = np.where(which > 0, 10.0 ** rng.uniform(-16, -9, n), 10.0 ** rng.uniform(-12, -5, n))
    q = at + u[:, None] * (bt - at) + v[:, None] * (ct - at)
    q += (height * rng.choice([-1, 1], n))[:, None] * _unit(np.cross(bt - at, ct - at))
    velocity = rng.normal(size=(n, 3))
    return [q - velocity * t, a0, b0, c0, q + velocity * (1 - t), a1, b1, c1]


def near_miss_ee(rng, n):
    """Two moving edges; the second is translated so that at a random time the edges pass at
    10^-16..10^-5, their closest points inside or just beyond an end."""
    a0, c0 = rng.normal(size=(n, 3)), rng.normal(size=(n, 3))
    b0, d0 = a0 + rng.normal(size=(n, 3)), c0 + rng.normal(size=(n, 3))
    a1, b1, c1, d1 = (x + rng.normal(scale=0.3, size=(n, 3)) for x in (a0, b0, c0, d0))
    t = rng.uniform(0, 1, n)[:, None]
    at, bt, ct, dt = (x0 + (x1 - x0) * t for x0, x1 in ((a0, a1), (b0, b1), (c0, c1), (d0, d1)))
    which = rng.integers(0, 5, n)  # 0: inside both edges; 1-4: just beyond one of the four ends
    eps = 10.0 ** rng.uniform(-13, -5, n) * rng.choice([-1, 1], n)
    u, w = rng.uniform(-0.05, 1.05, n), rng.uniform(-0.05, 1.05, n)
    u = np.where(which == 1, eps, np.where(which == 2, 1 + eps, u))
    w = np.where(which == 3, eps, np.where(which == 4, 1 + eps, w))
    height = np.where(which > 0, 10.0 ** rng.uniform(-16, -9, n), 10.0 ** rng.uniform(-12, -5, n))
    on_ab = at + u[:, None] * (bt - at)
    on_cd = ct + w[:, None] * (dt - ct)
    shift = on_ab + (height * rng.choice([-1, 1], n))[:, None] * _unit(np.cross(bt - at, dt - ct)) - on_cd
    return [a0, b0, c0 + shift, d0 + shift, a1, b1, c1 + shift, d1 + shift]


def face_orders(rows):
    """The VF rows with the face's corners in each of their six orders."""
    p0, a0, b0, c0, p1, a1, b1, c1 = rows
    for perm in itertools.permutations(range(3)):
        s0, s1 = [(a0, b0, c0)[i] for i in perm], [(a1, b1, c1)[i] for i in perm]
        yield perm, [p0, *s0, p1, *s1]


def edge_orders(rows):
    """The EE rows in each of their eight orders: either edge reversed, the edges swapped."""
    a0, b0, c0, d0, a1, b1, c1, d1 = rows
    for flip_ab, flip_cd, swap in itertools.product([False, True], repeat=3):
        e0, e1 = ((b0, a0), (b1, a1)) if flip_ab else ((a0, b0), (a1, b1))
        f0, f1 = ((d0, c0), (d1, c1)) if flip_cd else ((c0, d0), (c1, d1))
        if swap:
            e0, f0, e1, f1 = f0, e0, f1, e1
        yield (flip_ab, flip_cd, swap), [*e0, *f0, *e1, *f1]


def _sample_size(mode):
    return 400 if mode == "conservative" else 3000  # a conservative near miss takes ~0.1 ms


KINDS = {  # kind: (near misses, the rows test, the rows in each of their orders)
    "vf": (near_miss_vf, C.vertex_face_ccd_rows, face_orders),
    "ee": (near_miss_ee, C.edge_edge_ccd_rows, edge_orders),
}


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize("kind", KINDS)
def test_an_answer_ignores_the_order_of_the_corners(kind, mode):
    make, test, orders = KINDS[kind]
    rows = make(np.random.default_rng(11 if kind == "vf" else 12), _sample_size(mode))
    first = test(*rows, mode)
    # near misses on both sides of each mode's decision, not a sample every order agrees on trivially
    assert 0.05 < first.mean() < 0.95
    for order, reordered in orders(rows):
        again = test(*reordered, mode)
        assert np.array_equal(again, first), f"{kind} {mode}: order {order}: rows {np.flatnonzero(again != first)[:10]}"


def test_the_order_is_total_on_signed_zeros_and_ties():
    """Corners tied in their first coordinates, or differing only in the sign of a zero, still
    get one order: every permutation answers alike (here on a vertex grazing the face's edge by
    2^-52 in float, where the base corner decides)."""
    zero_faces = [
        ([0.0, 0.0, 0.0], [-0.0, 1.0, 0.0], [0.0, 0.0, 1.0]),  # x all zero, one of them -0
        ([0.5, 0.0, 0.0], [0.5, 0.0, 1.0], [0.5, 1.0, 0.0]),  # x tied; y tied for two
    ]
    for face in zero_faces:
        F0 = [np.array([c], float) for c in face]
        F1 = [x.copy() for x in F0]
        mid = (F0[1] + F0[2]) / 2
        for mode in MODES:
            for drift in (2.0**-52, -(2.0**-52), 0.0):
                p0 = mid + [[1.0, drift, drift]]
                p1 = mid + [[-1.0, drift, drift]]
                answers = {bool(C.vertex_face_ccd_rows(*[p0, *s0, p1, *s1], mode)[0])
                           for s0, s1 in ((list(o[1:4]), list(o[5:8])) for _, o in face_orders([p0, *F0, p1, *F1]))}
                assert len(answers) == 1, (face, mode, drift)


def _grazing_sheets():
    """Two 8x8 sheets, the upper one sliding across the lower at heights 1e-12..1e-6 per vertex
    (every vertex and edge of the upper sheet grazes the lower one's faces and edges)."""
    from conecull.datasets.generated import grid_sheet

    F, V = grid_sheet(8, 8)
    rng = np.random.default_rng(3)
    upper = V + [0.013, 0.021, 0.0]
    upper[:, 2] = 10.0 ** rng.uniform(-12, -6, len(V)) * rng.choice([-1, 1], len(V))
    V0 = np.vstack([V, upper])
    V1 = np.vstack([V, upper + [0.09, 0.05, 0.0]])
    return np.vstack([F, F + len(V)]), V0, V1


def _scenes():
    yield ("grazing-sheets", *_grazing_sheets())
    yield from generated_steps()


@pytest.mark.parametrize("scene", [s[0] for s in _scenes()])
@pytest.mark.parametrize("mode", MODES)
def test_a_query_ignores_how_faces_and_vertices_are_stored(scene, mode):
    name, F, V0, V1 = next(s for s in _scenes() if s[0] == scene)
    rng = np.random.default_rng(5)

    def query(F, V0, V1):
        col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=len(V0)), method="nc", threads=1)
        res = col.ccd(V0, V1, arithmetic=mode, toi=True)
        return col.mesh.edges, res

    E, res = query(F, V0, V1)
    vf = {(int(v), int(f)): t for (v, f), t in zip(res.vf, res.toi[: len(res.vf)])}
    ee = {(int(a), int(b)): t for (a, b), t in zip(res.ee, res.toi[len(res.vf):])}

    # Each face's corners rotated by a random amount (orientation kept: cones see the same faces).
    shift = rng.integers(0, 3, len(F))
    F_rot = np.stack([F[np.arange(len(F)), (shift + k) % 3] for k in range(3)], axis=1)
    _, res_rot = query(F_rot, V0, V1)
    assert {(int(v), int(f)): t for (v, f), t in zip(res_rot.vf, res_rot.toi[: len(res_rot.vf)])} == vf
    assert {(int(a), int(b)): t for (a, b), t in zip(res_rot.ee, res_rot.toi[len(res_rot.vf):])} == ee

    # The vertices renumbered: the contacts are the same once mapped back (edges by their ends).
    perm = rng.permutation(len(V0))  # new id of old vertex i is perm[i]
    inv = np.argsort(perm)
    E2, res_ren = query(perm[F], V0[inv], V1[inv])
    vf_ren = {(int(inv[v]), int(f)): t for (v, f), t in zip(res_ren.vf, res_ren.toi[: len(res_ren.vf)])}
    assert vf_ren == vf
    edge_id = {tuple(e): k for k, e in enumerate(E)}
    old_id = [edge_id[tuple(np.sort(inv[e]))] for e in E2]  # renumbered edge id -> original id
    ee_ren = {tuple(sorted((old_id[a], old_id[b]))): t for (a, b), t in zip(res_ren.ee, res_ren.toi[len(res_ren.vf):])}
    assert ee_ren == ee
