"""The DCD loop's pair tests (elementary/triangles_apart.hpp), four pairs at a time.

triangles_apart: a lane may say "apart" only when the rule holds exactly: the corners of one
triangle that are not corners of the other lie strictly on one side of the other's plane. Checked
against a Fraction twin of that rule and against the rational pair oracle, on the pair strategies
of the exact triangle test (lattice, near-degenerate, ulp-nudged, rotated flat sheets); the AVX2
path and the portable one must give the same bits, lane by lane; and clearly separated pairs must
be settled (a filter that never answers would pass the rest).

triangles_collide4: the whole answer (the rejection, then the lanes it leaves decided from its
signs, or by the exact test): equal to the rational oracle on the same strategies, both paths."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from conecull._core import elementary as E
from exact_twin import orient3d
from oracle import triangle_pair_collides
from test_triangle_triangle import _rotation, lattice, near, pair


def exact_rule(fp, P, fq, Q) -> bool:
    """Fraction twin: the corners of Q not in P strictly on one side of plane(P), or the reverse."""
    def one_side(A, B, b_shared):
        s = [orient3d(A[0], A[1], A[2], b) for b, shared in zip(B, b_shared) if not shared]
        return all(x > 0 for x in s) or all(x < 0 for x in s)
    return one_side(P, Q, [i in fp for i in fq]) or one_side(Q, P, [i in fq for i in fp])


def as_mesh(fp, P, fq, Q):
    """Faces 0 = fp, 1 = fq over the pair's vertex ids (shared ids share positions)."""
    pos = {}
    for ids, pts in ((fp, P), (fq, Q)):
        for i, v in zip(ids, pts):
            pos.setdefault(i, v)
    n = max(pos) + 1
    V = np.zeros((n, 3))
    for i, v in pos.items():
        V[i] = v
    return np.array([fp, fq], np.int32), V


def apart_both(faces, V, pairs):
    a = E.triangles_apart(faces, V, pairs)
    b = E.triangles_apart(faces, V, pairs, portable=True)
    np.testing.assert_array_equal(a, b)  # the AVX2 path and the portable one, lane by lane
    return a


def collide4_both(faces, V, pairs):
    a = E.triangles_collide4(faces, V, pairs)
    b = E.triangles_collide4(faces, V, pairs, portable=True)
    np.testing.assert_array_equal(a, b)
    return a


def check(fp, P, fq, Q):
    faces, V = as_mesh(fp, P, fq, Q)
    P, Q = V[fp].tolist(), V[fq].tolist()  # the positions the core sees
    both_ways = np.array([[0, 1], [1, 0]], np.int32)
    got = apart_both(faces, V, both_ways)
    assert got[0] == got[1]  # the rule is symmetric in P and Q
    shared = [k for k in range(3) if fp[k] in fq]
    collides = triangle_pair_collides(P, Q, tuple(shared))
    if got[0]:
        assert exact_rule(fp, P, fq, Q)
        assert not collides
    hit = collide4_both(faces, V, both_ways)
    assert hit[0] == hit[1] == collides, (fp, P, fq, Q)
    return bool(got[0])


@settings(max_examples=1500, deadline=None)
@given(pair(), st.sampled_from([1.0, 0.375, 1e-3]), st.sampled_from([0.0, 1e6, -12345.5]))
def test_lattice_pairs(p, scale, offset):
    fp, P, fq, Q = p
    check(fp, [[c * scale + offset for c in v] for v in P], fq, [[c * scale + offset for c in v] for v in Q])


@settings(max_examples=1000, deadline=None)
@given(pair(st.tuples(near, near, near)))
def test_random_pairs(p):
    check(*p)


@settings(max_examples=1000, deadline=None)
@given(pair(), st.lists(st.integers(-3, 3), min_size=18, max_size=18))
def test_ulp_perturbed_lattice_pairs(p, kicks):
    """Lattice pairs nudged by a few ulps: signs of size ~1e-16 next to exact zeros, where only a
    correct error bound keeps the filter from answering."""
    fp, P, fq, Q = p
    it = iter(kicks)
    nudge = lambda v: [c + next(it) * np.spacing(1.0) * 2.0 for c in v]  # noqa: E731
    moved = {}
    for ids, pts in ((fp, P), (fq, Q)):
        for i, v in zip(ids, pts):
            if i not in moved:
                moved[i] = nudge(v)
    check(fp, [moved[i] for i in fp], fq, [moved[i] for i in fq])


@settings(max_examples=1000, deadline=None)
@given(pair(st.tuples(lattice, lattice, st.just(0))), st.tuples(*[st.floats(0.0, 6.3)] * 3),
       st.sampled_from([0.0, 1e3, -7.25]))
def test_rotated_flat_pairs(p, angles, offset):
    """Coplanar lattice pairs turned by a floating-point rotation: every sign is near zero."""
    fp, P, fq, Q = p
    R = _rotation(angles)
    turn = lambda v: [0.0 if abs(x) < 2.0**-128 else float(x) for x in R @ np.array(v, float) + offset]  # noqa: E731
    check(fp, [turn(v) for v in P], fq, [turn(v) for v in Q])


def random_triangles(rng, k, lift):
    """k triangles of unit size in the plane z = 0 (random shapes), lifted by lift."""
    T = rng.uniform(-1, 1, (k, 3, 3))
    T[:, :, 2] *= 0.2
    T[:, :, 2] += lift
    return T


def test_separated_pairs_are_settled():
    """Pairs whose planes clearly separate them: every lane must say apart, with no corner shared,
    one shared (the others' corners well off the plane) and an edge shared (a real dihedral)."""
    rng = np.random.default_rng(7)
    k = 203  # not a multiple of four: the padded last block too
    A, B = random_triangles(rng, k, 0.0), random_triangles(rng, k, 3.0)
    V = np.concatenate([A.reshape(-1, 3), B.reshape(-1, 3)])
    faces = np.arange(6 * k, dtype=np.int32).reshape(-1, 3)
    pairs = np.stack([np.arange(k), np.arange(k) + k], axis=1).astype(np.int32)
    assert apart_both(faces, V, pairs).all()
    # One shared corner: Q = (p0, far, far) with its free corners 3 above P's plane z ~ 0.
    P = np.array([[0, 0, 0], [1, 0, 0.01], [0, 1, -0.01]], float)
    V = np.concatenate([P, rng.uniform(-1, 1, (2 * k, 3)) + [0, 0, 3]])
    faces = np.array([[0, 1, 2]] + [[0, 3 + 2 * i, 4 + 2 * i] for i in range(k)], np.int32)
    pairs = np.stack([np.zeros(k), np.arange(1, k + 1)], axis=1).astype(np.int32)
    assert apart_both(faces, V, pairs).all()
    # A shared edge (0, 1), the third corner of Q above or below P's plane: a hinge.
    V = np.concatenate([P, rng.uniform(-1, 1, (k, 3)) + [0, 0, 0]])
    V[3:, 2] = np.where(rng.random(k) < 0.5, -1, 1) * rng.uniform(0.5, 2, k)
    faces = np.array([[0, 1, 2]] + [[1, 0, 3 + i] for i in range(k)], np.int32)
    assert apart_both(faces, V, pairs).all()


def soup(seed, n_vertices, n_faces, n_pairs):
    """Random faces over random points in the unit cube (vertices shared at random), and random
    pairs of distinct faces."""
    rng = np.random.default_rng(seed)
    V = rng.uniform(-1, 1, (n_vertices, 3))
    faces = np.array([rng.choice(n_vertices, 3, replace=False) for _ in range(n_faces)], np.int32)
    pairs = rng.integers(0, n_faces, (n_pairs, 2)).astype(np.int32)
    return faces, V, pairs[pairs[:, 0] != pairs[:, 1]]


def test_lanes_match_single_pairs():
    """Many pairs of a random soup in one call: each lane's bit is the bit of its pair tested on
    its own (a transpose or a mask that mixed lanes would show here), and sound."""
    faces, V, pairs = soup(seed=11, n_vertices=60, n_faces=80, n_pairs=401)
    got = apart_both(faces, V, pairs)
    one = np.array([apart_both(faces, V, pairs[i:i + 1])[0] for i in range(len(pairs))])
    np.testing.assert_array_equal(got, one)
    assert 0.1 < got.mean() < 0.9  # a soup in the unit cube: some pairs settled, some not
    rule = np.array([exact_rule(faces[i].tolist(), V[faces[i]].tolist(), faces[j].tolist(), V[faces[j]].tolist())
                     for i, j in pairs])
    assert not (got & ~rule).any()  # sound
    np.testing.assert_array_equal(got, rule)  # and, far from degenerate, as sharp as the exact rule


def test_collide4_lanes_match_the_exact_test():
    """A soup of generic pairs (no corner shared, one shared, an edge shared; most planes cross each
    other, so most pairs reach the decision from signs) in one call: each lane is triangles_collide's
    answer for its pair, and pairs sharing no corner or one both collide and miss."""
    faces, V, pairs = soup(seed=5, n_vertices=40, n_faces=120, n_pairs=2001)
    got = collide4_both(faces, V, pairs)
    fp, fq = faces[pairs[:, 0]], faces[pairs[:, 1]]
    want = E.triangles_collide(fp, V[fp], fq, V[fq])
    np.testing.assert_array_equal(got, want)
    shared = np.array([len(set(a) & set(b)) for a, b in zip(fp.tolist(), fq.tolist())])
    for k in (0, 1):  # both cases of the decision from signs, each with both answers
        assert 0 < got[shared == k].mean() < 1, k
    assert (shared == 2).sum() > 10  # shared edges too (they go to the exact test)


@pytest.mark.parametrize("bad, match", [
    (dict(pairs=np.array([[0, 2]], np.int32)), "pairs: face index 2"),
    (dict(faces=np.array([[0, 1, 9], [0, 1, 2]], np.int32)), "faces: vertex index 9"),
    (dict(V=np.array([[0, 0, 0], [1, 0, 0], [0, 1, np.nan]])), "V: non-finite"),
    (dict(pairs=np.array([0, 1], np.int32)), "pairs: expected shape"),
])
def test_bad_input_is_named(bad, match):
    args = dict(faces=np.array([[0, 1, 2], [0, 2, 1]], np.int32), V=np.eye(3), pairs=np.array([[0, 1]], np.int32))
    args.update(bad)
    for test in (E.triangles_apart, E.triangles_collide4):
        with pytest.raises(ValueError, match=match):
            test(args["faces"], args["V"], args["pairs"])


def test_the_lane_comparisons_reach_the_avx2_path():
    """apart_both and collide4_both compare the default path with the portable one; without AVX2 the
    default is the portable path and that comparison is vacuous: say so as a skip, not as a pass."""
    if not E.triangles_apart_vectorised():
        pytest.skip("this CPU has no AVX2: apart_both and collide4_both compared the portable path with itself")
