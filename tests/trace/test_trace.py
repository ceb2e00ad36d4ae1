"""Trace consistency: the events of a traced query agree with its stats and with the oracle,
and tracing never changes the result."""

import numpy as np
import pytest

import conecull
import meshcases
from conecull.trace import EVENT_KINDS, REASONS, Trace, explain, reason_name
from oracle import brute_force_pairs

NAMES = ["crumple_medium_s2", "fold_zfold_240_back150_g12", "sphere_twist_strong", "holes_zfold_200",
         "components_three_crossing", "fins_strip_pierced_by_flap", "offset_1e6_crumpled", "bent_sheet_parabola",
         "fan_ring_winds_twice_helix", "sliver_midpoint_bent"]


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.parametrize("leaf_size", [1, 2])
def test_trace_matches_stats_and_oracle(name, leaf_size):
    _, F, V = meshcases.case(name)
    mesh = conecull.Mesh(F, n_vertices=len(V))
    col = conecull.SelfCollider(mesh, method="nc", leaf_size=leaf_size)
    plain = col.dcd(V)
    res = col.dcd(V, trace=True)
    assert plain.trace is None and isinstance(res.trace, Trace)
    assert np.array_equal(plain.pairs, res.pairs)  # tracing never changes the answer
    for k, v in res.trace.counts().items():
        assert res.stats[k] == v, k
    tr = res.trace
    assert int(tr.level["pairs"].sum()) == res.stats["bv_tests"]
    assert int(tr.level["overlaps"].sum()) <= res.stats["bv_tests"]
    # elementary events are exactly the candidate pairs, with the exact results
    hits = {tuple(p) for p in tr.elementary["pair"][tr.elementary["result"]].tolist()}
    assert hits == {tuple(p) for p in res.pairs.tolist()}
    # every culled node has no colliding pair beneath it (the oracle decides)
    truth = brute_force_pairs(F, V)
    bvh = col.bvh_arrays()
    for node in tr.culled_nodes():
        tris = set(bvh["order"][bvh["begin"][node] : bvh["end"][node]].tolist())
        assert not any(i in tris and j in tris for i, j in truth), f"{name}: culled node {node} hides a collision"
    # DCD has one pose: the kernel point at its "end" is the kernel point (NaN both where the
    # simplicity test ran first, as on nodes it proved in the untraced query before: no kernel point)
    tested = tr.contour["reason"] < 16
    assert np.array_equal(tr.contour["kernel_end"][tested], tr.contour["kernel"][tested], equal_nan=True)
    no_kernel = np.isnan(tr.contour["kernel"]).any(axis=1)
    assert (tr.contour["simple"][no_kernel] & (tr.contour["reason"][no_kernel] == 0)).all()
    # every reason code is known and explainable
    for code, edge, cr in zip(tr.contour["reason"], tr.contour["edge"], tr.contour["crossings"]):
        assert int(code) in REASONS and explain(code, edge, cr)
    # schema: every declared field is present with its declared shape
    for kind, spec in EVENT_KINDS.items():
        table = getattr(tr, kind)
        assert set(table) == {f.name for f in spec.fields}


def test_trace_aabb_has_no_cone_events():
    _, F, V = meshcases.case("crumple_medium_s2")
    res = conecull.SelfCollider(conecull.Mesh(F, n_vertices=len(V)), method="aabb").dcd(V, trace=True)
    assert len(res.trace.cone["node"]) == 0 and len(res.trace.contour["node"]) == 0
    assert len(res.trace.elementary["pair"]) == res.stats["elementary_tests"]


@pytest.mark.parametrize("code", [99, -1, "x", None, 1.5e300, 1.5, np.float64(2.0)])
def test_unknown_verdict_codes_are_named(code):
    # a float is no code, even a whole one (1.5 was read as code 1)
    with pytest.raises(ValueError, match=r"code: expected a contour verdict code in \[0, 1, "):
        explain(code)
    with pytest.raises(ValueError, match=r"code: expected a contour verdict code"):
        reason_name(code)


def test_explain_names_a_bad_edge_or_crossing_count():
    assert explain(np.int8(2), edge=np.int64(3)) == explain(2, edge=3)  # numpy integers are integers
    for kw in ({"edge": "x"}, {"crossings": 1.5}):
        with pytest.raises(ValueError, match=rf"{next(iter(kw))}: expected an integer, got"):
            explain(2, **kw)


@pytest.mark.parametrize("method", ["nc+front", "aabb+front"])
@pytest.mark.parametrize("ccd", [False, True])
def test_front_events_match_the_front(method, ccd):
    """One front event per FrontTracking(Front_N) (Alg. 4 line 13): its size before is what the
    last query left (front_arrays before), after is what this one keeps (front_arrays after), the
    sizes kept add up to stats["front_entries"], the resting ones count stats["front_rested"].
    The fold is queried in order, then its last frame again and again, so that fronts are
    resumed, built from the top, churn and rest."""
    from conecull.datasets.inputs import load_sequence
    from conecull.trace import FRONT_MODES

    F, P = load_sequence("fold")
    col = conecull.SelfCollider(conecull.Mesh(F), method=method)
    col.dcd(P[0])
    kind = "ccd" if ccd else "dcd"
    seen = set()
    for k in list(range(1, 30)) + [29, 28, 29, 28, 29]:
        before = col.front_arrays(kind)["count"]
        res = col.ccd(P[k - 1], P[k], trace=True) if ccd else col.dcd(P[k], trace=True)
        fr, after = res.trace.front, col.front_arrays(kind)["count"]
        assert len(np.unique(fr["node"])) == len(fr["node"])  # once per node
        assert np.array_equal(fr["before"], before[fr["node"]])
        assert np.array_equal(fr["after"], after[fr["node"]])
        assert int(fr["after"].sum()) == res.stats["front_entries"]
        assert int((fr["mode"] == 2).sum()) == res.stats["front_rested"]
        assert ((fr["after"] == 0) == np.isin(fr["mode"], (2, 3))).all()  # a kept cut is never empty
        assert (fr["before"][fr["mode"] == 1] == 0).all() and (fr["before"][fr["mode"] == 0] > 0).all()
        assert 0 <= int(fr["box_tests"].sum()) <= res.stats["bv_tests"]
        seen |= set(fr["mode"].tolist())
    assert {0, 1} <= seen and set(seen) <= set(FRONT_MODES)
    assert ccd or seen == {0, 1, 2, 3}  # DCD: repeating the last frames makes fronts churn, then rest


def test_front_events_only_with_a_front():
    _, F, V = meshcases.case("crumple_medium_s2")
    res = conecull.SelfCollider(conecull.Mesh(F, n_vertices=len(V)), method="nc").dcd(V, trace=True)
    assert all(len(v) == 0 for v in res.trace.front.values())
