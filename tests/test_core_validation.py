"""The core's stage functions (conecull._core, what tests, benchmarks and teachers call directly)
reject values the exact predicates cannot take — NaN, infinities, non-zero magnitudes outside
[2^-128, 2^128] — with a ValueError naming the argument and the entry, like the public API (which
now relies on the same check). Before, they answered anyway: a sign, a verdict, a cone."""

import numpy as np
import pytest

import exact_twin as ex
from conecull import _core as core
from conecull._core import ccd as CC, cone as C, contour as CT, elementary as E, predicates as P

BAD = [(np.nan, "non-finite coordinate nan"), (np.inf, "non-finite coordinate inf"),
       (-np.inf, "non-finite coordinate -inf"), (1e300, r"coordinate 1e\+300"), (-2.0**129, r"coordinate -6.80564733841877e\+38"),
       (1e-300, "coordinate 1e-300"), (2.0**-129, r"coordinate 1.4693679385278594e-39")]

pts = [np.array([[0.1, 0.2, 0.3]]), np.array([[1.0, 0.0, 0.5]]), np.array([[0.0, 1.0, -0.5]]), np.array([[0.3, 0.3, 2.0]])]
loop = np.array([0, 1, 2, 3], np.int32)
topo = core.build_topology(np.array([[0, 1, 2], [1, 2, 3]], np.int32), 4)


def with_bad(arrays, which, value, index):
    out = [a.copy() for a in arrays]
    out[which][index] = value
    return out


# name -> (call on a list of arrays, the arrays, the names of the arguments they become)
CASES = {
    "orient3d": (lambda a: P.orient3d(*a), pts, ["a", "b", "c", "d"]),
    "side_sign": (lambda a: P.side_sign(*a), pts, ["a", "b", "c", "l"]),
    "ray_side_sign": (lambda a: P.ray_side_sign(*a), pts, ["v", "o", "r", "l"]),
    "orient2d": (lambda a: P.orient2d(*a), [p[:, :2].copy() for p in pts[:3]], ["a", "b", "c"]),
    "contour_test": (lambda a: CT.contour_test(loop, a[0], a[1][0]), [np.vstack(pts), np.array([[0.0, 0.0, 1.0]])],
                     ["V", "l"]),
    "sct_contour_test": (lambda a: CT.sct_contour_test(loop, a[0], np.array([0.0, 0.0, 1.0])), [np.vstack(pts)], ["V"]),
    "cbc_contour_test": (lambda a: CT.cbc_contour_test(loop, a[0], np.array([0.0, 0.0, 1.0])), [np.vstack(pts)], ["V"]),
    "cbc_contour_test_ccd": (lambda a: CT.cbc_contour_test_ccd(loop, a[0], a[1], np.array([0.0, 0.0, 1.0])),
                             [np.vstack(pts), np.vstack(pts) + 0.1], ["V0", "V1"]),
    "simplicity_test": (lambda a: CT.simplicity_test(loop, a[0], np.array([0.0, 0.0, 1.0])), [np.vstack(pts)], ["V"]),
    "simplicity_test_ccd": (lambda a: CT.simplicity_test_ccd(loop, a[0], a[1], np.array([0.0, 0.0, 1.0])),
                            [np.vstack(pts), np.vstack(pts) + 0.1], ["V0", "V1"]),
    "contour_test_ccd": (lambda a: CC.contour_test_ccd(loop, a[0], a[1], np.array([0.0, 0.0, 1.0])),
                         [np.vstack(pts), np.vstack(pts) + 0.1], ["V0", "V1"]),
    "triangle_cone": (lambda a: C.triangle_cone(*a), pts[:3], ["a", "b", "c"]),
    "triangle_cone_ccd": (lambda a: CC.triangle_cone_ccd(*a), pts[:3] + pts[1:4], ["a0", "b0", "c0", "a1", "b1", "c1"]),
    "csidesign1": (lambda a: CC.csidesign1(*a), pts + [pts[0] + 1.0, np.array([[0.0, 0.0, 1.0]])],
                   ["o", "b0", "c0", "b1", "c1", "l"]),
    "vertex_face_ccd_rows": (lambda a: CC.vertex_face_ccd_rows(*a, "exact"), pts + [p + 0.5 for p in pts],
                             ["v_t0", "f0_t0", "f1_t0", "f2_t0", "v_t1", "f0_t1", "f1_t1", "f2_t1"]),
    "edge_edge_ccd_rows": (lambda a: CC.edge_edge_ccd_rows(*a, "conservative"), pts + [p + 0.5 for p in pts],
                           ["ea0_t0", "ea1_t0", "eb0_t0", "eb1_t0", "ea0_t1", "ea1_t1", "eb0_t1", "eb1_t1"]),
    "SelfCollider.dcd": (lambda a: core.SelfCollider(topo, "nc", 2, 1).dcd(a[0], False, 1), [np.vstack(pts)], ["V"]),
    "SelfCollider.ccd": (lambda a: core.SelfCollider(topo, "nc", 2, 1).ccd(a[0], a[1], "exact", False, False, 1),
                         [np.vstack(pts), np.vstack(pts) + 0.1], ["V0", "V1"]),
}


@pytest.mark.parametrize("name", list(CASES))
def test_good_input_runs(name):
    fn, arrays, _ = CASES[name]
    fn(arrays)


@pytest.mark.parametrize("value,text", BAD, ids=[t.split()[-1] for _, t in BAD])
@pytest.mark.parametrize("name", list(CASES))
def test_every_coordinate_argument_rejects_bad_values(name, value, text):
    """Each argument in turn gets the bad value; the error names that argument and the entry."""
    fn, arrays, names = CASES[name]
    for which, arg in enumerate(names):
        r = arrays[which].shape[0] - 1  # the last row, column 1
        bad = with_bad(arrays, which, value, (r, 1))
        where = "at index 1" if (name, arg) == ("contour_test", "l") else f"at row {r}, column 1"  # l: a (3,) vector
        with pytest.raises(ValueError, match=rf"^{arg}: {text} {where}"):
            fn(bad)


def test_zero_and_range_ends_are_accepted():
    """Zero and the two ends of the range are inputs like any other."""
    for v in (0.0, -0.0, 2.0**-128, -(2.0**-128), 2.0**128, -(2.0**128)):
        a = [p.copy() for p in pts]
        a[3][0, 2] = v
        assert P.orient3d(*a)[0] == ex.orient3d(*(p[0] for p in a)), v  # and the sign is exact


def test_triangle_pairs_name_the_pair_and_corner():
    ids = np.array([[0, 1, 2]], np.int32), np.array([[3, 4, 5]], np.int32)
    Pt = np.vstack(pts[:3])[None].copy()
    Qt = np.vstack(pts[1:])[None].copy()
    assert E.triangles_collide(ids[0], Pt, ids[1], Qt).shape == (1,)
    Qt[0, 2, 0] = np.nan
    with pytest.raises(ValueError, match=r"^Q: non-finite coordinate nan at index \(0, 2, 0\)"):
        E.triangles_collide(ids[0], Pt, ids[1], Qt)


def test_optional_points_and_cones():
    V = np.vstack(pts)
    with pytest.raises(ValueError, match=r"^r: non-finite coordinate nan at index 0"):
        CT.contour_test(loop, V, np.array([0.0, 0.0, 1.0]), r=np.array([np.nan, 1.0, 0.0]))
    with pytest.raises(ValueError, match=r"^o: coordinate 1e\+200 at index 2 is outside"):
        CT.contour_test(loop, V, np.array([0.0, 0.0, 1.0]), o=np.array([0.0, 1.0, 1e200]))
    axis, cb, sb = C.triangle_cone(*pts[:3])
    C.merge_cones(axis, cb, sb, axis, cb, sb)
    axis_tiny = axis.copy()
    axis_tiny[0, 0] = 1e-300  # cone axes are not coordinates: tiny components are fine
    C.merge_cones(axis_tiny, cb, sb, axis, cb, sb)
    with pytest.raises(ValueError, match=r"^sin_q: non-finite value nan at index 0"):
        C.merge_cones(axis, cb, sb, axis, cb, np.array([np.nan]))
    # A bounded cone must be one the merge can bound: unit axis, cos <= 1, sin >= 0; a full
    # cone's axis is never read.
    assert cb[0] > 0
    with pytest.raises(ValueError, match=r"^axis_q: row 0 has length (2|1\.9999\d*); a bounded cone \(cos_q > 0\) needs a unit axis"):
        C.merge_cones(axis, cb, sb, 2.0 * axis, cb, sb)
    with pytest.raises(ValueError, match=r"^axis_p: row 0 has length 0(\.0)?;"):
        C.merge_cones(0.0 * axis, cb, sb, axis, cb, sb)
    with pytest.raises(ValueError, match=r"^cos_p: 1\.5 at index 0 is above 1"):
        C.merge_cones(axis, np.array([1.5]), sb, axis, cb, sb)
    with pytest.raises(ValueError, match=r"^sin_q: -0\.5 at index 0 is negative"):
        C.merge_cones(axis, cb, sb, axis, cb, np.array([-0.5]))
    full_axis, full_cb, full_sb = C.merge_cones(0.0 * axis, np.array([-1.0]), np.array([1.0]), axis, cb, sb)
    assert full_cb[0] <= 0  # a full cone merges into a full cone, whatever its axis


def _in_range(x: float) -> bool:
    """The rule, on the value: 0, or finite with magnitude in [2^-128, 2^128]."""
    return x == 0.0 or (np.isfinite(x) and 2.0**-128 <= abs(x) <= 2.0**128)


def test_range_check_agrees_with_the_rule_at_its_edges():
    """The check works on the bit patterns' 32-bit words (common.hpp); every value here, alone in
    a long array (the vectorised scan) at a random entry, is accepted exactly when the rule on
    the value says so: both ends and their neighbours, denormals, NaNs with payloads, patterns
    whose high word alone is in range, both signs."""
    rng = np.random.default_rng(6)
    ends = [2.0**-128, 2.0**128, 2.0**-1022, 5e-324, np.inf, 1.0, 2.0**-127, 2.0**127]
    values = [0.0, np.nan, np.float64(np.uint64(0x7ff0000000000001).view(np.float64)),
              np.float64(np.uint64(0x47f0000000000001).view(np.float64)),  # 2^128's high word, low bits set
              np.float64(np.uint64(0x37efffffffffffff).view(np.float64)),  # just below 2^-128
              np.float64(np.uint64(0x0000000000000001).view(np.float64))]
    for e in ends:
        values += [e, np.nextafter(e, 0.0), np.nextafter(e, np.inf)]
    values += list(2.0 ** rng.uniform(-140, 140, 200) * rng.uniform(1, 2, 200))
    pos = np.array(values, dtype=np.float64)
    values = list(pos) + list((pos.view(np.uint64) | np.uint64(1 << 63)).view(np.float64))  # the sign bit set
    V = np.full((3000, 3), 0.5)
    for v in values:
        r, c = int(rng.integers(V.shape[0])), int(rng.integers(3))
        a = V.copy()
        a[r, c] = v
        if _in_range(v):
            core.contour.simplicity_test(np.arange(3, dtype=np.int32), a, np.array([0.0, 0.0, 1.0]))
        else:
            with pytest.raises(ValueError, match=rf"^V: .* at row {r}, column {c}"):
                core.contour.simplicity_test(np.arange(3, dtype=np.int32), a, np.array([0.0, 0.0, 1.0]))


@pytest.mark.parametrize("threads", [1, 2, 3])
def test_query_inputs_are_checked_in_chunks_on_several_threads(threads):
    """A query scans its positions on its threads, in chunks of 16K values (common.hpp,
    require_points): on a mesh of 40K values (three chunks), a bad value in the first, middle or
    last chunk, or two of them, is found and named (the first in row order) as on one thread, for
    V (DCD) and for V0 and V1 (CCD)."""
    n = 40000 // 3 + 1
    faces = np.array([[i, i + 1, i + 2] for i in range(0, n - 2, 3)], np.int32)
    big = core.build_topology(faces, n)
    V = np.random.default_rng(3).uniform(-1.0, 1.0, (n, 3))
    for rows in ([0], [n // 2], [n - 1], [n // 2, n - 1], [5, n - 1]):
        for value, text in BAD[:1] + BAD[3:4]:
            a = V.copy()
            for r in rows:
                a[r, 2] = value
            where = rf"at row {rows[0]}, column 2"
            with pytest.raises(ValueError, match=rf"^V: {text} {where}"):
                core.SelfCollider(big, "nc", 2, threads).dcd(a, False, threads)
            with pytest.raises(ValueError, match=rf"^V0: {text} {where}"):
                core.SelfCollider(big, "nc", 2, threads).ccd(a, V, "exact", False, False, threads)
            with pytest.raises(ValueError, match=rf"^V1: {text} {where}"):
                core.SelfCollider(big, "nc", 2, threads).ccd(V, a, "exact", False, False, threads)
    core.SelfCollider(big, "nc", 2, threads).dcd(V, False, threads)  # and good input passes
