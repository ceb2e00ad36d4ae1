"""explain_node refuses what it cannot explain, naming the argument: a result of another
collider, an untraced result, a bad node id, a collider without a BVH yet."""

import dataclasses

import numpy as np
import pytest

import conecull
from conecull.datasets.generated import folding_sheet
from conecull.viz.explain import explain_node


def traced(n_triangles, method="nc"):
    F, P = folding_sheet(n_triangles, 4)
    col = conecull.SelfCollider(conecull.Mesh(F), method=method)
    col.dcd(P[0])
    return col, col.dcd(P[-1], trace=True), P


@pytest.fixture(scope="module")
def sheets():
    return traced(200), traced(2000), traced(160), traced(200, method="aabb")


def test_explains_its_own_result(sheets):
    col, res, _ = sheets[0]
    assert explain_node(col, res, 0).startswith("node 0: depth 0")


@pytest.mark.parametrize("other", [1, 2])
def test_refuses_a_result_of_another_mesh(sheets, other):
    col, res, _ = sheets[0]
    col2, res2, _ = sheets[other]
    with pytest.raises(ValueError, match="res: comes from another collider"):
        explain_node(col, res2, 0)
    with pytest.raises(ValueError, match="res: comes from another collider"):
        explain_node(col2, res, 0)
    with pytest.raises(ValueError, match="res: was traced on another BVH than col's"):  # by its BVH's fingerprint
        explain_node(col, dataclasses.replace(res2, collider=None), 0)
    res2.trace.bvh = None  # a trace without one (built by hand) is judged by what it shows
    try:
        with pytest.raises(ValueError, match="res: comes from another collider"):
            explain_node(col, dataclasses.replace(res2, collider=None), 0)
    finally:
        res2.trace.bvh = col2.bvh_digest()


def test_refuses_a_result_of_another_method(sheets):
    col, res, _ = sheets[0]
    with pytest.raises(ValueError, match="res: comes from another collider"):
        explain_node(col, sheets[3][1], 0)
    # a result without its collider (built by hand) is judged by what its trace shows
    with pytest.raises(ValueError, match="res: comes from a query with method 'aabb', but col uses 'nc'"):
        explain_node(col, dataclasses.replace(sheets[3][1], collider=None), 0)


def test_refuses_a_result_of_a_twin_collider(sheets):
    """Same mesh, same method, same poses: the trace cannot tell the two apart, the result can."""
    col, res, P = sheets[0]
    twin = conecull.SelfCollider(col.mesh, method=col.method)
    twin.dcd(P[0])
    assert res.collider() is col
    with pytest.raises(ValueError, match="res: comes from another collider"):
        explain_node(twin, res, 0)
    assert explain_node(twin, dataclasses.replace(res, collider=None), 0) == explain_node(col, res, 0)


def test_an_unpickled_result_needs_a_collider_with_its_bvh(sheets):
    """A pickled result loses its collider; its trace keeps the BVH's fingerprint. A collider of
    the same mesh and method whose BVH was built from another pose has the same depth and node
    count, so only the fingerprint tells that its node ids name other nodes (found by review:
    25 of 100 explanations differed, silently); one built from the same first pose explains it
    exactly as the original does."""
    import pickle

    col, res, P = sheets[0]
    back = pickle.loads(pickle.dumps(res))
    assert back.collider() is None and back.trace.bvh == col.bvh_digest() is not None
    other = conecull.SelfCollider(col.mesh, method=col.method)
    other.dcd(np.ascontiguousarray(P[-1][:, ::-1]))  # another first pose: another BVH
    assert other.bvh_digest() != col.bvh_digest()
    assert len(other.bvh_arrays()["begin"]) == len(col.bvh_arrays()["begin"])
    with pytest.raises(ValueError, match="res: was traced on another BVH than col's"):
        explain_node(other, back, 0)
    twin = conecull.SelfCollider(col.mesh, method=col.method)
    twin.dcd(P[0])
    assert twin.bvh_digest() == col.bvh_digest()
    last = len(col.bvh_arrays()["begin"]) - 1
    for node in (0, last // 2, last):
        assert explain_node(twin, back, node) == explain_node(col, res, node)


def test_refuses_an_untraced_result(sheets):
    col, _, P = sheets[0]
    with pytest.raises(ValueError, match=r"res: the query was not traced; run it with trace=True"):
        explain_node(col, col.dcd(P[-1]), 0)


@pytest.mark.parametrize("node,match", [  # {last}: the BVH's last node id
    (1.5, r"node: expected an integer node id in 0\.\.{last}, got 1\.5"),
    ("3", r"node: expected an integer node id in 0\.\.{last}, got '3'"),
    ("last+1", r"^node: {last+1} is out of range: the BVH has nodes 0\.\.{last}"),
    (-1, r"^node: -1 is out of range"),
])
def test_names_a_bad_node(sheets, node, match):
    col, res, _ = sheets[0]
    last = len(col.bvh_arrays()["begin"]) - 1
    assert last > 0
    if node == "last+1":
        node = last + 1
    match = match.replace("{last+1}", str(last + 1)).replace("{last}", str(last))
    with pytest.raises(ValueError, match=match):  # `node`, the Python name: the CLI says --node
        explain_node(col, res, node)


def test_before_any_query(sheets):
    col, res, _ = sheets[0]
    fresh = conecull.SelfCollider(col.mesh)
    with pytest.raises(ValueError, match=r"col: has no BVH yet .*run col\.dcd\(V\) first"):
        explain_node(fresh, res, 0)


# --- triage: which triangles collide, and why no node holding them was culled -----------------

from conecull.datasets.inputs import load_sequence  # noqa: E402
from conecull.viz.explain import (collision_sentences, explain_face, explain_pair, node_verdict,  # noqa: E402
                                  path_to_root, smallest_common_nodes)


def _holds(bvh, node, faces):
    inside = set(bvh["order"][bvh["begin"][node] : bvh["end"][node]].tolist())
    return all(f in inside for f in faces)


def test_smallest_common_node_against_a_walk(sheets):
    """The node holds both faces and neither of its children does (checked by listing the
    nodes' triangles), for random pairs and for a face with itself (its leaf)."""
    col, _, _ = sheets[1]
    bvh = col.bvh_arrays()
    rng = np.random.default_rng(1)
    a, b = rng.integers(0, col.mesh.n_faces, 300), rng.integers(0, col.mesh.n_faces, 300)
    a[:20] = b[:20]
    for i, j, n in zip(a, b, smallest_common_nodes(bvh, a, b)):
        assert _holds(bvh, n, (i, j))
        if bvh["right"][n] >= 0:
            assert not _holds(bvh, bvh["left"][n], (i, j)) and not _holds(bvh, bvh["right"][n], (i, j))
        elif i == j:
            assert bvh["right"][n] < 0


def _scenes():
    F, P = load_sequence("fold")
    G, Q = load_sequence("crumple")
    R, S = load_sequence("roll")
    return [("fold", F, P, (28, 29)), ("crumple", G, Q, (24, 29)), ("roll", R, S, (15, 29))]


@pytest.mark.parametrize("method", ["nc", "nc+front", "sct", "cbc", "aabb", "aabb+front"])
def test_every_dcd_collision_is_explained_by_nodes_not_culled(method):
    """Each colliding pair's sentence names the smallest node holding both triangles, and no node
    on its path to the root was culled by the trace's own verdicts (culling one would have lost
    the pair): a check of the trace against the result, pair by pair."""
    for name, F, P, ks in _scenes():
        col = conecull.SelfCollider(conecull.Mesh(F), method=method)
        col.dcd(P[0])
        for k in ks:
            res = col.dcd(P[k], trace=True)
            assert len(res.pairs), (name, k)
            bvh = col.bvh_arrays()
            nodes = smallest_common_nodes(bvh, res.pairs[:, 0], res.pairs[:, 1])
            for node in np.unique(nodes):
                assert not any(node_verdict(res, x)[0] for x in path_to_root(bvh, int(node))), (name, k, node)
            sentences = collision_sentences(col, res)
            assert len(sentences) == len(res.pairs)
            for (i, j), node, s in zip(res.pairs, nodes, sentences):
                assert s.startswith(f"triangles {i} and {j} intersect: the smallest node holding both, node {node} ")
                assert "was not culled" in s and "report this as a bug" not in s
                if bvh["right"][node] >= 0:  # met between the node's children: by its front with a front method
                    front = method.endswith("+front")
                    assert (f"FrontTracking(Front_{node})" in s) == front and ("Collide(node" in s) == (not front)


@pytest.mark.parametrize("method", ["nc", "cbc"])
def test_every_ccd_contact_is_explained_by_nodes_not_culled(method):
    F, P = load_sequence("fold")
    col = conecull.SelfCollider(conecull.Mesh(F), method=method)
    col.dcd(P[0])
    res = col.ccd(P[27], P[28], trace=True, toi=True)
    assert len(res.vf) and len(res.ee)
    sentences = collision_sentences(col, res)
    assert len(sentences) == len(res.vf) + len(res.ee)
    for (v, f), s in zip(res.vf, sentences):
        assert s.startswith(f"vertex {v} touches triangle {f} during the step (not before t = ")
    for (a, b), s in zip(res.ee, sentences[len(res.vf):]):
        assert s.startswith(f"edge {a} (") and f"touches edge {b} (" in s
    assert all("was not culled" in s and "report this as a bug" not in s for s in sentences)
    assert len(collision_sentences(col, res, 5)) == 5


def test_explain_pair_and_face():
    """A colliding pair is said to intersect and where it was met; a pair inside a culled node is
    said never to have been tested, naming that node; a face lists its collisions, or says it has
    none and names the smallest judged node holding it."""
    F, P = load_sequence("fold")
    col = conecull.SelfCollider(conecull.Mesh(F))
    col.dcd(P[0])
    res = col.dcd(P[28], trace=True)
    i, j = (int(x) for x in res.pairs[0])
    text = explain_pair(col, res, j, i)
    assert text.startswith(f"triangles {j} and {i} intersect: the smallest node holding both") and "Collide(node" in text
    bvh = col.bvh_arrays()
    culled = int(res.trace.culled_nodes()[0])
    a, b = (int(x) for x in bvh["order"][[bvh["begin"][culled], bvh["end"][culled] - 1]])
    text = explain_pair(col, res, a, b)
    assert text.startswith(f"triangles {a} and {b} do not intersect: they were never tested: node {culled} ")
    mine = int(((res.pairs[:, 0] == i) | (res.pairs[:, 1] == i)).sum())
    assert explain_face(col, res, i).startswith(f"triangle {i} takes part in {mine} collision")
    assert explain_face(col, res, a).startswith(f"triangle {a} collides with nothing in this query; the smallest "
                                                f"node judged that holds it")
    assert explain_pair(col, res, a, a).endswith("a triangle is never tested against itself.")
    for bad, match in ((col.mesh.n_faces, r"face: 2048 is out of range: the mesh has triangles 0\.\.2047"),
                       (1.5, r"face: expected an integer triangle id in 0\.\.2047, got 1\.5")):
        with pytest.raises(ValueError, match=match):
            explain_face(col, res, bad)
    with pytest.raises(ValueError, match=r"^j: -1 is out of range"):
        explain_pair(col, res, 0, -1)
    ccd = col.ccd(P[27], P[28], trace=True, toi=True)
    v, f = (int(x) for x in ccd.vf[0])
    g = int(col.mesh.vertex_faces[1][col.mesh.vertex_faces[0][v]])
    assert explain_pair(col, ccd, g, f).startswith(f"triangles {g} and {f} touch during the step (")
    assert f"vertex {v} touches triangle {f}" in explain_face(col, ccd, f)


def test_edge_edge_contacts_name_the_smallest_node_over_all_triangles_around_them():
    """The nodes holding a triangle around each edge of an edge-edge contact are not nested: the
    sentence names the one with the fewest triangles (a review found crumple's step 28 -> 29
    naming a 170-triangle node where a 74-triangle one also holds the contact), and the pair
    sentence of any two triangles around the edges never names a smaller one."""
    from conecull.viz.explain import _Triage

    F, P = load_sequence("crumple")
    col = conecull.SelfCollider(conecull.Mesh(F))
    col.dcd(P[0])
    res = col.ccd(P[28], P[29], trace=True, toi=True)
    t = _Triage(col, res)
    eoff, eids = col.mesh.edge_faces
    bvh = col.bvh_arrays()
    size = bvh["end"] - bvh["begin"]
    checked = 0
    for (a, b), s in zip(res.ee[:300], t.ee(res.ee[:300], None)):
        fa, fb = eids[eoff[a] : eoff[a + 1]], eids[eoff[b] : eoff[b + 1]]
        nodes = [int(smallest_common_nodes(bvh, [i], [j])[0]) for i in fa for j in fb]
        named = int(s.split("), node ")[1].split(" ")[0]) if "), node " in s else None
        best = min(nodes, key=lambda n: size[n])
        assert named == best or size[named] == size[best], (a, b, s)
        checked += len(set(size[nodes].tolist())) > 1
    assert checked  # some contacts had candidates of different sizes


def test_contact_times_are_rounded_down():
    from conecull.viz.explain import time_bound, time_floor

    assert time_floor(0.76659966, 3) == "0.766" and time_floor(0.12345982, 4) == "0.1234"
    assert time_floor(0.9999999999, 3) == "0.999" and time_floor(0.5, 3) == "0.500"
    assert time_bound(0.0) == "already at t = 0" and time_bound(0.25) == "not before t = 0.2500"
    rng = np.random.default_rng(3)
    for t in rng.random(2000):
        assert float(time_floor(t, 4)) <= t


def test_a_resting_front_is_named_as_such():
    """With a front method, the sentence says how the smallest node's front met the pair, from
    the query's own front events: resumed, built from the top, or, where it rests after churning,
    Collide from the top (repeating the fold's last frames makes node 1's front churn, then rest)."""
    F, P = load_sequence("fold")
    col = conecull.SelfCollider(conecull.Mesh(F), method="nc+front")
    for k in range(30):
        col.dcd(P[k])
    modes = set()
    for k in (29, 28, 29, 28, 29):
        res = col.dcd(P[k], trace=True)
        fr = dict(zip(res.trace.front["node"].tolist(), res.trace.front["mode"].tolist()))
        bvh = col.bvh_arrays()
        nodes = smallest_common_nodes(bvh, res.pairs[:, 0], res.pairs[:, 1])
        for node, s in zip(nodes, collision_sentences(col, res)):
            mode = fr[int(node)]
            modes.add(mode)
            want = {0: "resumed from the front the last query left", 1: "built from the top",
                    2: f"from the top: Front_{node} rests after churning", 3: "dropped for churning"}[mode]
            assert want in s, (mode, s)
    assert 2 in modes and 0 in modes


def test_a_pair_not_colliding_says_whether_it_was_tested():
    """For a pair that does not collide and was not culled: the trace says whether its test ran
    (DCD: the triangle-triangle test; CCD: vertex-face and edge-edge tests between them)."""
    from conecull.viz.explain import _Triage

    F, P = load_sequence("fold")
    col = conecull.SelfCollider(conecull.Mesh(F))
    col.dcd(P[0])
    res = col.dcd(P[28], trace=True)
    t = _Triage(col, res)
    tested = {tuple(p) for p in res.trace.elementary["pair"][~res.trace.elementary["result"]].tolist()}
    i, j = sorted(tested)[0]
    assert explain_pair(col, res, i, j).endswith("their triangle-triangle test ran and found no intersection.")
    rng = np.random.default_rng(0)
    untested = 0
    for a, b in rng.integers(0, len(F), (400, 2)):
        if a == b or (min(a, b), max(a, b)) in tested or t.first_culled([int(t.smallest([a], [b])[0])]) is not None:
            continue
        assert explain_pair(col, res, int(a), int(b)).endswith("no triangle-triangle test ran: their boxes, or those "
                                                               "of nodes holding them, were apart.")
        untested += 1
    assert untested
    # CCD: a vertex-face test that found no contact; a triangle g at the vertex and the face f
    # either touch through another of their tests, or not, and then the sentence says which ran.
    ccd = col.ccd(P[27], P[28], trace=True)
    apart = 0
    for v, f in ccd.trace.vf["pair"][~ccd.trace.vf["result"]][:20].tolist():
        g = int(col.mesh.vertex_faces[1][col.mesh.vertex_faces[0][v]])
        text = explain_pair(col, ccd, g, f)
        if text.startswith(f"triangles {g} and {f} do not touch during the step"):
            assert "tests between them ran and found no contact" in text, text
            apart += 1
        else:
            assert text.startswith(f"triangles {g} and {f} touch during the step"), text
    assert apart


def _fold_node(method, frame=28, node=1665, *, facts=False):
    """explain_node for a node of fold whose contour test runs; with facts, also the number of its
    contour's edges (counted here from its triangles: the edges only one of them has) and its
    contour event's crossings."""
    F, P = load_sequence("fold")
    col = conecull.SelfCollider(conecull.Mesh(F), method=method)
    col.dcd(P[0])
    res = col.dcd(P[frame], trace=True)
    text = explain_node(col, res, node)
    if not facts:
        return text
    bvh = col.bvh_arrays()
    tris = F[bvh["order"][bvh["begin"][node] : bvh["end"][node]]]
    edges = np.sort(np.vstack([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), axis=1)
    _, count = np.unique(edges, axis=0, return_counts=True)
    (event,) = np.flatnonzero(res.trace.contour["node"] == node)
    return text, int((count == 1).sum()), int(res.trace.contour["crossings"][event])


def _crumple_failure(method: str, reason: int) -> str:
    """explain_node for the first node whose contour test fails with `reason` at crumple's last frame."""
    F, P = load_sequence("crumple")
    col = conecull.SelfCollider(conecull.Mesh(F), method=method)
    col.dcd(P[0])
    res = col.dcd(P[-1], trace=True)
    return explain_node(col, res, int(res.trace.contour["node"][res.trace.contour["reason"] == reason][0]))


def test_cbc_is_explained_as_its_edge_pair_test():
    """cbc ([TCYM09]) tests every pair of projected contour edges: no kernel point, no ray, no star
    test. Its trace reports the contour's mean as "kernel", a zero ray and 0 crossings, which were
    shown as if tested ("kernel point [...], ray [0, 0, 0], crossings 0 ... star-shaped")."""
    text, n, _ = _fold_node("cbc", facts=True)
    assert n >= 3
    assert "contour test (cbc, the quadratic edge-pair test of Tang et al. 2009): every pair of the contour's " \
           f"{n} edges, projected along the cone axis, must be proven apart ({n * (n - 1) // 2} pairs); no kernel " \
           "point, no ray" in text
    assert "verdict: culled, passed: no two edges of the contour, projected along the cone axis, meet" in text
    assert "kernel point [" not in text and "ray [" not in text and "crossings" not in text and "star" not in text
    text = _crumple_failure("cbc", 7)  # a failure names the edge pair test too
    assert "quadratic edge-pair test" in text and "verdict: not culled, edges_may_overlap: cbc: contour edge" in text
    assert "kernel point [" not in text and "star" not in text


def test_sct_is_explained_as_its_projected_star_test():
    """sct ([SPO10]) projects the contour on the plane perpendicular to the cone axis, finds a kernel
    point there by a line search and runs the star test: its kernel point, ray and crossings are
    shown, as that method's; where the line search found none, no star test is claimed."""
    text, n, crossings = _fold_node("sct", facts=True)
    assert n >= 3 and crossings == 1  # passed: a ray from a kernel point leaves a star contour once
    assert "contour test (sct, the projected star contour test of Schvartzman et al. 2010): the contour's " \
           f"{n} edges projected on the plane perpendicular to the cone axis; kernel point from the line search [" in text
    assert f"crossings {crossings}" in text
    assert "verdict: culled, passed: the contour, projected on the plane perpendicular to the cone axis, is " \
           "star-shaped around the kernel point the line search found" in text
    text = _crumple_failure("sct", 6)
    assert "the line search found no kernel point there, so no star test ran" in text
    assert "kernel point [" not in text and "crossings" not in text
    assert "verdict: not culled, no_kernel_on_search_line" in text
    # nc's Alg. 1 keeps its own line
    assert "contour test: kernel point [" in _fold_node("nc")


@pytest.mark.parametrize("method", ["sct", "cbc"])
def test_triage_sentences_use_the_method_s_own_test(method):
    """The triage sentences (explain_face, the viewer's panel) name a culled node's verdict in the
    method's own words, not Alg. 1's star test."""
    F, P = load_sequence("fold")
    col = conecull.SelfCollider(conecull.Mesh(F), method=method)
    col.dcd(P[0])
    res = col.dcd(P[28], trace=True)
    bvh = col.bvh_arrays()
    culled = int(res.trace.culled_nodes()[0])
    a, b = (int(x) for x in bvh["order"][[bvh["begin"][culled], bvh["end"][culled] - 1]])
    text = explain_pair(col, res, a, b)
    want = {"sct": "star-shaped around the kernel point the line search found", "cbc": "every pair proven apart"}
    assert want[method] in text and "projects to a star-shaped polygon" not in text


@pytest.mark.parametrize("limit", [0, -1, 1.5, "a", None, True])
def test_names_a_bad_limit(sheets, limit):
    """limit counts items to show, not a slice bound (found by review: -1 silently dropped the
    last item, 0 printed a heading with nothing under it, 'a' raised a TypeError about slices)."""
    from conecull.viz.explain import collision_sentences, explain_cones, explain_face

    col, res, _ = sheets[0]
    with pytest.raises(ValueError, match=r"^limit: expected an integer >= 1"):
        explain_cones(col, res, limit=limit)
    with pytest.raises(ValueError, match=r"^limit: expected an integer >= 1"):
        explain_face(col, res, 0, limit=limit)
    if limit is not None:
        with pytest.raises(ValueError, match=r"^limit: expected an integer >= 1 or None \(all\)"):
            collision_sentences(col, res, limit=limit)
    else:
        assert len(collision_sentences(col, res, limit=None)) == len(res.pairs) > 0
