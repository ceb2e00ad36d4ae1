"""The non-penetration filter (ccd/non_penetration.hpp, Tang et al. 2010 Sec. 5.1) against its
exact twin: the Bernstein coefficients of the coplanarity cubic, and the filter's verdict on
random, near-coplanar and far-offset VF and EE pairs, where rounded coefficients get signs wrong."""

import zlib
from fractions import Fraction as Fr

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import exact_twin as ex
from conecull._core import predicates as P

FILTER = {"vf": P.vf_never_coplanar, "ee": P.ee_never_coplanar}
coord = st.floats(-4.0, 4.0, allow_nan=False).map(lambda x: 0.0 if abs(x) < 2.0**-100 else x)
pt = st.tuples(coord, coord, coord)


def bern3(c, t):
    return c[0] * (1 - t) ** 3 + 3 * c[1] * t * (1 - t) ** 2 + 3 * c[2] * t ** 2 * (1 - t) + c[3] * t ** 3


@settings(max_examples=200, deadline=None)
@given(st.sampled_from(["vf", "ee"]), st.lists(pt, min_size=8, max_size=8))
def test_bernstein_coefficients_give_the_cubic(kind, pts):
    """The twin's coefficients are the cubic's: equal at seven values of t, so identical."""
    rows0, rows1 = ex.coplanarity_rows(kind, pts[:4], pts[4:])
    c = ex.coplanarity_bernstein(rows0, rows1)
    for t in (Fr(0), Fr(1, 5), Fr(1, 3), Fr(1, 2), Fr(2, 3), Fr(6, 7), Fr(1)):
        assert bern3(c, t) == ex.coplanarity_cubic(rows0, rows1, t)


def run_filter(kind, x0, x1):
    """The core's verdicts on k pairs: x0, x1 of shape (k, 4, 3)."""
    return FILTER[kind](*[np.ascontiguousarray(x[:, j]) for x in (x0, x1) for j in range(4)])


def check_against_twin(kind, x0, x1):
    got = run_filter(kind, x0, x1)
    want = [ex.never_coplanar(kind, a, b) for a, b in zip(x0, x1)]
    bad = [i for i in range(len(got)) if bool(got[i]) != want[i]]
    assert not bad, f"{kind}: filter differs from the exact twin at rows {bad[:5]}: {x0[bad[0]]}, {x1[bad[0]]}"
    return np.array(want)


@settings(max_examples=300, deadline=None)
@given(st.sampled_from(["vf", "ee"]), st.lists(pt, min_size=8, max_size=8))
def test_filter_matches_exact_twin_random(kind, pts):
    x = np.array(pts, dtype=float).reshape(1, 2, 4, 3)
    check_against_twin(kind, x[:, 0], x[:, 1])


def rounded_signs(kind, x0, x1):
    """The coefficients' signs as a plain floating-point evaluation would give them (no filter)."""
    def rows(x):
        if kind == "vf":
            v, a, b, c = x
            return b - a, c - a, v - a
        a, b, c, d = x
        return b - a, d - c, c - a
    (p0, q0, r0), (p1, q1, r1) = rows(x0), rows(x1)
    det = lambda p, q, r: float(np.dot(p, np.cross(q, r)))
    c = (det(p0, q0, r0), det(p1, q0, r0) + det(p0, q1, r0) + det(p0, q0, r1),
         det(p1, q1, r0) + det(p1, q0, r1) + det(p0, q1, r1), det(p1, q1, r1))
    return [int(np.sign(v)) for v in c]


def near_coplanar_pairs(rng, n, offset, scale):
    """VF / EE points nearly coplanar at t = 0, t = 1 or both (the fourth point put on the plane
    of the other three in floating point, so a few ulps off it), on an offset: the cubic's end
    coefficients sit at the rounding level, and the inner ones often too."""
    out0, out1 = [], []
    for _ in range(n):
        frames = []
        base = rng.standard_normal((3, 3)) * scale + offset
        motion = rng.standard_normal((3, 3)) * scale * rng.choice([1e-3, 1.0])
        s, t = rng.uniform(-1, 2, size=2)
        for k in range(2):
            a, b, c = base + k * motion
            d = a + s * (b - a) + t * (c - a)  # on the plane, up to rounding
            if rng.random() < 0.3:
                d = d + rng.standard_normal(3) * scale * 1e-15
            frames.append(np.array([d, a, b, c]))
        if rng.random() < 0.5:  # one end only near-coplanar
            frames[1][0] = frames[1][0] + rng.standard_normal(3) * scale
        out0.append(frames[0])
        out1.append(frames[1])
    return np.array(out0), np.array(out1)


@pytest.mark.parametrize("kind", ["vf", "ee"])
@pytest.mark.parametrize("offset,scale", [(0.0, 1.0), (1.0, 1.0), (1e6, 1e-3), (-3.7e4, 1.0), (1e-30, 1e-32)])
def test_filter_matches_exact_twin_near_coplanar(kind, offset, scale):
    rng = np.random.default_rng(zlib.crc32(repr((kind, offset, scale)).encode()))  # the same cases every run
    x0, x1 = near_coplanar_pairs(rng, 300, offset, scale)  # as EE: edge (d, a) against edge (b, c)
    want = check_against_twin(kind, x0, x1)
    assert want.any() and not want.all(), "the cases should include culled and kept pairs"


def test_rounded_signs_are_wrong_on_these_cases():
    """Why the filter must be certified: on the near-coplanar pairs a plain floating-point
    evaluation gets some coefficient's sign wrong (about a third of them near the origin, where
    the fourth point's rounding is at the determinant's rounding level; far from it the rows are
    rounded first and the evaluation is right), and the filter still agrees with the twin."""
    rng = np.random.default_rng(7)
    wrong = 0
    for kind in ("vf", "ee"):
        x0, x1 = near_coplanar_pairs(rng, 300, 0.0, 1.0)
        for a, b in zip(x0, x1):
            exact = [ex.sgn(c) for c in ex.coplanarity_bernstein(*ex.coplanarity_rows(kind, a, b))]
            wrong += rounded_signs(kind, a, b) != exact
        check_against_twin(kind, x0, x1)
    assert wrong >= 50


@pytest.mark.parametrize("kind", ["vf", "ee"])
def test_exactly_coplanar_end_is_never_culled(kind):
    """A pair coplanar at t = 0 (c0 = 0 exactly) may touch there: never culled, whatever the rest."""
    a, b, c = np.array([0.0, 0, 0]), np.array([1.0, 0, 0]), np.array([0.0, 1, 0])
    d = np.array([0.25, 0.5, 0.0])
    x0 = np.array([[d, a, b, c]])
    x1 = np.array([[d + [0, 0, 1.0], a + [0, 0, 2.0], b + [0, 0, 2.0], c + [0, 0, 2.0]]])
    assert not run_filter(kind, x0, x1)[0]
    assert not ex.never_coplanar(kind, x0[0], x1[0])


@pytest.mark.parametrize("name,value", [("v0", np.nan), ("c1", 1e300)])
def test_bad_input_names_the_argument(name, value):
    x = [np.zeros((2, 3)) for _ in range(8)]
    names = ["v0", "a0", "b0", "c0", "v1", "a1", "b1", "c1"]
    x[names.index(name)][1, 2] = value
    with pytest.raises(ValueError, match=name):
        P.vf_never_coplanar(*x)


def as_mesh_pairs(kind, x0, x1):
    """Pairs of points (k, 4, 3) as the loop sees them: positions V0, V1 with four vertices per
    pair, faces or edges over them, and (vertex, face) or (edge, edge) rows."""
    k = len(x0)
    V0, V1 = x0.reshape(-1, 3).copy(), x1.reshape(-1, 3).copy()
    base = 4 * np.arange(k, dtype=np.int32)
    if kind == "vf":  # (v, a, b, c): face (a, b, c)
        prims = np.stack([base + 1, base + 2, base + 3], axis=1).astype(np.int32)
        pairs = np.stack([base, np.arange(k)], axis=1).astype(np.int32)
    else:  # (a, b, c, d): edges (a, b) and (c, d)
        prims = np.stack([base, base + 1, base + 2, base + 3], axis=1).reshape(-1, 2).astype(np.int32)
        pairs = np.stack([2 * np.arange(k), 2 * np.arange(k) + 1], axis=1).astype(np.int32)
    return V0, V1, prims, pairs


FOUR = {"vf": P.vf_never_coplanar4, "ee": P.ee_never_coplanar4}


def exact_signs(kind, x0, x1):
    return [{ex.sgn(c) for c in ex.coplanarity_bernstein(*ex.coplanarity_rows(kind, a, b))} for a, b in zip(x0, x1)]


def check_four(kind, x0, x1):
    """The four-lane filter's verdicts (1 culled, -1 kept, 0 left to the exact filter): the same
    from the AVX2 and the portable path, and each proven verdict the exact one."""
    V0, V1, prims, pairs = as_mesh_pairs(kind, x0, x1)
    fast = FOUR[kind](V0, V1, prims, pairs)
    assert fast.dtype == np.int8 and set(np.unique(fast)) <= {-1, 0, 1}
    assert (fast == FOUR[kind](V0, V1, prims, pairs, portable=True)).all()
    signs = exact_signs(kind, x0, x1)
    culled = np.array([s in ({1}, {-1}) for s in signs])
    mixed = np.array([{1, -1} <= s for s in signs])  # two coefficients of opposite signs
    assert not ((fast == 1) & ~culled).any(), "proved culled a pair the exact filter keeps"
    assert not ((fast == -1) & ~mixed).any(), "proved kept a pair without coefficients of opposite signs"
    return fast, culled, mixed


@pytest.mark.parametrize("kind", ["vf", "ee"])
@pytest.mark.parametrize("offset,scale", [(0.0, 1.0), (1.0, 1.0), (1e6, 1e-3), (1e-30, 1e-32)])
def test_four_at_a_time_filter(kind, offset, scale):
    """The CCD loop's four-lane filter (AVX2 where the CPU has it) gives the portable path's
    verdicts, and proves only what the exact twin says; near the origin most of these pairs are
    beyond any floating-point proof (the loop's full filter decides them exactly), far from it
    most are proven."""
    rng = np.random.default_rng(11)
    x0, x1 = near_coplanar_pairs(rng, 203, offset, scale)  # 203: the last block is padded
    fast, culled, mixed = check_four(kind, x0, x1)
    if offset == 1e6:
        assert (fast == 1).sum() >= 0.9 * culled.sum() and (fast == -1).sum() >= 0.9 * mixed.sum()


def test_four_at_a_time_filter_on_random_pairs():
    """Away from degeneracy the filter decides every pair, both ways."""
    rng = np.random.default_rng(3)
    x0 = rng.standard_normal((401, 4, 3))
    x1 = x0 + 0.3 * rng.standard_normal((401, 4, 3))
    for kind in ("vf", "ee"):
        fast, culled, mixed = check_four(kind, x0, x1)
        assert ((fast == 1) == culled).all() and ((fast == -1) == mixed).all()
        assert (fast != 0).all() and 0 < (fast == 1).sum() < len(fast)


def test_four_at_a_time_filter_bad_input():
    V = np.zeros((4, 3))
    faces = np.array([[1, 2, 3]], dtype=np.int32)
    with pytest.raises(ValueError, match="pairs"):
        P.vf_never_coplanar4(V, V, faces, np.array([[0, 1]], dtype=np.int32))
    with pytest.raises(ValueError, match="V1"):
        P.vf_never_coplanar4(V, np.zeros((3, 3)), faces, np.array([[0, 0]], dtype=np.int32))
    with pytest.raises(ValueError, match="edges"):
        P.ee_never_coplanar4(V, V, np.array([[0, 9]], dtype=np.int32), np.array([[0, 0]], dtype=np.int32))


def test_the_four_lane_comparisons_reach_the_avx2_path():
    """check_four compares the default path with the portable one; without AVX2 the default is the
    portable path and that comparison is vacuous: say so as a skip, not as a pass."""
    if not P.never_coplanar4_vectorised():
        pytest.skip("this CPU has no AVX2: check_four compared the portable path with itself")
