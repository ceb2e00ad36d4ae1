"""The event schema of conecull traces: one definition of every event kind, its fields, their
shapes and units, shared by the core's Python façade and both viewers (rerun, viser).

A traced query (`col.dcd(V, trace=True)`) returns a `Trace`: per event kind a table of NumPy
columns (struct-of-arrays). Node ids index the arrays of `SelfCollider.bvh_arrays()`.
Later kinds (CCD steps, BVTT front changes: `front`) extend `EVENT_KINDS`; existing fields never change.
"""

from __future__ import annotations

import operator
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Field:
    name: str
    dtype: str
    shape: tuple  # per event, () for scalars
    unit: str
    doc: str


@dataclass(frozen=True)
class EventKind:
    name: str
    doc: str
    fields: tuple[Field, ...]


EVENT_KINDS: dict[str, EventKind] = {
    k.name: k
    for k in (
        EventKind("cone", "Normal cone test of a node (Alg. 2 line 5: ApexAngle(C_N) < pi).", (
            Field("node", "int32", (), "node id", "BVH node"),
            Field("axis", "float64", (3,), "unit vector", "cone axis l, the projection direction of the contour test"),
            Field("apex_angle", "float64", (), "rad", "certified apex angle (twice the half-angle); 2 pi when full"),
            Field("bounded", "bool", (), "", "apex angle < pi: every exact normal below has n . l > 0"),
        )),
        EventKind("contour", "Contour test of a node whose cone passed (Alg. 1), or why it could not run.", (
            Field("node", "int32", (), "node id", "BVH node"),
            Field("reason", "uint8", (), "code", "0 passed (culled); 1-5 why Alg. 1 failed, 6 sct, 7 cbc; 16+ why the node is ineligible (REASONS)"),
            Field("edge", "int32", (), "contour index", "contour edge (v_i, v_i+1) / vertex where Alg. 1 failed; -1 if none"),
            Field("crossings", "int32", (), "count", "ray crossings counted before the verdict"),
            Field("kernel", "float64", (3,), "length", "kernel point o of the verdict: the contour's mean, or the "
                  "point inside the contour's clipped kernel if the mean failed the kernel test (CCD: o at t = 0)"),
            Field("kernel_end", "float64", (3,), "length", "CCD: the kernel point at t = 1 (it moves linearly over the "
                  "step: the mean's, or the clipped kernel's of the contour at t = 1); DCD: the kernel point again"),
            Field("ray", "float64", (3,), "direction", "ray direction r (its projection on the plane perpendicular to l)"),
            Field("simple", "bool", (), "", "passed by the simplicity test: the contour projects to a simple "
                  "polygon (nc; reason 0). Run after Alg. 1 failed (kernel, ray: its attempt), or first on a node "
                  "it proved when last tested (kernel, kernel_end, ray: NaN)"),
        )),
        EventKind("level", "Node pairs of Collide(A, B) per BVH level (depth of the deeper node); with a BVTT "
                  "front (Alg. 4), the front entries and the sibling merges tested too.", (
            Field("pairs", "int64", (), "count", "node pairs visited"),
            Field("overlaps", "int64", (), "count", "of which the boxes overlapped"),
        )),
        EventKind("front", "FrontTracking(Front_N) of a front method (Alg. 4 line 13): how the node's BVTT front "
                  "between its children was updated by this query (FRONT_MODES), its size before and after.", (
            Field("node", "int32", (), "node id", "BVH node N"),
            Field("mode", "uint8", (), "code", "0 resumed from the front the last query left; 1 built from the top "
                  "(none was kept); 2 resting: Collide(L, R) from the top, unrecorded, since its front churned; "
                  "3 resumed but churned: dropped, N rests from the next query (FRONT_MODES)"),
            Field("before", "int32", (), "entries", "|Front_N| the last query left (0: none kept)"),
            Field("after", "int32", (), "entries", "|Front_N| kept by this query (0 when resting or churned)"),
            Field("box_tests", "int64", (), "count", "box tests spent updating it (descents and merges included)"),
        )),
        EventKind("elementary", "Exact triangle-triangle tests of the candidate pairs (DCD).", (
            Field("pair", "int32", (2,), "face ids", "the two triangles, i < j"),
            Field("result", "bool", (), "", "they collide"),
        )),
        EventKind("vf", "Vertex-face CCD tests that passed the low-level filters (CCD).", (
            Field("pair", "int32", (2,), "(vertex id, face id)", "the vertex and the face"),
            Field("result", "bool", (), "", "they touch during the step"),
        )),
        EventKind("ee", "Edge-edge CCD tests that passed the low-level filters (CCD).", (
            Field("pair", "int32", (2,), "edge ids", "the two edges (ids of Mesh.edges)"),
            Field("result", "bool", (), "", "they touch during the step"),
        )),
    )
}

# The front event's modes (bvtt_front.hpp, FrontMode).
FRONT_MODES: dict[int, str] = {0: "resumed", 1: "from_top", 2: "resting", 3: "churned"}

# Plain-language reasons, for logs, panels and `conecull explain`.
REASONS: dict[int, tuple[str, str]] = {
    0: ("passed", "the contour projects to a star-shaped polygon around its kernel point: no self-collision, culled"),
    1: ("kernel_sign_zero", "the kernel point lies exactly on the line of contour edge {edge}, so the kernel test cannot pass"),
    2: ("not_star_shaped", "contour edge {edge} turns the other way around the kernel point: the projected contour is not star-shaped from it"),
    3: ("ray_through_vertex", "the test ray passes exactly through contour vertex {edge} for every ray direction tried"),
    4: ("multiple_crossings", "the ray from the kernel point crosses the contour {crossings} times: the projected contour winds more than once"),
    5: ("no_crossing", "the ray never crosses the contour"),
    6: ("no_kernel_on_search_line", "sct: the line search found no point of the search line inside every edge's half-plane, so no kernel point was tried"),
    7: ("edges_may_overlap", "cbc: contour edge {edge} and another edge could not be proven apart in projection (they cross, touch, or a sign is undecidable)"),
    16 + 1: ("nonmanifold", "the node's triangles touch a non-manifold edge or vertex, so it is never culled by normal cones"),
    16 + 2: ("inconsistent_orientation", "an edge inside the node is used twice in the same direction (or more than twice)"),
    16 + 3: ("disconnected", "the node's triangles are not one connected patch"),
    16 + 4: ("no_boundary", "the node's patch is closed: it has no boundary contour"),
    16 + 5: ("pinched_boundary", "the node's boundary passes through a vertex twice: not a simple cycle"),
    16 + 6: ("multiple_loops", "the node's patch has holes: more than one boundary loop"),
}
# A failed cone test has no width to report: a cone that cannot be bounded below 180 degrees is
# kept as the full cone (NormalCone::full), whatever its normals' real spread; merged bottom-up
# from the children's cones (Sec. 3.6), the bound can be looser than the normals (a node whose
# normals span 156 degrees can fail), so the sentence says "could not be bounded", not "is wide".
CONE_TOO_WIDE = ("cone_too_wide", "its normal cone could not be bounded below 180 degrees (Alg. 2 line 5: the "
                                  "cone merged from its children's may be wider than its normals' real spread), so "
                                  "its normals may point to both sides and the contour test is not tried")


def _reason(code) -> tuple:
    """REASONS[code], or a ValueError naming `code` (a contour event's reason is one of them)."""
    try:
        return REASONS[operator.index(code)]  # integers only: int(1.5) read code 1.5 as 1
    except (KeyError, TypeError):
        raise ValueError(f"code: expected a contour verdict code in {sorted(REASONS)}, got {code!r}") from None


def reason_name(code: int) -> str:
    return _reason(code)[0]


# A pass by the simplicity test (the contour event's `simple`): reason 0, in other words. "nc" runs
# it after Alg. 1 failed with the mean (kernel, ray: that attempt), or first on a node it proved when
# the node was last tested (kernel, ray: NaN, as no kernel point was tried).
PASSED_SIMPLE = ("passed", "the contour projects to a simple polygon (no two edges meet): no self-collision, culled")
PASSED_SIMPLE_AFTER_STAR = ("passed", "the contour is not star-shaped from its kernel point, but it projects to a "
                                      "simple polygon (no two edges meet): no self-collision, culled")


def explain(code: int, edge: int = -1, crossings: int = 0, simple: bool = False, star_tried: bool = True) -> str:
    """The sentence for a contour verdict. simple: passed by the simplicity test; star_tried: Alg. 1
    failed before it (the event's kernel point is finite)."""
    sentence = _reason(code)[1]
    if operator.index(code) == 0 and simple:
        return (PASSED_SIMPLE_AFTER_STAR if star_tried else PASSED_SIMPLE)[1]
    named = {}
    for name, value in (("edge", edge), ("crossings", crossings)):
        try:
            named[name] = operator.index(value)
        except TypeError:
            raise ValueError(f"{name}: expected an integer, got {value!r}") from None
    return sentence.format(**named)


class Trace:
    """Events of one traced query: `trace.cone["axis"]`, `trace.contour["reason"]`, ..."""

    def __init__(self, raw: dict, positions: tuple, bvh: str | None = None):
        # The query's positions, copied: (V,) for DCD, (V0, V1) for CCD; what the events were
        # computed from (normal_spread reads them to say why a cone failed).
        self.positions = positions
        # The fingerprint of the BVH whose node ids the events name (SelfCollider.bvh_digest).
        self.bvh = bvh
        self.cone = {f.name: raw["cone_" + f.name] for f in EVENT_KINDS["cone"].fields}
        self.contour = {f.name: raw["contour_" + f.name] for f in EVENT_KINDS["contour"].fields}
        self.level = {"pairs": raw["level_pairs"], "overlaps": raw["level_overlaps"]}
        self.front = {f.name: raw["front_" + f.name] for f in EVENT_KINDS["front"].fields}
        self.elementary = {"pair": raw["elementary_pair"], "result": raw["elementary_result"]}
        self.vf = {"pair": raw["vf_pair"], "result": raw["vf_result"]}
        self.ee = {"pair": raw["ee_pair"], "result": raw["ee_result"]}
        for kind in EVENT_KINDS:
            table = getattr(self, kind)
            for f in EVENT_KINDS[kind].fields:
                a = table[f.name]
                assert a.dtype == np.dtype(f.dtype) and a.shape[1:] == f.shape, (kind, f.name, a.dtype, a.shape)

    def culled_nodes(self) -> np.ndarray:
        """Nodes culled by the normal cone + contour test."""
        return self.contour["node"][self.contour["reason"] == 0]

    def failed_nodes(self) -> dict[str, np.ndarray]:
        """Nodes that were not culled, by reason (cone too wide, or a contour reason)."""
        out = {"cone_too_wide": self.cone["node"][~self.cone["bounded"]]}
        for code in np.unique(self.contour["reason"]):
            if code != 0:
                out[reason_name(code)] = self.contour["node"][self.contour["reason"] == code]
        return out

    def counts(self) -> dict[str, int]:
        c = {"cone_tests": len(self.cone["node"]), "cone_passed": int(self.cone["bounded"].sum())}
        if len(self.vf["result"]) or len(self.ee["result"]):
            c["vf_tests"], c["ee_tests"] = len(self.vf["result"]), len(self.ee["result"])
            c["vf_contacts"], c["ee_contacts"] = int(self.vf["result"].sum()), int(self.ee["result"].sum())
        else:
            c["elementary_tests"] = len(self.elementary["result"])
            c["colliding_pairs"] = int(self.elementary["result"].sum())
        r = self.contour["reason"]
        c["contour_ineligible"] = int((r >= 16).sum())
        c["contour_tests"] = int((r < 16).sum())
        c["contour_passed"] = int((r == 0).sum())
        c["contour_failed"] = int(((r > 0) & (r < 16)).sum())
        return c
