"""Per-node contours and the unprojected contour test (Alg. 1).

- Every eligible node's loop is exactly the boundary of its triangle set (half-edges whose
  reverse is not in the node), as one simple cycle; ineligible nodes are ineligible for the
  right reason.
- Alg. 1 in C++ returns the same verdict, reason and edge as an exact twin evaluated on the
  printed definitions (fractions).
- Soundness: whenever it passes, the projection of the loop along l is a simple polygon
  (checked by exact brute-force segment intersection).
"""

from fractions import Fraction as Fr

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import conecull
import exact_twin as ex
from conecull._core import contour as CT
from conecull.datasets.generated import grid_sheet
from meshgen_basic import random_meshes

STATUS = {0: "simple", 1: "nonmanifold", 2: "inconsistent", 3: "disconnected", 4: "closed", 5: "nonsimple", 6: "multiloop"}


def boundary_halfedges(F, tris):
    he = set()
    for t in tris:
        a, b, c = (int(x) for x in F[t])
        he.update([(a, b), (b, c), (c, a)])
    return {e for e in he if (e[1], e[0]) not in he}


def check_contours(F, leaf_size=1, V=None):
    mesh = conecull.Mesh(F)
    col = conecull.SelfCollider(mesh, method="nc", leaf_size=leaf_size)
    col.dcd(np.zeros((mesh.n_vertices, 3)) if V is None else V)
    bvh, ct = col.bvh_arrays(), col.contour_arrays()
    counts = {}
    for i in range(len(bvh["begin"])):
        tris = bvh["order"][bvh["begin"][i] : bvh["end"][i]]
        st_ = STATUS[int(ct["status"][i])]
        counts[st_] = counts.get(st_, 0) + 1
        loop = ct["vertices"][ct["offsets"][i] : ct["offsets"][i + 1]]
        if st_ == "simple":
            assert len(set(loop.tolist())) == len(loop) >= 3
            edges = {(int(loop[k]), int(loop[(k + 1) % len(loop)])) for k in range(len(loop))}
            assert edges == boundary_halfedges(F, tris), f"node {i}: loop is not the node's boundary"
        else:
            assert len(loop) == 0
    return counts


def test_grid_nodes_are_disks():
    F, _ = grid_sheet(9, 9)
    counts = check_contours(F)
    # A median-split grid: almost all nodes are disks.
    assert counts.get("simple", 0) >= 0.9 * sum(counts.values())


@pytest.mark.parametrize("leaf_size", [1, 3])
@pytest.mark.parametrize("name,F,V", list(random_meshes()), ids=[m[0] for m in random_meshes()])
def test_loops_are_node_boundaries(name, F, V, leaf_size):
    counts = check_contours(F, leaf_size, V)
    if name.startswith("sphere"):
        assert counts.get("closed", 0) >= 1  # the root of a closed surface has no boundary


def test_hole_gives_multiple_loops_and_fins_are_nonmanifold():
    F, V = grid_sheet(8, 8)
    keep = np.ones(len(F), bool)
    keep[[48, 49, 50, 51]] = False  # two interior quads of row 3: a hole
    counts = check_contours(F[keep], V=V)
    assert counts.get("multiloop", 0) >= 1
    # A fin: a third face on an interior edge makes every node holding its edge's faces ineligible.
    a, b = (int(x) for x in F[30][:2])
    fin = np.vstack([F, [[a, b, len(V)]]])
    counts = check_contours(fin, V=np.vstack([V, [[0.5, 0.5, 1.0]]]))
    assert counts.get("nonmanifold", 0) >= 1
    # Inconsistent orientation: flip one face of the grid.
    flipped = F.copy()
    flipped[30] = flipped[30][::-1]
    mesh = conecull.Mesh(flipped)
    assert len(mesh.nonmanifold_edges) == 3  # its three interior edges are traversed the same way twice
    counts = check_contours(flipped, V=V)
    assert counts.get("nonmanifold", 0) >= 1


def projected_simple(points, l):
    """Exact check that the polygon projected along l is simple."""
    l = ex.fr3(l)
    r = ex.fr3(ex.ray_direction(tuple(float(x) for x in l)))
    w = ex.cross(l, r)
    P = [(ex.dot(ex.fr3(p), r), ex.dot(ex.fr3(p), w)) for p in points]
    n = len(P)

    def orient(a, b, c):
        return ex.sgn((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))

    def on_seg(a, b, c):
        return min(a[0], b[0]) <= c[0] <= max(a[0], b[0]) and min(a[1], b[1]) <= c[1] <= max(a[1], b[1])

    def meet(a, b, c, d):
        d1, d2, d3, d4 = orient(c, d, a), orient(c, d, b), orient(a, b, c), orient(a, b, d)
        if d1 * d2 < 0 and d3 * d4 < 0:
            return True
        return (d1 == 0 and on_seg(c, d, a)) or (d2 == 0 and on_seg(c, d, b)) or (d3 == 0 and on_seg(a, b, c)) or (d4 == 0 and on_seg(a, b, d))

    if len(set(P)) != n:
        return False
    for i in range(n):
        for j in range(i + 1, n):
            a, b, c, d = P[i], P[(i + 1) % n], P[j], P[(j + 1) % n]
            if j == i + 1 or (i == 0 and j == n - 1):
                shared = b if j == i + 1 else a
                other = d if j == i + 1 else c
                # adjacent edges meet only at their shared vertex: not collinear-overlapping
                if orient(a, b, other) == 0 and on_seg(a, b, other) or orient(c, d, a if j == i + 1 else b) == 0 and on_seg(c, d, a if j == i + 1 else b):
                    return False
                continue
            if meet(a, b, c, d):
                return False
    return True


coord = st.floats(min_value=-2.0, max_value=2.0, allow_nan=False).map(lambda x: 0.0 if abs(x) < 2.0**-60 else x)


@st.composite
def loops(draw):
    """Loops around an axis: star-shaped, winding twice, zig-zag, or with exact degeneracies."""
    n = draw(st.integers(3, 12))
    kind = draw(st.sampled_from(["star", "star", "twice", "wild", "grid"]))
    l = np.array([draw(coord), draw(coord), draw(coord)])
    if np.linalg.norm(l) < 1e-3:
        l = np.array([0.0, 1.0, 0.0]) if draw(st.booleans()) else np.array([0.3, 0.0, -0.2])
    l = l / np.linalg.norm(l)
    l[np.abs(l) < 2.0**-60] = 0.0
    u = np.cross(l, [0.3, 0.7, 0.1])
    u /= np.linalg.norm(u)
    w = np.cross(l, u)
    turns = 2 if kind == "twice" else 1
    ang = np.sort(np.array([draw(st.floats(0, 2 * np.pi)) for _ in range(n)]))
    if kind == "wild":
        ang = np.array([draw(st.floats(0, 2 * np.pi)) for _ in range(n)])
    rad = np.array([draw(st.floats(0.2, 1.0)) for _ in range(n)])
    h = np.array([draw(st.floats(-1.0, 1.0)) for _ in range(n)])
    pts = rad[:, None] * (np.cos(turns * ang)[:, None] * u + np.sin(turns * ang)[:, None] * w) + h[:, None] * l
    if kind == "grid":  # integer points with an axis-aligned l: many exact zeros
        pts = np.round(pts * 4)
        l = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]][draw(st.integers(0, 2))])
    pts[np.abs(pts) < 2.0**-100] = 0.0  # cancellations leave values far below 2^-128 (the core refuses them)
    return pts, l


@settings(max_examples=500, deadline=None)
@given(loops())
def test_contour_test_matches_exact_twin_and_is_sound(loop):
    pts, l = loop
    P = [tuple(p) for p in pts]
    ids = np.arange(len(pts), dtype=np.int32)
    # Alg. 1's kernel point (the mean): the twin runs the printed Alg. 1 with the ray the core
    # ended up using ...
    first = CT.contour_test(ids, pts, l, o=np.array(ex.float_mean(P)))
    passed, reason, edge = ex.contour_test(P, tuple(l), r=first["ray"])
    assert (first["passed"], first["reason"]) == (passed, reason)
    if reason in (1, 2, 3, 4):
        assert first["edge"] == edge
    # ... and the core given the paper's ray agrees with the twin on the paper's ray.
    paper_r = np.array(ex.ray_direction(tuple(l)))
    res_paper = CT.contour_test(ids, pts, l, paper_r)
    assert (res_paper["passed"], res_paper["reason"]) == ex.contour_test(P, tuple(l))[:2]
    # The core's full test: the mean, then (after a kernel failure) the clipped kernel's point.
    res = CT.contour_test(ids, pts, l)
    o2 = ex.retry_kernel(reason, edge, P, tuple(l))
    if o2 is None:
        assert (res["passed"], res["reason"], res["kernel"]) == (first["passed"], first["reason"], first["kernel"])
    else:
        assert res["kernel"] == o2
        assert (res["passed"], res["reason"]) == ex.contour_test(P, tuple(l), o=o2, r=res["ray"])[:2]
    for v in (first, res):
        if v["passed"]:
            assert projected_simple(pts, l), "Alg. 1 passed a loop whose projection is not simple"


def test_kernel_retry_passes_a_star_whose_mean_is_outside_its_kernel():
    """A star around the origin with a long thin spike: the mean lies up in the spike, outside
    the kernel, and Alg. 1 with the mean fails; the retry's point (the clipped kernel's) passes,
    and the loop is indeed simple."""
    l = np.array([0.0, 0.0, 1.0])
    pts = np.array([[1, 0, 0], [0.7, 0.7, 0], [0.1, 0.9, 0], [0.05, 6, 0], [0, 6.2, 0], [-0.05, 6, 0], [-0.1, 0.9, 0],
                    [-0.7, 0.7, 0], [-1, 0, 0], [-0.7, -0.7, 0], [0, -1, 0], [0.7, -0.7, 0]], float)
    ids = np.arange(len(pts), dtype=np.int32)
    P = [tuple(p) for p in pts]
    first = CT.contour_test(ids, pts, l, o=np.array(ex.float_mean(P)))
    assert not first["passed"] and first["reason"] == 2
    res = CT.contour_test(ids, pts, l)
    status, o, visited = ex.clipped_kernel_candidate(P, tuple(l), first["edge"])
    assert status == "found" and visited == len(pts)
    assert res["passed"] and res["kernel"] == o
    assert res["edges_visited"] == first["edges_visited"] + visited + len(pts)  # both attempts and the clipping
    assert projected_simple(pts, l)
    with pytest.raises(ValueError, match="o: expected shape"):
        CT.contour_test(ids, pts, l, o=np.zeros(2))


def test_kernel_point_lies_in_the_predicates_domain(monkeypatch):
    """The retry's kernel point enters the exact predicates like a vertex, so its coordinates must
    be 0 or of magnitude >= 2^-128 (below, expansion products could underflow). The spiked star at
    scale 2^-80, moved so that its clipped kernel point sits at the origin: recomputed, that point
    comes out with a coordinate of ~1e-40. The core sets it to 0 (any o is valid), as the twin
    does, and the test still passes."""
    l = np.array([0.0, 0.0, 1.0])
    star = np.array([[1, 0, 0], [0.7, 0.7, 0], [0.1, 0.9, 0], [0.05, 6, 0], [0, 6.2, 0], [-0.05, 6, 0],
                     [-0.1, 0.9, 0], [-0.7, 0.7, 0], [-1, 0, 0], [-0.7, -0.7, 0], [0, -1, 0], [0.7, -0.7, 0]])
    rng = np.random.default_rng(0)
    pts = star * 2.0**-80 + np.array([rng.uniform(-1, 1) * 2.0**-78, rng.uniform(-1, 1) * 2.0**-78, 0.0])
    ids = np.arange(len(pts), dtype=np.int32)
    start = CT.contour_test(ids, pts, l, o=np.array(ex.float_mean([tuple(p) for p in pts])))["edge"]
    o = ex.clipped_kernel_candidate([tuple(p) for p in pts], tuple(l), start)[1]
    pts = pts - np.array([o[0], o[1], 0.0])
    pts[np.abs(pts) < 2.0**-128] = 0.0  # vertices must be in the domain too
    P = [tuple(p) for p in pts]
    with monkeypatch.context() as m:
        m.setattr(ex, "_predicate_domain", lambda o: o)
        raw = ex.clipped_kernel_candidate(P, tuple(l), start)[1]
    assert any(0 < abs(x) < 2.0**-128 for x in raw), raw  # the case this test is about
    res = CT.contour_test(ids, pts, l)  # the mean lies in the spike: the retry's point decides
    assert ex.contour_test(P, tuple(l), o=ex.float_mean(P), r=res["ray"])[1:] == (2, start)  # where the clipping starts
    assert all(x == 0 or abs(x) >= 2.0**-128 for x in res["kernel"]), res["kernel"]
    assert res["kernel"] == ex.clipped_kernel_candidate(P, tuple(l), start)[1]
    assert res["passed"] and ex.contour_test(P, tuple(l), o=res["kernel"], r=res["ray"])[0]


def _sideways_spike():
    """The spiked star turned to point along x: the mean lies out in the spike (x = 1.58), and
    the line the [SPO10] search scans for l = z (the frame's u = y: the line x = mean x) runs
    through the spike, where no point sees the whole star."""
    spike = [[0.9, -0.1, 0], [6, -0.05, 0], [6.2, 0, 0], [6, 0.05, 0], [0.9, 0.1, 0]]
    disc = [[0.7, 0.7, 0], [0, 1, 0], [-0.7, 0.7, 0], [-1, 0, 0], [-0.7, -0.7, 0], [0, -1, 0], [0.7, -0.7, 0]]
    return np.array(spike + disc, float)


def test_kernel_retry_finds_a_kernel_off_the_line_search():
    """The clipped kernel finds the kernel point [SPO10]'s line search misses: on the sideways
    spike, the mean fails, the line search (sct) finds no kernel point on its line, and the full
    test passes with the clipped kernel's point, which is in the exact kernel."""
    l = np.array([0.0, 0.0, 1.0])
    pts = _sideways_spike()
    ids = np.arange(len(pts), dtype=np.int32)
    P = [tuple(p) for p in pts]
    area = ex.kernel_area(P, tuple(l))[0]
    assert area > 0, "the loop is star-shaped"
    first = CT.contour_test(ids, pts, l, o=np.array(ex.float_mean(P)))
    assert first["reason"] == 2
    assert ex.sct_candidate(P, tuple(l))[0] is None
    assert CT.sct_contour_test(ids, pts, l)["reason"] == 6  # no kernel point on the search line
    res = CT.contour_test(ids, pts, l)
    assert res["passed"] and res["kernel"] == ex.clipped_kernel_candidate(P, tuple(l), first["edge"])[1]
    assert ex.contour_test(P, tuple(l), o=res["kernel"], r=res["ray"])[0]
    assert projected_simple(pts, l)


def test_kernel_retry_falls_back_to_the_line_search_beyond_64_corners():
    """A finely divided disk (1200 vertices) with a long spike along +y (1500 vertices a side):
    the mean lies out in the spike, and the kernel (a strip inside the disk) is bounded by over
    a hundred disk edges, so the clipping gives up at 64 corners; the line search through the
    mean finds the strip and the test passes from its point. Counts: both attempts, the clipping
    up to where it gave up, and the search's pass."""
    s, c = np.sin(0.3), np.cos(0.3)
    xs = np.linspace(c, 6.0, 1500)
    ang = np.linspace(0.3, 2 * np.pi - 0.3, 1200)[1:-1]
    flat = [(x, -s) for x in xs] + [(x, s) for x in xs[::-1]] + list(zip(np.cos(ang), np.sin(ang)))
    pts = np.array([(-y, x, 0.0) for x, y in flat])  # turned: the spike points along +y
    l = np.array([0.0, 0.0, 1.0])
    ids = np.arange(len(pts), dtype=np.int32)
    P = [tuple(p) for p in pts]
    first = CT.contour_test(ids, pts, l, o=np.array(ex.float_mean(P)))
    assert first["reason"] == 2
    status, _, clipped = ex.clipped_kernel_candidate(P, tuple(l), first["edge"])
    assert status == "too_many_corners"
    res = CT.contour_test(ids, pts, l)
    assert res["passed"] and res["kernel"] == ex.sct_candidate(P, tuple(l))[0] == ex.kernel_candidate(P, tuple(l), first["edge"])
    assert res["edges_visited"] == first["edges_visited"] + clipped + len(pts) + len(pts)


@settings(max_examples=300, deadline=None)
@given(loops())
def test_contour_test_passes_wherever_the_kernel_has_room(loop):
    """Against the exact kernel (the intersection of the edges' inner half-planes): whenever the
    projected loop is simple, its kernel a region of some size (a 1e-6 share of the loop's
    bounding box) and no edge projects to almost a point (shorter than 1e-6 of the box's
    diagonal: an edge nearly along l, whose projected line floats do not resolve), the core's
    test passes (or a ray passed exactly through a vertex twice); wherever the intersection is
    empty, it fails. (A loop winding twice, a pentagram, has a non-empty intersection too;
    there the ray test fails it.)"""
    pts, l = loop
    P = [tuple(p) for p in pts]
    ids = np.arange(len(pts), dtype=np.int32)
    area, box, short2 = ex.kernel_area(P, tuple(l))
    res = CT.contour_test(ids, pts, l)
    if box > 0 and area > box * Fr(1, 10**6) and short2 > Fr(1, 10**12) and projected_simple(pts, l):
        assert res["passed"] or res["reason"] == 3, (res, pts.tolist(), l.tolist(), float(area / box))
    if area == 0:
        assert not res["passed"]


def test_star_and_twice_winding_examples():
    l = np.array([0.0, 0.0, 1.0])
    k = 8
    ang = 2 * np.pi * np.arange(k) / k
    star = np.c_[np.cos(ang + 0.2), np.sin(ang + 0.2), 0.1 * np.sin(3 * ang)]
    assert CT.contour_test(np.arange(k, dtype=np.int32), star, l)["passed"]
    twice = np.c_[np.cos(2 * ang + 0.1), np.sin(2 * ang + 0.1), np.linspace(0, 1, k)]
    r = CT.contour_test(np.arange(k, dtype=np.int32), twice, l)
    assert not r["passed"] and r["reason"] == 4  # winds twice: the ray crosses it twice
    # Reversed orientation still passes (the kernel sign is consistent, just negative).
    assert CT.contour_test(np.arange(k, dtype=np.int32)[::-1].copy(), star, l)["passed"]
    # A vertex exactly on the line of the paper's ray (even behind o) is "cannot determine"
    # (Alg. 1 l. 24); the core's generic ray directions avoid the grid line and pass.
    on_line = np.array([[2.0, 0, 0], [0, 2.0, 0], [-2.0, 0, 0], [0, -2.0, 0]])  # o = 0 exactly
    r = CT.contour_test(np.arange(4, dtype=np.int32), on_line, l, np.array(ex.ray_direction(tuple(l))))
    assert not r["passed"] and r["reason"] == 3
    assert CT.contour_test(np.arange(4, dtype=np.int32), on_line, l)["passed"]
