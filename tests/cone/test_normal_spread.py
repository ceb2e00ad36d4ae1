"""normal_spread: whether a node's normals fit in an open hemisphere, with witnesses checked here
in exact arithmetic (Fractions), independently of the module's own integer checks:
- "within": the axis l has l . n > 0 for every exact normal (DCD) or control vector (CCD), and
  then for n(t) at sampled t of the step;
- "beyond": the witness's exact vectors hold the origin in their convex hull (an exact solve here).
Completeness against a floating-point LP (scipy) where its margin is clear, hand cases whose
answer turns on a sign 2^-40 away, and the core's cones: a bounded cone proves "within", so a
node proven "beyond" must have failed the cone test (else the core's cone would be unsound)."""

import itertools
from fractions import Fraction as Fr

import numpy as np
import pytest

import conecull
import exact_twin as ex
from conecull.normal_spread import CONTROL_NAMES, Normals, exact_dot_signs, node_spreads, normal_spread
from meshgen_basic import random_meshes, wavy_sheet
from shared_data import import_or_skip


def exact_row(F, V0, V1, t, control):
    """The exact normal of triangle t (DCD), or its control vector (CCD): twin of ccd_cone.hpp."""
    a0, b0, c0 = (ex.fr3(V0[v]) for v in F[t])
    if V1 is None or control == 0:
        return ex.cross(ex.sub(b0, a0), ex.sub(c0, a0))
    a1, b1, c1 = (ex.fr3(V1[v]) for v in F[t])
    if control == 1:
        return ex.cross(ex.sub(b1, a1), ex.sub(c1, a1))
    p = ex.cross(ex.sub(b0, a0), ex.sub(c1, a1))
    q = ex.cross(ex.sub(b1, a1), ex.sub(c0, a0))
    return tuple(x + y for x, y in zip(p, q))


def zero_combination(vs):
    """lambda >= 0, sum 1, sum lambda_j v_j = 0 over exact vectors vs (a Gauss-Jordan solve in
    Fractions; None if there is none or it is not unique)."""
    t = len(vs)
    rows = [[Fr(vs[j][r]) for j in range(t)] + [Fr(0)] for r in range(3)] + [[Fr(1)] * t + [Fr(1)]]
    r = 0
    for c in range(t):
        p = next((i for i in range(r, 4) if rows[i][c] != 0), None)
        if p is None:
            return None
        rows[r], rows[p] = rows[p], rows[r]
        rows[r] = [x / rows[r][c] for x in rows[r]]
        for i in range(4):
            if i != r and rows[i][c] != 0:
                f = rows[i][c]
                rows[i] = [x - f * y for x, y in zip(rows[i], rows[r])]
        r += 1
    if any(rows[i][t] != 0 for i in range(r, 4)):
        return None
    lam = [rows[i][t] for i in range(t)]
    return lam if all(x >= 0 for x in lam) else None


def check_spread(s, F, tris, V0, V1=None):
    """The spread's witness, checked exactly; returns its kind."""
    ccd = V1 is not None
    controls = range(3) if ccd else range(1)
    if s.kind == "within":
        l = ex.fr3(s.axis)
        for t in tris:
            for c in controls:
                assert ex.dot(l, exact_row(F, V0, V1, int(t), c)) > 0, (t, c)
        assert 0 <= s.half_angle <= 90  # rounded: a margin of 1e-17 prints as 90
    elif s.kind == "beyond":
        assert 1 <= len(s.witness) <= 4
        assert {t for t, _ in s.witness} <= {int(t) for t in tris}
        vs = [exact_row(F, V0, V1, t, c) for t, c in s.witness]
        assert zero_combination(vs) is not None, s.witness
    return s.kind


def tri_mesh(normals_pts):
    """A soup of triangles given by their corner points."""
    V = np.array([p for tri in normals_pts for p in tri], np.float64)
    return np.arange(len(V)).reshape(-1, 3), V


def with_normal(n):
    """A triangle (integer corners) whose normal (b - a) x (c - a) is a positive multiple of n."""
    n = np.array(n, np.float64)
    u = np.cross(n, [1.0, 0, 0]) if abs(n[0]) < 0.9 * np.linalg.norm(n) else np.cross(n, [0, 1.0, 0])
    w = np.cross(n, u)
    tri = [np.zeros(3), u, w]
    assert np.dot(np.cross(u, w), n) > 0
    return tri


def spread_of(F, V, V1=None):
    return normal_spread(Normals(F, V, V1), np.arange(len(F)))


def test_a_fold_is_within_until_the_two_triangles_lie_on_each_other():
    # two triangles sharing the edge (0,0,0)-(0,1,0) at dihedral angle `angle` (pi: flat); at 0
    # the second lies on the first, facing the other way: opposite normals
    for angle, kind in ((np.pi, "within"), (np.pi / 2, "within"), (0.05 * np.pi, "within"), (0.0, "beyond")):
        p = [1.0, 0.0, 0.0] if angle == 0 else [-1.0, 0.0, 0.0] if angle == np.pi else [np.cos(np.pi - angle), 0.0,
                                                                                          np.sin(np.pi - angle)]
        V = np.array([[0, 0, 0], [0, 1, 0], [1, 0, 0], p], np.float64)
        F = np.array([[0, 2, 1], [0, 1, 3]])
        assert check_spread(spread_of(F, V), F, [0, 1], V) == kind, angle


def test_a_zero_area_triangle_is_its_own_witness():
    V = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0]], np.float64)
    F = np.array([[0, 1, 2], [0, 1, 3]])
    sp = spread_of(F, V)
    assert check_spread(sp, F, [0, 1], V) == "beyond"
    assert sp.witness == ((0, 0),)
    assert "zero area" in sp.sentence()


def test_three_normals_through_a_plane_of_the_origin():
    F, V = tri_mesh([with_normal(n) for n in ((1, 0, 0), (0, 1, 0), (-1, -1, 0))])
    sp = spread_of(F, V)
    assert check_spread(sp, F, range(3), V) == "beyond"
    assert len(sp.witness) == 3


@pytest.mark.parametrize("sign", [1, -1])
def test_the_answer_turns_on_a_sign_2_to_the_minus_40_away(sign):
    # (1,0,0), (0,1,0), (-1,-1,e), (0,0,-1): the origin is in their hull iff e > 0
    e = sign * 2.0**-40
    F, V = tri_mesh([with_normal(n) for n in ((1, 0, 0), (0, 1, 0), (-1, -1, e), (0, 0, -1))])
    # the corners are rounded: the exact normals decide, so compute the expected answer from them
    vs = [exact_row(F, V, None, t, 0) for t in range(4)]
    expected = "beyond" if any(zero_combination([vs[i] for i in sub]) is not None
                               for k in range(1, 5) for sub in itertools.combinations(range(4), k)) else "within"
    assert expected == ("beyond" if sign > 0 else "within")
    assert check_spread(spread_of(F, V), F, range(4), V) == expected


def test_random_normal_sets_match_a_linear_program_and_a_convex_hull():
    # clearly within: max t s.t. n_i . l >= t, l in [-1, 1]^3 (scipy's LP) is above 1e-6;
    # clearly beyond: the origin is inside the normals' convex hull (qhull), 1e-6 from every facet
    why = "the float twins of this test (pip install 'conecull[test]')"
    linprog = import_or_skip("scipy.optimize", why).linprog
    ConvexHull = import_or_skip("scipy.spatial", why).ConvexHull
    rng = np.random.default_rng(7)
    decided = {"within": 0, "beyond": 0}
    for trial in range(150):
        k = int(rng.integers(2, 12))
        spread = rng.uniform(0.2, 1.6)  # about a random axis: narrow sets fit, wide ones do not
        axis = rng.standard_normal(3)
        axis /= np.linalg.norm(axis)
        normals = axis + spread * rng.standard_normal((k, 3))
        F, V = tri_mesh([with_normal(n) for n in normals])
        N = np.array([np.cross(V[f[1]] - V[f[0]], V[f[2]] - V[f[0]]) for f in F])
        N /= np.linalg.norm(N, axis=1)[:, None]
        lp = linprog([0, 0, 0, -1], A_ub=np.hstack([-N, np.ones((k, 1))]), b_ub=np.zeros(k),
                     bounds=[(-1, 1)] * 3 + [(None, 1)])
        inside = k >= 4 and bool((ConvexHull(N).equations[:, 3] < -1e-6).all())
        kind = check_spread(spread_of(F, V), F, range(k), V)
        if -lp.fun > 1e-6 or inside:
            assert kind == ("beyond" if inside else "within"), (trial, -lp.fun)
            decided[kind] += 1
    assert min(decided.values()) >= 20, decided  # both answers were exercised


def test_ccd_control_vectors_are_the_bernstein_coefficients_of_the_normal():
    # n(t) = (1-t)^2 n0 + 2t(1-t) n1 + t^2 n2, with the rows n0, n2 and 2 n1 (CONTROL_NAMES)
    rng = np.random.default_rng(3)
    F = np.array([[0, 1, 2]])
    for _ in range(20):
        V0, V1 = rng.standard_normal((3, 3)), rng.standard_normal((3, 3))
        n0, n2, two_n1 = (exact_row(F, V0, V1, 0, c) for c in range(3))
        for t in (Fr(0), Fr(1, 3), Fr(1, 2), Fr(1)):
            a, b, c = (ex.lerp(V0[i], V1[i], t) for i in range(3))
            nt = ex.cross(ex.sub(b, a), ex.sub(c, a))
            assert nt == tuple((1 - t) ** 2 * x + t * (1 - t) * y + t**2 * z for x, y, z in zip(n0, two_n1, n2))
    assert CONTROL_NAMES == ("n0", "n2", "2 n1")


def test_ccd_within_holds_the_normal_at_every_sampled_time():
    F, V0 = wavy_sheet(6, 0.1, 0.0, 1)
    V1 = V0.copy()
    V1[:, 2] += 0.3 * V0[:, 0] ** 2  # bend over the step
    sp = spread_of(F, V0, V1)
    assert check_spread(sp, F, range(len(F)), V0, V1) == "within"
    l = ex.fr3(sp.axis)
    for t in (Fr(k, 8) for k in range(9)):
        P = [ex.lerp(V0[i], V1[i], t) for i in range(len(V0))]
        for f in F:
            assert ex.dot(l, ex.cross(ex.sub(P[f[1]], P[f[0]]), ex.sub(P[f[2]], P[f[0]]))) > 0


def crumpled_frames():
    for name, F, V in random_meshes():
        yield name, F, V, None
        rng = np.random.default_rng(len(F))
        yield name + "-ccd", F, V, V + 0.05 * rng.standard_normal(V.shape)


@pytest.mark.parametrize("name,F,V0,V1", list(crumpled_frames()), ids=lambda x: x if isinstance(x, str) else "")
def test_every_node_agrees_with_the_core_cones(name, F, V0, V1):
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=len(V0)), method="nc", leaf_size=1)
    res = col.dcd(V0, trace=True) if V1 is None else col.ccd(V0, V1, trace=True)
    bvh, cones = col.bvh_arrays(), col.cone_arrays()
    nodes = np.arange(len(bvh["depth"]))
    normals = Normals(F, *res.trace.positions)
    spreads = node_spreads(normals, bvh, nodes)
    kinds = {"within": 0, "beyond": 0, "undecided": 0}
    for n in nodes.tolist():
        tris = bvh["order"][bvh["begin"][n] : bvh["end"][n]]
        s = spreads[n]
        kinds[check_spread(s, F, tris, V0, V1)] += 1
        if cones["cos_bound"][n] > 0:  # the core bounded the cone: its normals fit in a hemisphere
            assert s.kind == "within", (name, n)
        if not s.analysed:  # inherited from a descendant: the search gives the same kind
            assert normal_spread(normals, tris).kind == "beyond"
    assert kinds["undecided"] == 0, kinds
    assert kinds["within"] > 0


def test_nodes_whose_cone_failed_in_a_traced_query():
    # the recording's question: on the folding sheet's last frames some cones fail because the
    # normals span a hemisphere, some only because the merged bound is loose
    from conecull.datasets.generated import folding_sheet

    F, P = folding_sheet(n_triangles=2000, n_frames=24)
    col = conecull.SelfCollider(conecull.Mesh(F), method="nc")
    seen = set()
    for V in P[18:]:
        tr = col.dcd(V, trace=True).trace
        bvh = col.bvh_arrays()
        bad = tr.cone["node"][~tr.cone["bounded"]]
        for n, s in node_spreads(Normals(F, *tr.positions), bvh, bad).items():
            seen.add(check_spread(s, F, bvh["order"][bvh["begin"][n] : bvh["end"][n]], V))
    assert seen == {"beyond", "within"}  # both happen (frame 21: 18 within, 3 beyond)


def test_no_triangles_is_an_error():
    F, V = tri_mesh([with_normal((0, 0, 1))])
    with pytest.raises(ValueError, match="tris"):
        normal_spread(Normals(F, V), [])


@pytest.mark.parametrize("call,match", [  # found by review: a silent wrap-around, a truncation, raw numpy errors
    (lambda F, V: normal_spread(Normals(F, V), [-1]), r"tris: triangle id -1 is outside \[0, 2\)"),
    (lambda F, V: normal_spread(Normals(F, V), [2]), r"tris: triangle id 2 is outside \[0, 2\)"),
    (lambda F, V: normal_spread(Normals(F, V), [0.5]), r"tris: expected triangle ids \(integers"),
    (lambda F, V: normal_spread(Normals(F, V), [[0, 1]]), r"tris: expected triangle ids .* shape \(1, 2\)"),
    (lambda F, V: Normals(F, np.where(np.arange(V.size).reshape(V.shape) == 3, np.nan, V)), r"V0: non-finite coordinate nan at row 1, column 0"),
    (lambda F, V: Normals(F, V[:, :2]), r"V0: expected shape \(n, 3\), got \(\d+, 2\)"),
    (lambda F, V: Normals(F, V[:2]), r"faces: vertex index \d+ but V0 has 2 rows"),
    (lambda F, V: Normals(F, V, V[:-1]), r"V1: has \d+ rows but the mesh has \d+ vertices"),
    (lambda F, V: Normals(F + 0.5, V), r"faces: expected an integer array"),
])
def test_bad_input_is_named(call, match):
    F, V = tri_mesh([with_normal((0, 0, 1)), with_normal((0, 1, 0))])
    with pytest.raises(ValueError, match=match):
        call(F, V)


def test_the_filter_decides_subnormal_products_exactly():
    """From a review: one triangle with coordinates near 2^-127 and an axis l = (1, l1, l2) whose
    two products with its normal round to +2 and -1 units of 2^-1074 while their exact sum is
    negative; the relative bound rounded to 0, and +2^-1074 passed as a proven positive sign."""
    import math

    U = Fr(2) ** -1074
    rng = np.random.default_rng(0)
    F = np.array([[0, 1, 2]])
    made = 0
    while made < 20:
        s = 2.0**-127
        u0, w1, w2 = (float(x) * s for x in rng.uniform(1, 2, 3))
        m4, m3 = u0 * w1, u0 * w2
        if not (Fr(m4) > Fr(u0) * Fr(w1) and Fr(m3) <= Fr(u0) * Fr(w2)):
            continue
        l2 = float(Fr(3, 2) * U / Fr(m4))  # l2 m4 just above 1.5 units: rounds to 2
        while Fr(l2) * Fr(m4) <= Fr(3, 2) * U:
            l2 = math.nextafter(l2, math.inf)
        l1 = float(Fr(3, 2) * U / Fr(m3))  # l1 m3 just below 1.5 units: rounds to 1
        while Fr(l1) * Fr(m3) >= Fr(3, 2) * U:
            l1 = math.nextafter(l1, 0)
        l = np.array([1.0, l1, l2])
        V = np.array([[0, 0, 0], [u0, 0, 0], [0.5, w1, w2]], np.float64)
        got = int(exact_dot_signs(l, Normals(F, V), np.array([0]))[0])
        e = ex.dot(ex.fr3(l), exact_row(F, V, None, 0, 0))
        assert got == (e > 0) - (e < 0), (V, l)
        made += 1


def test_a_normal_that_rounds_to_zero_still_takes_part():
    """Its rounded cross product cancels to 0 while the exact one points along -z: it was left out
    of the search ("undecided" for the triangle alone)."""
    V = np.array([[2.0**58, 0, 0], [2, 1, 0], [7, 1, 0]])  # exact normal (0, 0, -5) times 2^58
    F = np.array([[0, 1, 2]])
    assert not np.cross(V[1] - V[0], V[2] - V[0]).any()
    assert check_spread(spread_of(F, V), F, [0], V) == "within"
    V2 = np.vstack([V, [[0, 0, 1], [1, 0, 1], [0, 1, 1]]])  # and with a triangle facing +z: beyond
    F2 = np.array([[0, 1, 2], [3, 4, 5]])
    assert check_spread(spread_of(F2, V2), F2, [0, 1], V2) == "beyond"


def test_ccd_a_zero_middle_control_vector_is_not_a_zero_area():
    # n(t) = ((1-t)^2 + t^2) (0, 0, 1) never vanishes, but 2 n1 = 0: no cone over the control
    # vectors (what CCD cones bound) passes, and the sentence says so, not "zero area"
    F = np.array([[0, 1, 2]])
    V0 = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    V1 = np.array([[0, 0, 0], [1, 1, 0], [-2, -1, 0]], float)
    sp = spread_of(F, V0, V1)
    assert check_spread(sp, F, [0], V0, V1) == "beyond" and sp.witness == ((0, 2),)
    words = sp.sentence(ccd=True)
    assert "control vector 2 n1 of triangle 0 is zero" in words and "zero area" not in words
    assert "what a CCD cone bounds" in words


def test_a_capped_search_leaves_the_rest_unsearched_deepest_first():
    """node_spreads(max_searches=k): k searches, deepest nodes first; a node holding a searched
    descendant's "beyond" witness still takes it; the rest are "unsearched", and say so."""
    from conecull.datasets.generated import folding_sheet

    F, P = folding_sheet(n_triangles=2000, n_frames=24)
    col = conecull.SelfCollider(conecull.Mesh(F), method="nc")
    col.dcd(P[0])
    tr = col.dcd(P[21], trace=True).trace  # 21 failed cones: 18 within, 3 beyond
    bvh = col.bvh_arrays()
    bad = tr.cone["node"][~tr.cone["bounded"]]
    normals = Normals(F, *tr.positions)
    full = node_spreads(normals, bvh, bad)
    capped = node_spreads(normals, bvh, bad, max_searches=5)
    searched = [n for n, s in capped.items() if s.analysed]
    assert len(searched) == 5
    assert min(bvh["depth"][searched]) >= max(bvh["depth"][[n for n, s in capped.items() if s.kind == "unsearched"]])
    for n, s in capped.items():
        assert s.kind in (full[n].kind, "unsearched")
        if s.kind == "unsearched":
            assert "was not searched" in s.sentence()
    assert any(s.kind == "unsearched" for s in capped.values())
