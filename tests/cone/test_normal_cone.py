"""The cone invariant of the issue, on every node of random meshes, in exact arithmetic:
whenever a node's cone is bounded (apex angle < pi), the exact normal of every triangle below
it satisfies n . axis > 0 for the very axis the contour test uses, and indeed
n . axis >= cos_bound |n| |axis|."""

from fractions import Fraction as Fr

import numpy as np
import pytest

import conecull
import exact_twin as ex
from conecull._core import ccd as CC
from conecull._core import cone as C
from meshgen_basic import random_meshes, wavy_sheet


def node_triangles(bvh, i):
    return bvh["order"][bvh["begin"][i] : bvh["end"][i]]


def check_invariant(F, V, leaf_size=1):
    col = conecull.SelfCollider(conecull.Mesh(F), method="nc", leaf_size=leaf_size)
    col.dcd(V)
    bvh, cones = col.bvh_arrays(), col.cone_arrays()
    normals = [ex.triangle_normal(*V[f]) for f in F]
    bounded = 0
    for i in range(len(bvh["begin"])):
        cb = cones["cos_bound"][i]
        if cb <= 0:
            continue
        bounded += 1
        a = ex.fr3(cones["axis"][i])
        aa = ex.dot(a, a)
        cb2 = Fr(float(cb)) ** 2
        sb2 = Fr(float(cones["sin_bound"][i])) ** 2
        for t in node_triangles(bvh, i):
            n = normals[t]
            na = ex.dot(n, a)
            assert na > 0, f"node {i}: triangle {t} has n.axis <= 0 under a bounded cone"
            assert na * na >= cb2 * ex.dot(n, n) * aa, f"node {i}: triangle {t} outside the cone"
            # sin(angle(n, axis)) <= sin_bound: the parent's merge relies on it as on cos_bound.
            nxa = ex.cross(n, a)
            assert ex.dot(nxa, nxa) <= sb2 * ex.dot(n, n) * aa, f"node {i}: triangle {t} beyond sin_bound"
    return bounded, len(bvh["begin"])


@pytest.mark.parametrize("name,F,V", list(random_meshes()), ids=[m[0] for m in random_meshes()])
@pytest.mark.parametrize("leaf_size", [1, 4])
def test_cone_invariant_every_node(name, F, V, leaf_size):
    bounded, total = check_invariant(F, V, leaf_size)
    if name == "sheet-smooth":
        assert bounded > total // 2  # the invariant was checked on many bounded nodes


def test_cone_invariant_slivers():
    """Near-degenerate triangles: vertices pushed to within a few ulps of the opposite edge."""
    F, V = wavy_sheet(10, 0.2, 0.0, 7)
    V = V.copy()
    rng = np.random.default_rng(3)
    for f in rng.choice(len(F), 20, replace=False):
        a, b, c = F[f]
        mid = 0.5 * (V[a] + V[b])
        V[c] = mid + rng.integers(-3, 4, 3) * np.spacing(np.abs(mid).max())
    check_invariant(F, V)


def test_zero_area_triangle_makes_ancestors_full():
    F, V = wavy_sheet(8, 0.0, 0.0, 0)  # flat: every cone would be tiny
    V = V.copy()
    t = 17
    a, b, c = F[t]
    V[c] = 0.5 * (V[a] + V[b])  # exact midpoint (grid coordinates are dyadic-friendly? check below)
    assert ex.triangle_normal(*V[F[t]]) == (0, 0, 0), "test setup: triangle must have exactly zero area"
    col = conecull.SelfCollider(conecull.Mesh(F), method="nc")
    col.dcd(V)
    bvh, cones = col.bvh_arrays(), col.cone_arrays()
    for i in range(len(bvh["begin"])):
        if t in set(node_triangles(bvh, i).tolist()):
            assert cones["cos_bound"][i] <= 0, f"ancestor {i} of a zero-area triangle has a bounded cone"
        elif bvh["end"][i] - bvh["begin"][i] == 1:
            assert cones["cos_bound"][i] > 0


@pytest.mark.parametrize("name,F,V", list(random_meshes()), ids=[m[0] for m in random_meshes()])
def test_sin_bound_does_not_drift(name, F, V):
    """sin_bound stays within rounding of sqrt(1 - cos_bound^2) on every bounded node (merge takes
    the smaller of the two bounds, normal_cone.hpp: with_sin_from_cos). Without it sin_bound grew
    level by level past 1 on rough sheets, and merges whose children fit in a cone narrower than a
    hemisphere came out full."""
    col = conecull.SelfCollider(conecull.Mesh(F), method="nc", leaf_size=1)
    col.dcd(V)
    cones = col.cone_arrays()
    cb, sb = cones["cos_bound"], cones["sin_bound"]
    ok = cb > 0
    assert ok.sum() > 10
    assert np.all(sb[ok] <= np.sqrt(1.0 - cb[ok] ** 2 + 4.4e-16) + 1e-12 + 1e-15)


def test_merges_stay_the_smallest_cones_level_after_level():
    """Merging merged cones: each level's cone is again the smallest holding both children, up to
    rounding, and its (cos, sin) pair stays consistent. Two 60 deg cones 25 deg apart give 72.5 deg;
    that cone and a copy turned 15 deg give 80 deg; that and a copy turned 16 deg, 88 deg. Before
    with_sin_from_cos (normal_cone.hpp) the sine bounds added up instead (sin 72.5 deg taken as 1.06),
    the second level came out at 80.8 deg and the third full."""
    def turned(ax, deg):
        c, s_ = np.cos(np.radians(deg)), np.sin(np.radians(deg))
        return ax @ np.array([[c, -s_, 0.0], [s_, c, 0.0], [0.0, 0.0, 1.0]]).T

    t = np.radians(60.0)
    a = np.array([[1.0, 0.0, 0.0]])
    one = np.ones(1)
    cone = C.merge_cones(a, np.cos(t) * one - 1e-15, np.sin(t) * one + 1e-15,
                         turned(a, 25.0), np.cos(t) * one - 1e-15, np.sin(t) * one + 1e-15)
    for turn, want in ((None, 72.5), (15.0, 80.0), (16.0, 88.0)):
        if turn is not None:
            ax, cb, sb = cone
            cone = C.merge_cones(ax, cb, sb, turned(ax, turn), cb, sb)
        ax, cb, sb = cone
        assert cb[0] > 0 and np.degrees(np.arccos(cb[0])) == pytest.approx(want, abs=1e-6), (turn, cb[0])
        assert np.sin(np.arccos(cb[0])) <= sb[0] <= np.sqrt(1.0 - cb[0] ** 2) + 1e-11


def test_merge_contains_both_cones():
    rng = np.random.default_rng(11)
    k = 500
    n1 = rng.standard_normal((k, 3))
    n2 = n1 + 0.3 * rng.standard_normal((k, 3))
    z = np.zeros((k, 3))
    ax1, cb1, sb1 = C.triangle_cone(z, np.tile([1.0, 0, 0], (k, 1)), np.cross(n1, [1.0, 0, 0]) * -1)
    ax2, cb2, sb2 = C.triangle_cone(z, np.tile([0, 1.0, 0], (k, 1)), np.cross(n2, [0, 1.0, 0]) * -1)
    # widen the children to test merging of wide cones too
    w = np.linspace(0, 0.5, k)
    cb1, sb1 = np.cos(np.arccos(cb1) + w) - 1e-9, np.sin(np.arccos(cb1) + w) + 1e-9
    ax, cb, sb = C.merge_cones(ax1, cb1, sb1, ax2, cb2, sb2)
    def theta(c, s_):  # the half-angle the (cos, sin) bounds certify
        return min(np.arccos(min(1.0, c)), np.arcsin(min(1.0, s_)))

    merged = 0
    for i in range(k):
        if cb[i] <= 0:
            continue
        merged += 1
        for axc, cbc, sbc in ((ax1[i], cb1[i], sb1[i]), (ax2[i], cb2[i], sb2[i])):
            phi = np.arctan2(np.linalg.norm(np.cross(ax[i], axc)), np.dot(ax[i], axc))  # accurate near 0 too
            assert phi + theta(cbc, sbc) <= theta(cb[i], sb[i]) + 1e-9
    assert merged > k // 4


def test_merge_is_the_smallest_cone_holding_both():
    """Wide merges give the smallest cone holding both children: half-angle
    max(theta_p, theta_q, (phi + theta_p + theta_q) / 2), not the bisector's
    phi / 2 + max(theta_p, theta_q); narrow ones (cos > 0.9) may keep the bisector's."""
    rng = np.random.default_rng(5)
    k = 2000
    a1 = rng.standard_normal((k, 3))
    a1 /= np.linalg.norm(a1, axis=1)[:, None]
    a2 = a1 + rng.uniform(0.0, 1.5, (k, 1)) * rng.standard_normal((k, 3))
    a2 /= np.linalg.norm(a2, axis=1)[:, None]
    t1, t2 = rng.uniform(0.0, 0.8, k), rng.uniform(0.0, 0.8, k)
    ax, cb, sb = C.merge_cones(a1, np.cos(t1), np.sin(t1), a2, np.cos(t2), np.sin(t2))
    phi = np.arctan2(np.linalg.norm(np.cross(a1, a2), axis=1), np.einsum("ij,ij->i", a1, a2))
    smallest = np.maximum(np.maximum(t1, t2), 0.5 * (phi + t1 + t2))
    bisector = 0.5 * phi + np.maximum(t1, t2)
    theta = np.arccos(np.clip(cb, -1, 1))
    wide = (smallest > np.arccos(0.9) + 1e-6) & (smallest < 0.5 * np.pi - 1e-6)
    assert np.all(cb[wide] > 0), "a cone narrower than a hemisphere merged into a full one"
    assert np.allclose(theta[wide], smallest[wide], atol=1e-9)
    assert np.sum(bisector[wide] - smallest[wide] > 0.01) > k // 10  # cases where the bisector is wider
    full = smallest > 0.5 * np.pi + 1e-6
    assert np.all(cb[full] <= 0)
    narrow = smallest < np.arccos(0.9) - 1e-6
    assert np.all(theta[narrow] <= bisector[narrow] + 1e-9)


@pytest.mark.parametrize("mode", ["same", "1e-12 apart", "nearly opposite", "random"])
def test_merge_holds_both_children_in_extreme_cases(mode):
    """Whatever the merge returns (smallest cone, a child's, or the bisector's) holds both
    children: identical axes, axes 1e-12 apart, nearly opposite ones, half-angles from 0 to
    within 1e-4 of pi/2 (children's bounds widened by 1e-15 as the core's are)."""
    rng = np.random.default_rng(7)
    k = 4000
    a1 = rng.standard_normal((k, 3))
    a1 /= np.linalg.norm(a1, axis=1)[:, None]
    shift = {"same": 0.0, "1e-12 apart": 1e-12, "nearly opposite": 0.05, "random": 1.0}[mode]
    a2 = (-a1 if mode == "nearly opposite" else a1) + shift * rng.uniform(0, 3, (k, 1)) * rng.standard_normal((k, 3))
    a2 /= np.linalg.norm(a2, axis=1)[:, None]
    scale = np.array([0.0, 1e-15, 1e-8, 0.3, 1.0, 1.5, 1.5707])
    t1, t2 = (rng.choice(scale, k) * rng.uniform(0, 1, k) ** rng.integers(0, 2, k) for _ in range(2))
    ax, cb, sb = C.merge_cones(a1, np.cos(t1) - 1e-15, np.sin(t1) + 1e-15, a2, np.cos(t2) - 1e-15, np.sin(t2) + 1e-15)
    ok = cb > 0
    assert ok.sum() > k // 4 or mode == "nearly opposite"
    theta = np.minimum(np.arccos(np.clip(cb, -1, 1)), np.arcsin(np.clip(sb, 0, 1)))
    for a, t in ((a1, t1), (a2, t2)):
        phi = np.arctan2(np.linalg.norm(np.cross(ax, a), axis=1), np.einsum("ij,ij->i", ax, a))
        assert not np.any(ok & (phi + t > theta + 1e-11))


def test_merge_of_nearly_opposite_narrow_cones_keeps_both_bounds():
    """Axes pi - delta apart (delta from 1e-9 to 1e-3), half-angles below delta / 4: the merged
    cone is bounded, and its (cos, sin) pair must still bound the half-angle psi it needs to hold
    both children: cos_bound <= cos(psi) and sin_bound >= sin(psi). psi is computed from exact
    dot products (fractions) of the returned axis with the children's. With the sines taken from
    the nearly cancelling sum of the axes, sin_bound fell short of sin(psi) by up to 8e-9."""
    rng = np.random.default_rng(3)
    k = 300
    p = rng.standard_normal((k, 3))
    p /= np.linalg.norm(p, axis=1)[:, None]
    perp = np.cross(p, rng.standard_normal((k, 3)))
    perp /= np.linalg.norm(perp, axis=1)[:, None]
    delta = 10.0 ** rng.uniform(-9, -3, k)
    q = -p + delta[:, None] * perp
    q /= np.linalg.norm(q, axis=1)[:, None]
    tp, tq = delta * rng.uniform(0, 0.25, k), delta * rng.uniform(0, 0.25, k)
    cp_, sp_, cq_, sq_ = np.cos(tp), np.sin(tp) + 1e-18, np.cos(tq), np.sin(tq) + 1e-18
    ax, cb, sb = C.merge_cones(p, cp_, sp_, q, cq_, sq_)
    assert (cb > 0).sum() > k // 2
    for i in np.flatnonzero(cb > 0):
        a = ax[i]
        na = float(sum(Fr(x) ** 2 for x in a)) ** 0.5
        cos_psi, sin_psi = 1.0, 0.0
        for c, cc, sc in ((p[i], cp_[i], sp_[i]), (q[i], cq_[i], sq_[i])):
            cos_ac = float(sum(Fr(x) * Fr(y) for x, y in zip(a, c))) / (na * np.linalg.norm(c))
            sin_ac = np.sqrt(max(0.0, 1.0 - cos_ac * cos_ac))
            cos_need, sin_need = cos_ac * cc - sin_ac * sc, sin_ac * cc + cos_ac * sc  # angle(a, c) + theta_c
            if cos_need < cos_psi:
                cos_psi, sin_psi = cos_need, sin_need
        assert cb[i] <= cos_psi + 1e-15, (i, cb[i], cos_psi)
        assert sb[i] >= sin_psi - 1e-15, (i, delta[i], sb[i], sin_psi)


def _fold_cones_like_the_refit(triangle_cones, bvh):
    """Every node's cone from the scalar bindings: the triangles' cones (axis, cos, sin) merged by
    merge_cones in the refit's order (a leaf's triangles in order, an inner node from its left then
    right child)."""
    ax, cb, sb = triangle_cones
    n = len(bvh["begin"])
    out = [None] * n
    for i in reversed(range(n)):
        if bvh["right"][i] < 0:
            tris = bvh["order"][bvh["begin"][i] : bvh["end"][i]]
            c = (ax[tris[:1]], cb[tris[:1]], sb[tris[:1]])
            for t in tris[1:]:
                c = C.merge_cones(*c, ax[[t]], cb[[t]], sb[[t]])
        else:
            c = C.merge_cones(*out[i + 1], *out[bvh["right"][i]])
        out[i] = c
    return (np.concatenate([c[k] for c in out]) for k in range(3))


@pytest.mark.parametrize("query", ["dcd", "ccd"])
@pytest.mark.parametrize("leaf_size", [1, 2, 3])
@pytest.mark.parametrize("threads", [1, 2])
def test_refit_cones_equal_the_scalar_cones_bit_for_bit(query, leaf_size, threads):
    """The refits with cones compute their leaves' triangle cones in batches (cones_around, two at
    a time; CCD: the control vectors' cones); every node's cone must be bit for bit the one of the
    scalar triangle_cone (triangle_cone_ccd) and merge, on cones of every kind: zero-area
    triangles (full), slivers whose normal is not resolved (r >= 1/2: full), normals with
    components below the flush threshold (set to 0), and ordinary ones; on a mesh large enough for
    the parallel refit."""
    F, V = wavy_sheet(60, 0.2, 0.01, 4)
    V = V.copy()
    rng = np.random.default_rng(1)
    picks = rng.choice(len(F), 60, replace=False)
    for f in picks[:20]:  # zero area: c on a
        a, b, c = F[f]
        V[c] = V[a]
    for f in picks[20:40]:  # slivers: c within a few ulps of the midpoint of a and b
        a, b, c = F[f]
        mid = 0.5 * (V[a] + V[b])
        V[c] = mid + rng.integers(-2, 3, 3) * np.spacing(np.abs(mid).max())
    for f in picks[40:]:  # a normal along z up to 1e-20 (x and y components flushed to 0)
        a, b, c = F[f]
        V[b] = V[a] + [1.0, 0.0, 1e-20]
        V[c] = V[a] + [0.0, 1.0, 0.0]
    col = conecull.SelfCollider(conecull.Mesh(F), method="nc", leaf_size=leaf_size, threads=threads)
    P = V[F]
    tri = C.triangle_cone(P[:, 0], P[:, 1], P[:, 2])
    if query == "dcd":
        col.dcd(V)
        cones = tri
    else:  # a translation keeps the special triangles special at both ends
        V1 = V + [0.01, -0.02, 0.005]
        col.ccd(V, V1)
        Q = V1[F]
        cones = CC.triangle_cone_ccd(P[:, 0], P[:, 1], P[:, 2], Q[:, 0], Q[:, 1], Q[:, 2])
    bvh, got = col.bvh_arrays(), col.cone_arrays()
    assert len(bvh["begin"]) >= 4096  # the parallel refit's threshold
    ax, cb, sb = _fold_cones_like_the_refit(cones, bvh)
    assert got["axis"].tobytes() == ax.tobytes()
    assert got["cos_bound"].tobytes() == cb.tobytes()
    assert got["sin_bound"].tobytes() == sb.tobytes()
    tax, tcb, _ = tri
    assert (tcb <= 0).sum() >= 30 and ((tax[:, :2] == 0).all(axis=1) & (tcb > 0)).sum() >= 20  # the kinds occurred
