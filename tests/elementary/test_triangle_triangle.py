"""The exact triangle-triangle test against the rational oracle on many pairs: lattice points
(exact coplanarity, collinearity, touching, degenerate triangles) and random near-degenerate
ones, with 0, 1, 2 or 3 shared vertices."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from conecull._core import elementary as E
from oracle import triangle_pair_collides

lattice = st.integers(-2, 2)
lpoint = st.tuples(lattice, lattice, lattice)


def run_cpp(fp, P, fq, Q):
    return bool(E.triangles_collide(np.array([fp], np.int32), np.array([P], float), np.array([fq], np.int32),
                                    np.array([Q], float))[0])


def run_oracle(fp, P, fq, Q):
    shared = [k for k in range(3) if fp[k] in fq]
    return triangle_pair_collides(P, Q, tuple(shared))


@st.composite
def pair(draw, coords=lpoint):
    """Two faces over vertex ids 0..5; ids shared between faces share positions."""
    shared = draw(st.integers(0, 3))
    pos = [draw(coords) for _ in range(6)]
    fp = [0, 1, 2]
    others = [3, 4, 5]
    fq = draw(st.permutations(fp[:shared] + others[: 3 - shared]))
    if draw(st.booleans()):
        fp = draw(st.permutations(fp))
    P = [pos[i] for i in fp]
    Q = [pos[i] for i in fq]
    return fp, P, list(fq), Q


def distinct_ids(fp, fq):
    return len(set(fp)) == 3 and len(set(fq)) == 3


@settings(max_examples=3000, deadline=None)
@given(pair(), st.sampled_from([1.0, 0.375, 1e-3]), st.sampled_from([0.0, 1e6, -12345.5]))
def test_lattice_pairs_match_oracle(p, scale, offset):
    fp, P, fq, Q = p
    P = [[c * scale + offset for c in v] for v in P]
    Q = [[c * scale + offset for c in v] for v in Q]
    assert run_cpp(fp, P, fq, Q) == run_oracle(fp, P, fq, Q)


near = st.floats(-1.0, 1.0, allow_nan=False).map(lambda x: 0.0 if abs(x) < 2.0**-100 else x)


@settings(max_examples=1500, deadline=None)
@given(pair(st.tuples(near, near, near)))
def test_random_pairs_match_oracle(p):
    fp, P, fq, Q = p
    assert run_cpp(fp, P, fq, Q) == run_oracle(fp, P, fq, Q)


@settings(max_examples=1500, deadline=None)
@given(pair(), st.lists(st.integers(-3, 3), min_size=18, max_size=18))
def test_ulp_perturbed_lattice_pairs(p, kicks):
    """Lattice configurations nudged by a few ulps: just off (or on) the degenerate ones."""
    fp, P, fq, Q = p
    pos = {}
    for ids, pts in ((fp, P), (fq, Q)):
        for i, v in zip(ids, pts):
            pos.setdefault(i, v)
    it = iter(kicks)
    moved = {i: [c + k * np.spacing(1.0) * 2.0 for c, k in zip(v, (next(it), next(it), next(it)))] for i, v in pos.items()}
    P = [moved[i] for i in fp]
    Q = [moved[i] for i in fq]
    assert run_cpp(fp, P, fq, Q) == run_oracle(fp, P, fq, Q)


def _rotation(angles):
    a, b, c = angles
    rx = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    ry = np.array([[np.cos(b), 0, np.sin(b)], [0, 1, 0], [-np.sin(b), 0, np.cos(b)]])
    rz = np.array([[np.cos(c), -np.sin(c), 0], [np.sin(c), np.cos(c), 0], [0, 0, 1]])
    return rz @ ry @ rx


@settings(max_examples=1500, deadline=None)
@given(pair(st.tuples(lattice, lattice, st.just(0))), st.tuples(*[st.floats(0.0, 6.3)] * 3),
       st.sampled_from([0.0, 1e3, -7.25]))
def test_rotated_flat_pairs(p, angles, offset):
    """Coplanar lattice pairs (neighbours on a flat sheet, folded over or not) turned by a
    floating-point rotation: near-coplanar, so orient3d's filter fails and the shared-vertex and
    shared-edge tests take their 2D shortcut or the exact fallback."""
    fp, P, fq, Q = p
    R = _rotation(angles)
    # Coordinates in the domain the façade admits (0 or magnitude >= 2^-128), as the other tests.
    turn = lambda v: [0.0 if abs(x) < 2.0**-128 else float(x) for x in R @ np.array(v, float) + offset]  # noqa: E731
    P, Q = [turn(v) for v in P], [turn(v) for v in Q]
    ids = {}
    for f, pts in ((fp, P), (fq, Q)):  # shared ids keep bit-identical positions
        for k, i in enumerate(f):
            pts[k] = ids.setdefault(i, pts[k])
    assert run_cpp(fp, P, fq, Q) == run_oracle(fp, P, fq, Q)


CASES = [
    # name, fp, P, fq, Q, expected
    ("disjoint", [0, 1, 2], [[0, 0, 0], [1, 0, 0], [0, 1, 0]], [3, 4, 5], [[0, 0, 1], [1, 0, 1], [0, 1, 1]], False),
    ("vertex-on-face", [0, 1, 2], [[0, 0, 0], [1, 0, 0], [0, 1, 0]], [3, 4, 5], [[0.25, 0.25, 0], [1, 1, 1], [0, 1, 1]], True),
    ("vertex-on-vertex-distinct-ids", [0, 1, 2], [[0, 0, 0], [1, 0, 0], [0, 1, 0]], [3, 4, 5], [[1, 0, 0], [2, 0, 1], [2, 1, 1]], True),
    ("edge-crosses-edge", [0, 1, 2], [[0, 0, 0], [2, 0, 0], [0, 2, 0]], [3, 4, 5], [[1, -1, 0], [1, 3, 0], [1, 1, 5]], True),
    ("coplanar-overlap", [0, 1, 2], [[0, 0, 0], [2, 0, 0], [0, 2, 0]], [3, 4, 5], [[0.5, 0.5, 0], [3, 0.5, 0], [0.5, 3, 0]], True),
    ("shared-vertex-only", [0, 1, 2], [[0, 0, 0], [1, 0, 0], [0, 1, 0]], [0, 4, 5], [[0, 0, 0], [-1, 0, 0], [0, -1, 1]], False),
    ("shared-vertex-fold-through", [0, 1, 2], [[0, 0, 0], [2, 0, 0], [0, 2, 0]], [0, 4, 5], [[0, 0, 0], [1, 1, 1], [1, 1, -1]], True),
    ("shared-vertex-coplanar-overlap", [0, 1, 2], [[0, 0, 0], [2, 0, 0], [0, 2, 0]], [0, 4, 5], [[0, 0, 0], [2, 1, 0], [1, 2, 0]], True),
    ("shared-edge-hinge", [0, 1, 2], [[0, 0, 0], [1, 0, 0], [0, 1, 0]], [1, 0, 5], [[1, 0, 0], [0, 0, 0], [0, -1, 0.5]], False),
    ("shared-edge-coplanar-opposite", [0, 1, 2], [[0, 0, 0], [1, 0, 0], [0, 1, 0]], [1, 0, 5], [[1, 0, 0], [0, 0, 0], [0, -1, 0]], False),
    ("shared-edge-fold-over", [0, 1, 2], [[0, 0, 0], [1, 0, 0], [0, 1, 0]], [1, 0, 5], [[1, 0, 0], [0, 0, 0], [0.5, 2, 0]], True),
    ("same-three-vertices", [0, 1, 2], [[0, 0, 0], [1, 0, 0], [0, 1, 0]], [2, 1, 0], [[0, 1, 0], [1, 0, 0], [0, 0, 0]], False),
    ("degenerate-segment-through-face", [0, 1, 2], [[0, 0, 0], [2, 0, 0], [0, 2, 0]], [3, 4, 5], [[0.5, 0.5, -1], [0.5, 0.5, 0], [0.5, 0.5, 1]], True),
    ("degenerate-point-on-edge", [0, 1, 2], [[0, 0, 0], [2, 0, 0], [0, 2, 0]], [3, 4, 5], [[1, 0, 0], [1, 0, 0], [1, 0, 0]], True),
]


@pytest.mark.parametrize("name,fp,P,fq,Q,expected", CASES, ids=[c[0] for c in CASES])
def test_named_cases(name, fp, P, fq, Q, expected):
    assert run_oracle(fp, P, fq, Q) == expected
    assert run_cpp(fp, P, fq, Q) == expected
    assert run_cpp(fq, Q, fp, P) == expected  # symmetric
