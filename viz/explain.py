"""Plain-language verdicts in one traced query (`conecull explain`): of one BVH node, and, for
triage, of a collision, a pair of triangles or a triangle: why the smallest node holding them was
culled or not, and where the traversal met them."""

from __future__ import annotations

from decimal import ROUND_FLOOR, Decimal

import numpy as np

from conecull.normal_spread import Normals, node_spreads, normal_spread
from conecull.trace import CONE_TOO_WIDE, REASONS, explain
from conecull.viz.checks import check_face, check_limit, check_node
from conecull.viz.layers import cone_sentence


def parents(bvh: dict) -> np.ndarray:
    p = np.full(len(bvh["depth"]), -1, np.int64)
    inner = np.flatnonzero(bvh["right"] >= 0)
    p[bvh["left"][inner]] = inner
    p[bvh["right"][inner]] = inner
    return p


def path_to_root(bvh: dict, node: int, par: np.ndarray | None = None) -> list[int]:
    """node, its parent, ..., the root; par: parents(bvh), if already at hand."""
    par = parents(bvh) if par is None else par
    out = [int(node)]
    while par[out[-1]] >= 0:
        out.append(int(par[out[-1]]))
    return out


def check_result(col, res) -> None:
    """res must be a traced query of col itself: node ids mean nothing in another collider's BVH.
    A result names its collider (res.collider, a weak reference), and its trace the fingerprint of
    that collider's BVH (res.trace.bvh, SelfCollider.bvh_digest): a result parted from its
    collider (unpickled, or the collider gone) is accepted only by a collider with the same BVH.
    For a result built by hand (no collider, no fingerprint), what the trace shows is compared
    instead: the method, the BVH's depth (the trace has one level entry per depth) and that every
    node, face, vertex, edge and contour edge it names exists in col."""
    import conecull

    if not isinstance(col, conecull.SelfCollider):
        raise ValueError(f"col: expected a conecull.SelfCollider, got {type(col).__name__}")
    if not isinstance(res, (conecull.DcdResult, conecull.CcdResult)):
        raise ValueError(f"res: expected the result of a query of col (col.dcd(V, trace=True)), "
                         f"got {type(res).__name__}")
    if not len(col.bvh_arrays()["depth"]):
        raise ValueError("col: has no BVH yet (it is built by the first query): run col.dcd(V) first")
    if res.trace is None:
        raise ValueError("res: the query was not traced; run it with trace=True (col.dcd(V, trace=True))")
    owner = res.collider() if res.collider is not None else None
    if owner is not None and owner is not col:
        raise ValueError("res: comes from another collider; pass the result of a query of col itself")
    digest = getattr(res.trace, "bvh", None)
    if owner is None and digest is not None and digest != col.bvh_digest():
        raise ValueError("res: was traced on another BVH than col's (a collider of another mesh, or of this mesh "
                         "built from another first pose), so its node ids name other nodes; pass the result of a "
                         "query of col itself")
    method = res.stats.get("method")
    if method != col.method:
        raise ValueError(f"res: comes from a query with method {method!r}, but col uses {col.method!r}; "
                         "pass the result of col's own query")
    bvh, tr, mesh = col.bvh_arrays(), res.trace, col.mesh
    depth = int(bvh["depth"].max()) + 1 if len(bvh["depth"]) else 0
    ct = col.contour_arrays()
    loop_len = np.diff(ct["offsets"])
    problems = []
    if len(tr.level["pairs"]) != depth:
        problems.append(f"its trace covers a BVH of depth {len(tr.level['pairs']) - 1}, col's has depth {depth - 1}")
    n_nodes = len(bvh["depth"])
    for kind in ("cone", "contour"):
        nodes = getattr(tr, kind)["node"]
        if len(nodes) and nodes.max() >= n_nodes:
            problems.append(f"its trace names node {int(nodes.max())}, col's BVH has nodes 0..{n_nodes - 1}")
    c = tr.contour
    if not problems and len(c["node"]) and (c["edge"] >= loop_len[c["node"]]).any():
        problems.append("its trace names contour edges col's contours do not have")
    for kind, limits, what in (("elementary", (mesh.n_faces, mesh.n_faces), "triangle"),
                               ("vf", (mesh.n_vertices, mesh.n_faces), "vertex or face"),
                               ("ee", (len(mesh.edges),) * 2, "edge")):
        pairs = getattr(tr, kind)["pair"] if hasattr(tr, kind) else np.zeros((0, 2))
        if len(pairs) and (pairs.max(axis=0) >= limits).any():
            problems.append(f"its trace names a {what} col's mesh does not have")
    if problems:
        raise ValueError(f"res: comes from another collider ({problems[0]}); pass the result of a query of col itself")


NO_CONES = ("aabb", "aabb+front")  # the methods without normal cones (nor contours)


# The contour tests differ per method, though the trace fills the same fields for each: "nc" runs
# Alg. 1 (a kernel point o, a ray r, its crossings), or the simplicity test; "sct" [SPO10] projects
# the contour on the plane perpendicular to the cone axis, looks for o by a line search there,
# then runs the star test on the projection; "cbc" [TCYM09] tests every pair of projected contour
# edges, O(n^2): it has no kernel point, no ray, no star test (its trace reports the contour's
# mean as "kernel", a zero ray and 0 crossings: they must not be shown as if tested).
SCT_NAME = "sct, the projected star contour test of Schvartzman et al. 2010"
CBC_NAME = "cbc, the quadratic edge-pair test of Tang et al. 2009"
PASSED_SCT = ("the contour, projected on the plane perpendicular to the cone axis, is star-shaped around the "
              "kernel point the line search found: no self-collision, culled")
PASSED_CBC = ("no two edges of the contour, projected along the cone axis, meet (every pair proven apart): the "
              "projected contour is a simple polygon, so no self-collision, culled")


def contour_words(method: str, contour: dict, i: int) -> str:
    """The verdict sentence of contour event i (trace.contour) of a query by `method`."""
    code = int(contour["reason"][i])
    if code == 0 and method == "cbc":
        return PASSED_CBC
    if code == 0 and method == "sct":
        return PASSED_SCT
    star_tried = bool(np.isfinite(contour["kernel"][i]).all())
    return explain(code, contour["edge"][i], contour["crossings"][i], bool(contour["simple"][i]), star_tried)


def contour_test_line(method: str, contour: dict, i: int, n_edges: int) -> str:
    """What contour event i's test ran, in one line: only the quantities that method's test has."""
    kernel = np.round(contour["kernel"][i], 6).tolist()
    ray = np.round(contour["ray"][i], 4).tolist()
    crossings = int(contour["crossings"][i])
    if method == "cbc":
        return (f"contour test ({CBC_NAME}): every pair of the contour's {n_edges} edges, projected along the cone "
                f"axis, must be proven apart ({n_edges * (n_edges - 1) // 2} pairs); no kernel point, no ray")
    if method == "sct" and REASONS[int(contour["reason"][i])][0] == "no_kernel_on_search_line":
        return (f"contour test ({SCT_NAME}): the contour's {n_edges} edges projected on the plane perpendicular to "
                "the cone axis; the line search found no kernel point there, so no star test ran")
    if method == "sct":
        return (f"contour test ({SCT_NAME}): the contour's {n_edges} edges projected on the plane perpendicular to "
                f"the cone axis; kernel point from the line search {kernel}, ray {ray} (the ray tested is "
                f"its projection on that plane), crossings {crossings}")
    if np.isfinite(contour["kernel"][i]).all():
        return f"contour test: kernel point {kernel}, ray {ray}, crossings {crossings}"
    return "contour test: the simplicity test, run first: it proved this node when last tested"


def explain_node(col, res, node: int, *, node_name: str = "node") -> str:
    """A few lines: where the node is, what was tested there, and the verdict in words.
    res: a traced query (trace=True) of col itself; node: a node id of col's BVH (node_name is
    what errors call it: the CLI passes "--node")."""
    check_result(col, res)
    bvh = col.bvh_arrays()
    node = check_node(node, len(bvh["depth"]), node_name)
    tr = res.trace
    nt = int(bvh["end"][node] - bvh["begin"][node])
    path = path_to_root(bvh, node)
    lines = [f"node {node}: depth {int(bvh['depth'][node])}, {nt} triangle{'s' if nt != 1 else ''}, "
             f"{'leaf' if bvh['right'][node] < 0 else 'internal'}; path to root: {' -> '.join(map(str, path))}"]
    cone_i = np.flatnonzero(tr.cone["node"] == node)
    contour_i = np.flatnonzero(tr.contour["node"] == node)
    if len(cone_i):
        i = cone_i[0]
        if not tr.cone["bounded"][i]:
            lines.append("normal cone: the full cone (no bound below 180 degrees)")
            tris = bvh["order"][bvh["begin"][node] : bvh["end"][node]]
            spread = normal_spread(Normals(col.mesh.faces, *tr.positions), tris)
            lines.append(f"normals: {spread.sentence(hasattr(res, 'vf'))}")
            lines.append("verdict: not culled, cone_too_wide: " + CONE_TOO_WIDE[1] + ".")
            return "\n".join(lines)
        ang = float(np.degrees(tr.cone["apex_angle"][i]))
        ax = np.round(tr.cone["axis"][i], 4).tolist()
        lines.append(f"normal cone: axis {ax}, apex angle at most {ang:.2f} degrees")
    if len(contour_i):
        i = contour_i[0]
        code = int(tr.contour["reason"][i])
        method = res.stats.get("method", col.method)
        if code < 16:
            n_edges = int(np.diff(col.contour_arrays()["offsets"])[node])
            lines.append(contour_test_line(method, tr.contour, i, n_edges))
        verdict = "culled" if code == 0 else "not culled"
        lines.append(f"verdict: {verdict}, {REASONS[code][0]}: " + contour_words(method, tr.contour, i) + ".")
        return "\n".join(lines)
    # Not judged itself: say why.
    culled = set(tr.culled_nodes().tolist())
    above = [a for a in path[1:] if a in culled]
    if above:
        lines.append(f"verdict: not examined: its ancestor {above[0]} was culled, which covers this node.")
    elif nt < 2:
        lines.append("verdict: not examined: a single triangle cannot collide with itself (Alg. 2 line 1).")
    elif res.stats.get("method") in NO_CONES:
        lines.append(f"verdict: not examined: method '{res.stats['method']}' uses no normal cones.")
    else:
        lines.append("verdict: not examined by normal cones in this query.")
    return "\n".join(lines)


def explain_cones(col, res, limit: int = 20) -> str:
    """The nodes whose normal cone failed in a traced query (Alg. 2 line 5), counted by their
    normals' spread (normal_spread), then the largest of them one per line (at most `limit`)."""
    check_result(col, res)
    limit = check_limit(limit)
    tr = res.trace
    bvh = col.bvh_arrays()
    bad = tr.cone["node"][~tr.cone["bounded"]]
    if res.stats.get("method") in NO_CONES:
        return f"method '{res.stats['method']}' uses no normal cones: no cone test ran."
    if not len(bad):
        return "no normal cone failed in this query: every node tested had a cone bounded below 180 degrees."
    ccd = hasattr(res, "vf")
    spreads = node_spreads(Normals(col.mesh.faces, *tr.positions), bvh, bad)
    size = bvh["end"] - bvh["begin"]
    shown = sorted(spreads, key=lambda n: (-int(size[n]), n))[:limit]
    lines = [cone_sentence(spreads, ccd) + "."]
    for n in shown:
        s = spreads[n]
        lines.append(f"node {n} (depth {int(bvh['depth'][n])}, {int(size[n])} triangles): {s.sentence(ccd)}")
    if len(spreads) > len(shown):
        lines.append(f"(and {len(spreads) - len(shown)} more, smaller; `--node ID` for one)")
    return "\n".join(lines)


# --- Triage: why the region holding a collision was not culled -----------------------------
#
# A pair of triangles (or, for CCD, of a triangle and a vertex, or two edges, with the triangles
# around them) can only be found if no BVH node holding both was culled: culling a node proves
# its patch free of self-collision. So the answer to "why was this collision not culled away?"
# is the verdict of the smallest node holding both, and of its ancestors; the pair itself is a
# candidate of Collide(L, R) between that node's two children (Alg. 2).


def face_positions(bvh: dict) -> np.ndarray:
    """pos[f]: the index of face f in the BVH's triangle order (node ranges are of these)."""
    pos = np.empty(len(bvh["order"]), np.int64)
    pos[bvh["order"]] = np.arange(len(bvh["order"]))
    return pos


def smallest_common_nodes(bvh: dict, a, b, pos: np.ndarray | None = None) -> np.ndarray:
    """For each k, the smallest BVH node whose triangles include faces a[k] and b[k] (the leaf
    holding a[k] when a[k] == b[k]), descending from the root level by level. pos: face_positions
    (bvh), if already at hand."""
    pos = face_positions(bvh) if pos is None else pos
    pa, pb = pos[np.asarray(a, np.int64)], pos[np.asarray(b, np.int64)]
    node = np.zeros(len(pa), np.int64)
    left, right, begin, end = bvh["left"], bvh["right"], bvh["begin"], bvh["end"]
    active = right[node] >= 0
    while active.any():
        n = node[active]
        lc, rc = left[n], right[n]
        in_l = (begin[lc] <= pa[active]) & (pa[active] < end[lc]) & (begin[lc] <= pb[active]) & (pb[active] < end[lc])
        in_r = (begin[rc] <= pa[active]) & (pa[active] < end[rc]) & (begin[rc] <= pb[active]) & (pb[active] < end[rc])
        nxt = np.where(in_l, lc, np.where(in_r, rc, n))
        moved = nxt != n
        idx = np.flatnonzero(active)
        node[idx] = nxt
        active[idx[~moved]] = False
        active[idx[moved]] = right[nxt[moved]] >= 0
    return node


# The cone verdict in a triage sentence: short (it may repeat 100 times in a frame's log); the
# node sentences (explain --node, the log's failing nodes) keep CONE_TOO_WIDE's whole sentence.
CONE_SHORT = "its normal cone could not be bounded below 180 degrees"


class Verdicts:
    """verdicts(node) -> (culled, name, why) for the nodes of one traced query: culled True /
    False if the normal-cone test judged the node, None if it never did (no cone test there);
    name: the verdict's name (REASONS, cone_too_wide); why: in words, short. The events are
    indexed once, not searched per node (a recording explains up to 100 collisions per frame)."""

    def __init__(self, res):
        tr = res.trace
        self.res = res
        nodes, first = np.unique(tr.contour["node"], return_index=True)
        self.contour_at = dict(zip(nodes.tolist(), first.tolist()))
        nodes, first = np.unique(tr.cone["node"], return_index=True)
        self.cone_at = dict(zip(nodes.tolist(), first.tolist()))

    def __call__(self, node: int) -> tuple[bool | None, str, str]:
        tr = self.res.trace
        i = self.contour_at.get(int(node))
        if i is not None:
            code = int(tr.contour["reason"][i])
            why = contour_words(self.res.stats.get("method"), tr.contour, i)
            return code == 0, REASONS[code][0], why.removesuffix(", culled")
        i = self.cone_at.get(int(node))
        if i is not None and not tr.cone["bounded"][i]:
            return False, "cone_too_wide", CONE_SHORT
        method = self.res.stats.get("method")
        if method in NO_CONES:
            return None, "no_cones", f"method '{method}' uses no normal cones"
        return None, "not_judged", "not judged by normal cones in this query"


def node_verdict(res, node: int) -> tuple[bool | None, str]:
    """(culled, "name: why") for one node of a traced query (Verdicts, for a single node)."""
    culled, name, why = Verdicts(res)(node)
    return culled, f"{name}: {why}"


def time_floor(t: float, places: int) -> str:
    """t rounded down to `places` decimals, exactly (a certified lower bound on a contact time
    must never be printed rounded up: that would claim no contact before a time when one can
    still happen)."""
    return str(Decimal(float(t)).quantize(Decimal(1).scaleb(-places), rounding=ROUND_FLOOR))


def time_bound(t: float, places: int = 4) -> str:
    """A certified lower bound on a contact time, in words (time_floor)."""
    return "already at t = 0" if t <= 0.0 else f"not before t = {time_floor(t, places)}"


class _Triage:
    """What the sentences below look up, once per query: the BVH, its parents, the verdicts, the
    front events (front methods) and the tests the query ran."""

    def __init__(self, col, res):
        self.col, self.res = col, res
        self.bvh = col.bvh_arrays()
        self.parent = parents(self.bvh)
        self.pos = face_positions(self.bvh)
        self.verdict = Verdicts(res)
        fr = res.trace.front
        self.front_mode = dict(zip(fr["node"].tolist(), fr["mode"].tolist()))

    def smallest(self, a, b) -> np.ndarray:
        return smallest_common_nodes(self.bvh, a, b, self.pos)

    def size(self, node: int) -> int:
        return int(self.bvh["end"][node] - self.bvh["begin"][node])

    def path(self, node: int) -> list[int]:
        """The root, ..., node."""
        return path_to_root(self.bvh, node, self.parent)[::-1]

    def words(self, node: int) -> str:
        nt = self.size(node)
        return f"node {node} (depth {int(self.bvh['depth'][node])}, {nt} triangle{'s' if nt != 1 else ''})"

    def first_culled(self, nodes) -> int | None:
        """The highest culled node on the paths to the root of `nodes`, or None."""
        culled = [x for n in nodes for x in self.path(n) if self.verdict(x)[0]]
        return min(culled, key=lambda x: int(self.bvh["depth"][x])) if culled else None

    def met(self, node: int) -> str:
        """Where the traversal meets the pairs of triangles whose smallest common node is `node`."""
        bvh = self.bvh
        l, r = int(bvh["left"][node]), int(bvh["right"][node])
        if r < 0:
            return "Both are in this leaf, whose triangles are tested pairwise (Alg. 2)"
        mode = self.front_mode.get(int(node))
        if mode is None:
            return f"The pair is met by Collide(node {l}, node {r}), the test of its two children against each other (Alg. 2)"
        how = {0: "resumed from the front the last query left", 1: "built from the top (no front was kept)",
               3: "resumed, then dropped for churning (it rests from the next query)"}.get(mode)
        if how is None:  # resting
            return (f"The pair is met by Collide(node {l}, node {r}) from the top: Front_{node} rests after churning "
                    "(Alg. 4)")
        return f"The pair is met by FrontTracking(Front_{node}) between nodes {l} and {r}, {how} (Alg. 4)"

    def why_found(self, node: int, what: str, holding: str, collides: bool = True, also=()) -> str:
        """The sentence on `node`, the smallest node holding two triangles (`what`: which, and
        whether they collide; `holding`: the triangles, in words): if a node on its path (or on
        those of `also`, other nodes holding the collision) was culled, they were never tested
        (for a collision, a bug); else its verdict, its ancestors', and where the pair was met."""
        x = self.first_culled([node, *also])
        if x is not None:
            why = self.verdict(x)[2]
            if collides:
                return (f"{what}, yet {self.words(x)}, which holds {holding}, was culled ({why}): that contradicts "
                        "the collision; please report this as a bug.")
            return f"{what}: they were never tested: {self.words(x)}, which holds them, was culled ({why})."
        _, name, why = self.verdict(node)
        out = f"{what}: the smallest node holding {holding}, {self.words(node)}, was not culled ({name}: {why})"
        above = self.path(node)[:-1]
        if above and self.verdict(node)[0] is not None:
            kinds = sorted({self.verdict(a)[1] for a in above})
            out += (f"; nor was its parent ({kinds[0]})" if len(above) == 1
                    else f"; nor were its {len(above)} ancestors ({', '.join(kinds)})")
        return f"{out}. {self.met(node)}."

    def pairs(self, pairs) -> list[str]:
        nodes = self.smallest(pairs[:, 0], pairs[:, 1])
        return [self.why_found(int(n), f"triangles {int(i)} and {int(j)} intersect", "both")
                for (i, j), n in zip(pairs, nodes)]

    def vf(self, rows, toi, focus: int | None = None) -> list[str]:
        """rows: (vertex, face) contacts; toi: their times or None; focus: a triangle the reader
        asked about. Any node holding the face and a triangle around the vertex holds the contact;
        these nodes are all on the face's path, so the deepest is the smallest."""
        voff, vids = self.col.mesh.vertex_faces
        out = []
        for k, (v, f) in enumerate(rows):
            around = vids[voff[v] : voff[v + 1]]
            nodes = self.smallest(around, np.full(len(around), f))
            g = int(np.argmax(self.bvh["depth"][nodes]))
            corner = (f", a corner of triangle {focus}," if focus is not None and focus != f and focus in around
                      else "")
            when = "" if toi is None else f" ({time_bound(toi[k])})"
            out.append(self.why_found(int(nodes[g]), f"vertex {int(v)}{corner} touches triangle {int(f)} during the "
                                      f"step{when}", f"triangles {int(around[g])} (around the vertex) and {int(f)}"))
        return out

    def ee(self, rows, toi, focus: int | None = None) -> list[str]:
        """rows: (edge, edge) contacts. The nodes holding a triangle around each edge are not nested:
        the one with the fewest triangles is named, and none of them may be culled."""
        eoff, eids = self.col.mesh.edge_faces
        E = self.col.mesh.edges
        out = []
        for k, (a, b) in enumerate(rows):
            fa, fb = eids[eoff[a] : eoff[a + 1]], eids[eoff[b] : eoff[b + 1]]
            A, B = np.repeat(fa, len(fb)), np.tile(fb, len(fa))
            nodes = self.smallest(A, B)
            sizes = self.bvh["end"][nodes] - self.bvh["begin"][nodes]
            g = int(np.argmin(sizes))
            side = lambda e, fs: (f", of triangle {focus}," if focus is not None and focus in fs else "")  # noqa: E731
            when = "" if toi is None else f" ({time_bound(toi[k])})"
            out.append(self.why_found(int(nodes[g]), f"edge {int(a)} ({int(E[a][0])}-{int(E[a][1])}){side(a, fa)} "
                                      f"touches edge {int(b)} ({int(E[b][0])}-{int(E[b][1])}){side(b, fb)} during the "
                                      f"step{when}", f"triangles {int(A[g])} and {int(B[g])} (one around each edge)",
                                      also=np.unique(nodes).tolist()))
        return out

    def tested_between(self, i: int, j: int) -> str:
        """Whether the query ran a test between triangles i and j (the trace's elementary, VF and
        EE events), for a pair that does not collide and was not culled."""
        tr = self.res.trace
        if not hasattr(self.res, "vf"):
            pair = (min(i, j), max(i, j))
            ran = len(tr.elementary["pair"]) and bool((tr.elementary["pair"] == pair).all(axis=1).any())
            return ("their triangle-triangle test ran and found no intersection" if ran else
                    "no triangle-triangle test ran: their boxes, or those of nodes holding them, were apart")
        vf, ee = (len(x) for x in _between(self.col, tr.vf["pair"], tr.ee["pair"], i, j))
        if vf + ee:
            return f"{vf} vertex-face and {ee} edge-edge tests between them ran and found no contact"
        return ("no vertex-face or edge-edge test between them ran: their swept boxes were apart, or the "
                "non-penetration filter ruled the pairs out")


def _between(col, vf_rows, ee_rows, i: int, j: int) -> tuple[list, list]:
    """The vertex-face rows (v, f) and edge-edge rows (a, b) that pair a feature of triangle i
    with one of triangle j (a vertex of one with the other face, an edge of each)."""
    F, FE = col.mesh.faces, col.mesh.face_edges
    vf = [(v, f) for v, f in vf_rows.tolist() if (f == j and v in F[i]) or (f == i and v in F[j])]
    ee = [(a, b) for a, b in ee_rows.tolist() if (a in FE[i] and b in FE[j]) or (a in FE[j] and b in FE[i])]
    return vf, ee


def collision_sentences(col, res, limit: int | None = None) -> list[str]:
    """One sentence per collision of a traced query of col (DCD: per colliding pair; CCD: per
    vertex-face, then edge-edge contact), the first `limit` of them: what collides, and why the
    smallest node holding it was not culled (_Triage.why_found)."""
    check_result(col, res)
    limit = check_limit(limit, none_ok=True)
    t = _Triage(col, res)
    if not hasattr(res, "vf"):
        return t.pairs(res.pairs[:limit])
    n_vf = len(res.vf)
    out = t.vf(res.vf[:limit], None if res.toi is None else res.toi[:n_vf])
    left = None if limit is None else max(0, limit - len(out))
    return out + t.ee(res.ee[:left], None if res.toi is None else res.toi[n_vf:])


def explain_pair(col, res, i: int, j: int, *, names: tuple = ("i", "j")) -> str:
    """Triangles i and j in a traced query of col: do they collide (DCD: intersect; CCD: touch
    by a vertex-face or edge-edge contact of their own vertices and edges), and the verdict of
    the smallest node holding both, which decided whether they were ever tested."""
    check_result(col, res)
    i, j = (check_face(x, col.mesh.n_faces, n) for x, n in zip((i, j), names))
    if hasattr(res, "vf"):
        vf_rows, ee_rows = _between(col, res.vf, res.ee, i, j)
        vf = [f"vertex {v} and triangle {f}" for v, f in vf_rows]
        ee = [f"edges {a} and {b}" for a, b in ee_rows]
        hit = bool(vf + ee)
        what = (f"triangles {i} and {j} touch during the step ({'; '.join(vf + ee)})" if hit
                else f"triangles {i} and {j} do not touch during the step")
    else:
        lo, hi = min(i, j), max(i, j)
        hit = len(res.pairs) > 0 and bool(((res.pairs[:, 0] == lo) & (res.pairs[:, 1] == hi)).any())
        what = f"triangles {i} and {j} {'intersect' if hit else 'do not intersect'}"
    if i == j:
        return f"{what}: a triangle is never tested against itself."
    t = _Triage(col, res)
    node = int(t.smallest([i], [j])[0])
    text = t.why_found(node, what, "both", collides=hit)
    if not hit and t.first_culled([node]) is None:
        text = text.removesuffix(".") + f": {t.tested_between(i, j)}."
    return text


def explain_face(col, res, face: int, *, name: str = "face", limit: int = 5) -> str:
    """Triangle `face` in a traced query of col: the collisions it takes part in (the first
    `limit` explained, the rest counted), or, if none, the verdict of the smallest node judged
    that holds it."""
    check_result(col, res)
    face = check_face(face, col.mesh.n_faces, name)
    limit = check_limit(limit)
    t = _Triage(col, res)
    if hasattr(res, "vf"):
        F, FE = col.mesh.faces, col.mesh.face_edges
        vf = np.array([f == face or v in F[face] for v, f in res.vf.tolist()], bool).reshape(-1)
        ee = np.array([a in FE[face] or b in FE[face] for a, b in res.ee.tolist()], bool).reshape(-1)
        n = int(vf.sum() + ee.sum())
        toi = res.toi
        sentences = t.vf(res.vf[vf][:limit], None if toi is None else toi[: len(vf)][vf], focus=face)
        sentences += t.ee(res.ee[ee][: limit - len(sentences)], None if toi is None else toi[len(vf):][ee], focus=face)
    else:
        mine = res.pairs[(res.pairs[:, 0] == face) | (res.pairs[:, 1] == face)] if len(res.pairs) else res.pairs
        n = len(mine)
        sentences = t.pairs(mine[:limit])
    if n:
        more = f"\n(and {n - len(sentences)} more)" if n > len(sentences) else ""
        return f"triangle {face} takes part in {n} collision{'s' if n != 1 else ''}:\n" + "\n".join(sentences) + more
    leaf = int(t.smallest([face], [face])[0])
    head = f"triangle {face} collides with nothing in this query"
    judged = [x for x in t.path(leaf)[::-1] if t.verdict(x)[0] is not None]
    if not judged:
        return head + "."
    culled, verdict, why = t.verdict(judged[0])
    return (head + f"; the smallest node judged that holds it, {t.words(judged[0])}, was "
            + (f"culled ({why})." if culled else f"not culled ({verdict}: {why})."))
