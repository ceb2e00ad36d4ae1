"""CCD traces: events agree with the stats and results, no culled node hides a contact (the
exact brute force decides), and tracing never changes the result; CCD recordings read back."""

import numpy as np
import pytest

import conecull
from ccd_brute_force import brute_force_ccd, generated_steps

STEPS = generated_steps()


@pytest.mark.parametrize("name,F,V0,V1", STEPS, ids=[s[0] for s in STEPS])
def test_ccd_trace_consistency(name, F, V0, V1):
    mesh = conecull.Mesh(F, n_vertices=len(V0))
    col = conecull.SelfCollider(mesh, method="nc")
    plain = col.ccd(V0, V1)
    res = col.ccd(V0, V1, trace=True)
    assert plain.trace is None
    assert np.array_equal(plain.vf, res.vf) and np.array_equal(plain.ee, res.ee)
    tr = res.trace
    for k, v in tr.counts().items():
        assert res.stats[k] == v, k
    assert {tuple(p) for p in tr.vf["pair"][tr.vf["result"]].tolist()} == {tuple(p) for p in res.vf.tolist()}
    assert {tuple(p) for p in tr.ee["pair"][tr.ee["result"]].tolist()} == {tuple(p) for p in res.ee.tolist()}
    vf_true, ee_true = brute_force_ccd(F, V0, V1, "exact")
    bvh = col.bvh_arrays()
    E = mesh.edges
    for node in tr.culled_nodes():
        tris = bvh["order"][bvh["begin"][node] : bvh["end"][node]]
        verts = set(F[tris].ravel().tolist())
        tri_set = set(tris.tolist())
        edges = {i for i, (a, b) in enumerate(E.tolist()) if a in verts and b in verts}
        assert not any(v in verts and f in tri_set for v, f in vf_true), f"{name}: culled node {node} hides a VF contact"
        assert not any(a in edges and b in edges for a, b in ee_true), f"{name}: culled node {node} hides an EE contact"


def test_ccd_trace_kernel_moves_with_the_contour():
    """Each CCD contour event's kernel point moves over the step: for a mesh translated by d, from
    the point tested at t = 0 to that point + d (the contour's mean moves by d), and it is the
    verdict of contour_test_ccd on the node's loop."""
    from conecull._core import ccd as C

    name, F, V0, _ = STEPS[0]
    d = np.array([0.75, -0.5, 0.25])
    V1 = V0 + d
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=len(V0)), method="nc")
    col.ccd(V0, V1)
    tr = col.ccd(V0, V1, trace=True).trace
    loops, axes = col.contour_arrays(), col.cone_arrays()["axis"]
    tested = np.flatnonzero(tr.contour["reason"] < 16)
    assert len(tested) > 0
    np.testing.assert_allclose(tr.contour["kernel_end"][tested] - tr.contour["kernel"][tested], np.tile(d, (len(tested), 1)),
                               atol=1e-12)
    for i in tested[:20]:
        node = int(tr.contour["node"][i])
        loop = loops["vertices"][loops["offsets"][node] : loops["offsets"][node + 1]].astype(np.int32)
        v = C.contour_test_ccd(loop, V0, V1, axes[node])
        assert v["kernel"] == tuple(tr.contour["kernel"][i]) and v["kernel_end"] == tuple(tr.contour["kernel_end"][i])
        assert v["reason"] == int(tr.contour["reason"][i])


def test_ccd_recording(tmp_path):
    from conecull.datasets.inputs import load_sequence
    from conecull.viz.rerun_sink import record
    from rrd_helpers import rows_by_frame

    F, frames = load_sequence("fold")
    path = str(tmp_path / "ccd.rrd")
    stats = record(path, F, frames, frame_range=range(24, 30), ccd=True, recording_id="ccd")
    assert len(stats) == 5  # steps 24->25 ... 28->29
    pts = rows_by_frame(path, "/scene/contacts/vf", "Points3D:positions")
    assert sorted(pts) == list(range(24, 29))
    for i, k in enumerate(range(24, 29)):
        assert len(pts[k] or []) == stats[i]["vf_contacts"]
    assert any(s["vf_contacts"] + s["ee_contacts"] > 0 for s in stats)
