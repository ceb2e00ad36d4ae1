"""Hard CCD cases, named, with answers known by construction: exact gives the answer,
conservative never says no when the answer is yes."""

import numpy as np
import pytest

from conecull._core import ccd as C


def vf(p0, a0, b0, c0, p1, a1, b1, c1, arithmetic):
    return bool(C.vertex_face_ccd_rows(*[np.array([x], float) for x in (p0, a0, b0, c0, p1, a1, b1, c1)], arithmetic)[0])


def ee(a0, b0, c0, d0, a1, b1, c1, d1, arithmetic):
    return bool(C.edge_edge_ccd_rows(*[np.array([x], float) for x in (a0, b0, c0, d0, a1, b1, c1, d1)], arithmetic)[0])


T = ([0, 0, 0], [1, 0, 0], [0, 1, 0])  # a face in z = 0
Z = [0, 0, 0]


def still(face):
    return (*face, *face)


CASES = [
    # name, kind, args (t0 then t1), expected
    ("vf-vertex-on-face-at-t0", "vf", ([0.25, 0.25, 0], *T, [0.25, 0.25, 1], *T), True),
    ("vf-vertex-on-face-at-t1", "vf", ([0.25, 0.25, 1], *T, [0.25, 0.25, 0], *T), True),
    ("vf-contact-exactly-at-t1-edge", "vf", ([0.5, 0.5, 1], *T, [0.5, 0.5, 0], *T), True),   # lands on the hypotenuse
    ("vf-miss-just-outside-at-t1", "vf", ([0.5, 0.5 + 2**-40, 1], *T, [0.5, 0.5 + 2**-40, 0], *T), False),
    ("vf-vertex-on-edge-t0", "vf", ([0.5, 0, 0], *T, [0.5, 0, 3], *T), True),
    ("vf-zero-motion-apart", "vf", ([0.2, 0.2, 1e-3], *T, [0.2, 0.2, 1e-3], *T), False),
    ("vf-zero-motion-touching", "vf", ([0.2, 0.2, 0], *T, [0.2, 0.2, 0], *T), True),
    ("vf-pass-through", "vf", ([0.2, 0.2, 1], *T, [0.2, 0.2, -1], *T), True),
    ("vf-pass-beside", "vf", ([1.2, 1.2, 1], *T, [1.2, 1.2, -1], *T), False),
    ("vf-face-degenerates-to-zero-area", "vf",
     ([0.25, 0.1, 0.5], [0, 0, 0], [1, 0, 0], [0, 1, 0], [0.25, 0.1, 0.5], [0, 0, 1], [1, 0, 1], [0.5, 0, 1]), True),
    ("vf-degenerate-face-miss", "vf",
     ([0.25, 0.6, 0.5], [0, 0, 0], [1, 0, 0], [0, 1, 0], [0.25, 0.6, 0.5], [0, 0, 1], [1, 0, 1], [0.5, 0, 1]), False),
    ("vf-offset-1e6", "vf", (*[np.add(x, 1e6).tolist() for x in ([0.25, 0.25, 1], *T, [0.25, 0.25, -1], *T)],), True),
    ("vf-offset-1e6-miss", "vf", (*[np.add(x, 1e6).tolist() for x in ([1.25, 0.25, 1], *T, [1.25, 0.25, -1], *T)],), False),
    ("vf-motion-1e-12-through", "vf", ([0.25, 0.25, 5e-13], *T, [0.25, 0.25, -5e-13], *T), True),
    ("vf-motion-1e-12-short", "vf", ([0.25, 0.25, 2e-12], *T, [0.25, 0.25, 1e-12], *T), False),
    ("ee-crossing", "ee", ([0, 0, 1], [1, 0, 1], [0.5, -1, 0], [0.5, 1, 0], [0, 0, -1], [1, 0, -1], [0.5, -1, 0], [0.5, 1, 0]), True),
    ("ee-parallel-apart", "ee", ([0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0, 0, 0], [1, 0, 0], [0, 0.5, 0], [1, 0.5, 0]), False),
    ("ee-parallel-meeting-at-t1", "ee", ([0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0, 0, 0], [1, 0, 0], [0, 0, 0], [1, 0, 0]), True),
    ("ee-collinear-overlapping", "ee", ([0, 0, 0], [1, 0, 0], [0.5, 0, 0], [2, 0, 0], [0, 0, 0], [1, 0, 0], [0.5, 0, 0], [2, 0, 0]), True),
    ("ee-collinear-disjoint", "ee", ([0, 0, 0], [1, 0, 0], [1.5, 0, 0], [2, 0, 0], [0, 0, 0], [1, 0, 0], [1.5, 0, 0], [2, 0, 0]), False),
    ("ee-collinear-sliding-into-touch", "ee", ([0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0], [0, 0, 0], [1, 0, 0], [1, 0, 0], [2, 0, 0]), True),
    ("ee-endpoint-touch-at-t0", "ee", ([0, 0, 0], [1, 0, 0], [1, 0, 0], [1, 1, 0], [0, 0, 5], [1, 0, 5], [1, 0, 0], [1, 1, 0]), True),
    ("ee-skew-miss", "ee", ([0, 0, 0], [1, 0, 0], [2, -1, 1], [2, 1, 1], [0, 0, 0], [1, 0, 0], [2, -1, -1], [2, 1, -1]), False),
    ("ee-zero-motion", "ee", ([0, 0, 0], [1, 0, 0], [0.5, -1, 1e-9], [0.5, 1, 1e-9]) * 2, False),
]


@pytest.mark.parametrize("name,kind,args,expected", CASES, ids=[c[0] for c in CASES])
def test_hard_case(name, kind, args, expected):
    fn = vf if kind == "vf" else ee
    assert fn(*args, "exact") == expected
    if expected:
        assert fn(*args, "conservative")  # conservative never misses


def test_public_scalar_functions_and_errors():
    import conecull

    assert conecull.vertex_face_ccd([0.25, 0.25, 1], *T, [0.25, 0.25, -1], *T)
    assert not conecull.edge_edge_ccd([0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0, 0, 0], [1, 0, 0], [0, 0.5, 0],
                                      [1, 0.5, 0], arithmetic="conservative")
    with pytest.raises(ValueError, match=r"f1_t1: expected shape \(3,\), got \(2,\)"):
        conecull.vertex_face_ccd([0, 0, 0], *T, [0, 0, 0], T[0], [1, 0], T[2])
    with pytest.raises(ValueError, match=r"v_t0: non-finite coordinate nan"):
        conecull.vertex_face_ccd([np.nan, 0, 0], *T, [0, 0, 0], *T)
    with pytest.raises(ValueError, match="arithmetic: expected one of"):
        conecull.edge_edge_ccd(*([[0, 0, 0]] * 8), arithmetic="double")


def test_toi_is_a_lower_bound_on_the_earliest_contact():
    """A small triangle falling tip first onto a face at known times: toi <= the earliest
    contact of the tip, and close to it."""
    import conecull

    F = np.array([[0, 1, 2], [3, 4, 5]])
    tri = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    for z0, z1 in ((1.0, -1.0), (0.75, -0.25), (3.0, 0.0), (0.0, 5.0)):
        tip0, tip1 = np.array([0.2, 0.2, z0]), np.array([0.2, 0.2, z1])
        up = np.array([[0, 0, 0], [0.05, 0, 0.5], [0, 0.05, 0.5]])
        V0 = np.vstack([tri, tip0 + up])
        V1 = np.vstack([tri, tip1 + up])
        res = conecull.SelfCollider(conecull.Mesh(F)).ccd(V0, V1, toi=True)
        rows = res.vf.tolist()
        assert [3, 0] in rows
        t_true = z0 / (z0 - z1)
        t = res.toi[rows.index([3, 0])]
        assert t <= t_true and t_true - t < 1e-5


def test_toi_when_everything_meets_at_the_end_of_the_step():
    """Two triangles, one above the other, shrinking onto one point at t = 1: every contact is at
    t = 1 exactly, on a whole plane of the search's (t, u, v) box. The bound must still come
    within the search's tolerance (2^-20) of 1; splitting u and v as often as t ran out of
    boxes at 1 - 2^-7 (and took 3 ms per contact)."""
    import conecull

    V0 = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.2, 0.2, 1], [1.2, 0.2, 1], [0.2, 1.2, 1]], float)
    res = conecull.SelfCollider(conecull.Mesh(np.array([[0, 1, 2], [3, 4, 5]]))).ccd(V0, np.zeros_like(V0), toi=True)
    assert len(res.vf) + len(res.ee) == 15  # every vertex-face and edge-edge pair meets at the point
    assert (res.toi <= 1.0).all() and (1.0 - res.toi <= 2.0**-20).all(), res.toi


def test_toi_when_one_edge_of_the_box_hides_the_motion():
    """A review's case: vertex 0 slides in the plane of face (1, 2, 3), whose first two corners
    coincide at t = 0, and touches it only at t = 1. Along the search box's first t-edge F hardly
    changes, while along the other three it does; measured on that one edge, t was never split
    and the bound stayed at 0 (valid, but useless). Every contact here is at t = 1; each bound
    must come within a few boxes of the search's tolerance (2^-20) of it, also with the face made
    non-degenerate."""
    import conecull

    V0 = np.array([[0, 1, 0], [0, -1, 0], [0, -1, 0], [-1, 1, 0], [50, 50, 0], [51, 50, 0]], float)
    V1 = np.array([[0, 2, 0], [0, 0, 0], [2, 2, 0], [-1, 2, 0], [50, 50, 0], [51, 50, 0]], float)
    col = conecull.SelfCollider(conecull.Mesh(np.array([[1, 2, 3], [0, 4, 5]])))
    for nudge in (0.0, 1e-3, 1e-1):
        W0 = V0.copy()
        W0[2, 0] = nudge
        res = col.ccd(W0, V1, toi=True)
        assert res.vf.tolist() == [[0, 0]], (nudge, res.vf, res.ee)
        assert (1.0 - res.toi <= 2.0**-16).all() and (res.toi <= 1.0).all(), (nudge, res.toi)
