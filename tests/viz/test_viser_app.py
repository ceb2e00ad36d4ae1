"""The viser app's server side (no browser): the front-load colouring, the methods table, the
bounded inputs, the per-node drawings, the legend."""

import numpy as np

from ports import free_port


def test_viewer_colours_by_front_load():
    """Server side only: with a front method, "mesh colour: front load" paints each face by the
    front entries reaching it; with a method without a front it says so and keeps the verdicts."""
    from conecull.datasets.inputs import load_sequence
    from conecull.viz import layers as L
    from conecull.viz.viser_app import ViewerApp

    F, frames = load_sequence("fold")
    app = ViewerApp(F, frames, port=free_port(), method="nc+front")
    try:
        app.frame.value = 29
        app.colour_by.value = "front load"
        app.update()
        assert np.array_equal(app.face_colors, L.front_colors(app.col.front_load()))
        assert "front entries" in app.stats_md.content and len(np.unique(app.face_colors, axis=0)) > 3
        app.method.value = "nc"
        app.update()
        assert "needs a +front method" in app.stats_md.content
        assert np.array_equal(app.face_colors, L.compute(app.col, app.faces, app.V, app.res).face_colors)
    finally:
        app.close()


def test_viewer_refuses_bad_arguments_before_serving():
    """A bad method, port or host is a ValueError naming it, raised before any server starts:
    viser's server thread would die (port > 65535) or retry for ever (an address not of this
    machine) while the caller waits."""
    import pytest

    from conecull.datasets.generated import folding_sheet
    from conecull.viz.viser_app import ViewerApp

    F, P = folding_sheet(50, 2)
    for kwargs, match in (({"method": "xx"}, "method: expected one of aabb, nc"),
                          ({"port": 70000}, r"port: expected a TCP port in \[0, 65535\]"),
                          ({"port": -1}, r"port: expected a TCP port in \[0, 65535\]"),
                          ({"port": "80"}, r"port: expected a TCP port"),
                          ({"host": "192.0.2.1"}, "host: cannot listen on '192.0.2.1'"),  # TEST-NET: never ours
                          ({"host": ""}, "host: expected a host name or IP address")):
        with pytest.raises(ValueError, match=match):
            ViewerApp(F, P, **{"port": free_port(), **kwargs})
    with pytest.raises(ValueError, match="frames: expected a sequence of frames"):
        ViewerApp(F, P[0], port=free_port())
    with pytest.raises(ValueError, match="faces: no triangles to view"):  # was NumPy's "zero-size array"
        ViewerApp(np.zeros((0, 3), int), np.zeros((2, 3, 3)), port=free_port())


def test_printed_address_is_the_served_host(capsys, monkeypatch):
    from conecull.viz import viser_app

    class App:
        host, port = "127.0.0.2", 1234

        def close(self):
            pass

    monkeypatch.setattr(viser_app.time, "sleep", lambda _: (_ for _ in ()).throw(KeyboardInterrupt))
    viser_app.serve_forever(App())
    assert "open http://127.0.0.2:1234 " in capsys.readouterr().out
    App.host = "0.0.0.0"
    viser_app.serve_forever(App())
    out = capsys.readouterr().out
    assert "open http://127.0.0.1:1234 (Ctrl+C to stop, listening on all interfaces (0.0.0.0))" in out


def test_viewer_compares_methods_at_the_frame():
    """"compare all methods" fills a table with every method's counters at the shown frame, as
    an untraced query of that method on a fresh collider fed the same frames gives them; off,
    the table is empty."""
    import conecull
    from conecull.datasets.inputs import load_sequence
    from conecull.viz.viser_app import ViewerApp

    F, frames = load_sequence("fold")
    app = ViewerApp(F, frames, port=free_port(), method="nc")
    try:
        app.frame.value = 28
        app.update()
        assert app.compare_md.content == ""
        app.compare.value = True
        app.update()
        rows = [r.split("|")[1:-1] for r in app.compare_md.content.splitlines()[2:]]
        assert [r[0].strip() for r in rows] == list(conecull.METHODS)
        for r in rows:
            col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=frames.shape[1]), method=r[0].strip())
            col.dcd(frames[0])
            s = col.dcd(frames[28]).stats
            assert [int(r[1]), int(r[2]), int(r[4])] == [s["contour_tests"], s["contour_passed"], s["elementary_tests"]]
            assert (float(r[3]) > 0) == (s["contour_tests"] > 0) and float(r[5]) > 0
        assert len({r[1] for r in rows}) > 1  # the methods really differ
    finally:
        app.close()


def test_viewer_says_what_a_clicked_colliding_triangle_collides_with():
    """Clicking a colliding triangle names its partners and why no node holding both was culled;
    the node at the chosen depth alone (here culled: the pair lies across two nodes) follows. The
    triangle and its partners are outlined on the mesh until the next click or frame."""
    from conecull.datasets.inputs import load_sequence
    from conecull.viz.viser_app import ViewerApp

    F, frames = load_sequence("fold")
    app = ViewerApp(F, frames, port=free_port())
    try:
        app.frame.value = 28
        i, j = (int(x) for x in app.res.pairs[0])
        app.select_face(i)
        text = app.panel.content
        assert f"triangle {i} takes part in" in text and f"triangles {i} and {j} intersect" in text
        assert "was not culled" in text and "verdict:" in text
        # ... and marks them on the mesh: the clicked triangle and its partners, outlined on both
        # sides of each face (6 segments a triangle).
        partners = np.setdiff1d(app.res.pairs[(app.res.pairs == i).any(axis=1)], [i])
        assert j in partners
        assert f"outlined on the mesh: it in blue, the {len(partners)} it collides with in black" in text
        for name, faces in (("/selected/triangle", [i]), ("/selected/partners", partners)):
            pts = app.server.scene._handle_from_node_name[name].points
            assert pts.shape == (6 * len(faces), 2, 3)
            corners = frames[28][F[faces]].reshape(-1, 3)
            assert np.abs(pts.reshape(-1, 1, 3) - corners[None]).sum(axis=2).min(axis=1).max() < 1e-2
        partner_handle = app.server.scene._handle_from_node_name["/selected/partners"]
        app.select_face(int(np.setdiff1d(np.arange(len(F)), app.res.pairs)[0]))
        assert "takes part in" not in app.panel.content
        assert partner_handle._impl.removed and "/selected/partners" not in app.selection
        assert "/selected/triangle" in app.selection
        app.select_face(i)
        app.frame.value = 0  # no collisions there: the partners' outlines go
        assert "/selected/partners" not in app.selection and _node(app, "/selected/partners") is None
    finally:
        app.close()


def test_viewer_shows_an_error_and_keeps_playing(monkeypatch):
    """An error while drawing a frame (a bug) is shown in the stats panel; the controls and the
    player go on (it used to end play for good). The baselines' own contour verdicts (sct's on
    crumple from its first frame) are drawn: they once had no colour and raised."""
    import time

    from conecull.datasets.inputs import load_sequence
    from conecull.viz import viser_app
    from conecull.viz.viser_app import ViewerApp

    F, frames = load_sequence("crumple")
    app = ViewerApp(F, frames, port=free_port(), method="sct")
    try:
        assert 6 in app.res.trace.contour["reason"]  # sct's no_kernel_on_search_line, drawn
        real = viser_app.L.compute
        monkeypatch.setattr(viser_app.L, "compute", lambda *a: (_ for _ in ()).throw(RuntimeError("boom")))
        app.frame.value = 3
        assert "error while drawing this frame** (RuntimeError: boom)" in app.stats_md.content
        monkeypatch.setattr(viser_app.L, "compute", real)
        app.play.value = True
        start = int(app.frame.value)
        deadline = time.time() + 10
        while (int(app.frame.value) == start or "error" in app.stats_md.content) and time.time() < deadline:
            time.sleep(0.05)  # the value changes before its callback has drawn the frame
        assert int(app.frame.value) != start and "error" not in app.stats_md.content
    finally:
        app.close()


def _fold_app(method="nc"):
    from conecull.datasets.inputs import load_sequence
    from conecull.viz.viser_app import ViewerApp

    F, frames = load_sequence("fold")
    return ViewerApp(F, frames, port=free_port(), method=method), F, frames


def test_frame_and_depth_inputs_are_bounded():
    """The number boxes are bounded (min/max) and a value outside them, which a slider's number box
    sends anyway (each keystroke: 99, -1), is set back to the nearest valid one, said with the
    valid range in the stats panel; it never reaches indexing (99 raised IndexError, -1 showed
    frame 29 labelled frame -1)."""
    app, F, frames = _fold_app()
    try:
        assert (app.frame.min, app.frame.max) == (0, len(frames) - 1) == (0, 29)
        assert (app.depth.min, app.depth.max) == (0, app.max_depth)
        for typed, shown in ((99, 29), (-1, 0), (255, 29)):
            app.frame.value = typed
            assert int(app.frame.value) == shown and app.k == shown and np.array_equal(app.V, frames[shown])
            content = app.stats_md.content
            assert f"frame {typed} refused**: frames are 0..29; showing {shown}" in content, content
            assert f"frame **{shown}**" in content and "error" not in content
        app.frame.value = 5
        assert "refused" not in app.stats_md.content  # said once
        for typed, shown in ((99, app.max_depth), (-3, 0)):
            app.depth.value = typed
            assert int(app.depth.value) == shown == app.d
            assert f"BVH depth {typed} refused**: BVH depths are 0..{app.max_depth}" in app.stats_md.content
        # A value that reached the handle without its setter (as a client's update does, before
        # the callbacks run) is refused by update() itself.
        app.frame._impl.value = -1
        app.update()
        assert int(app.frame.value) == 0 and app.k == 0 and "frame -1 refused" in app.stats_md.content
    finally:
        app.close()


def _node(app, name):
    handle = app.server.scene._handle_from_node_name.get(name)
    return None if handle is None or handle._impl.removed else handle


def test_per_node_drawings_follow_method_frame_and_depth():
    """The selected node's cone arrow and contour are redrawn for each query and removed where the
    shown method has none: a method without normal cones (aabb, aabb+front) left nc's arrow on
    screen while its panel said it uses no normal cones."""
    app, F, frames = _fold_app()
    try:
        app.depth.value = 0
        app.select_face(0)
        arrow = _node(app, "/selected/cone")
        assert arrow is not None and _node(app, "/selected/contour") is not None
        for method in ("aabb", "aabb+front"):
            app.method.value = method
            assert "uses no normal cones" in app.panel.content
            assert _node(app, "/selected/cone") is None, method
        app.method.value = "nc"
        assert _node(app, "/selected/cone") is not None and _node(app, "/selected/cone") is not arrow
        app.frame.value = 28
        app.depth.value = app.max_depth  # a leaf: one triangle, no contour of its own drawn twice
        assert set(app.selection) <= {"/selected/cone", "/selected/contour", "/selected/triangle", "/selected/partners"}
        assert all(_node(app, n) is h for n, h in app.selection.items())
    finally:
        app.close()


def test_mesh_has_no_hover_outline_and_both_sides():
    """The yellow flap: viser outlines a mesh with a click binding while the pointer is over it, in
    yellow (0xfbff00), by drawing the mesh's back faces pushed out; the GLB has no material, so the
    mesh's own back faces are not drawn and a folded flap seen from below turned all yellow (until
    the mesh was re-added, which reset the hover). The mesh has no click binding now (a scene click
    and our ray test select), and each face is drawn with both windings."""
    import io

    import trimesh

    app, F, frames = _fold_app()
    try:
        app.frame.value = 28
        mesh = _node(app, "/mesh")
        assert not mesh._impl.click_cb
        tm = trimesh.load(io.BytesIO(mesh._impl.props.glb_data), file_type="glb", force="mesh", process=False)
        assert len(tm.faces) == 2 * len(F)
        tri = tm.vertices[tm.faces]
        assert np.allclose(tri[len(F):], tri[: len(F), ::-1], atol=1e-6)  # the same faces, reversed
        # A click in the scene selects the triangle under it.
        clicks = [e.callback for e in app.server.scene._scene_pointer_cb if e.event_type == "click"]
        assert len(clicks) == 1
        face = 100
        c = frames[28][F[face]].mean(axis=0)
        n = np.cross(*(frames[28][F[face]][1:] - frames[28][F[face]][0]))
        origin = c + 0.01 * n / np.linalg.norm(n)
        from types import SimpleNamespace
        clicks[0](SimpleNamespace(ray_origin=tuple(origin), ray_direction=tuple(c - origin)))
        assert app.selected_face == face and app.panel.content.startswith(f"triangle {face} → node")
    finally:
        app.close()


def test_legend_matches_the_colouring():
    """Front-load colouring shows its own key (the load ramp at this frame), not the verdicts'
    (whose yellow is "cone too wide"); back to verdicts, or a method without a front, the
    verdict key."""
    from conecull.viz import layers as L

    app, F, frames = _fold_app("nc+front")
    try:
        app.frame.value = 29
        assert "cone too wide" in app.legend_md.content
        app.colour_by.value = "front load"
        top = int(app.col.front_load().max())
        assert "cone too wide" not in app.legend_md.content and "no front entry" in app.legend_md.content
        assert f"{top} entries (the most now)" in app.legend_md.content
        # every key colour is one the mesh can show for that load
        for load, (_, rgb) in zip([0, 1], L.front_legend(app.col.front_load())):
            assert tuple(L.front_colors(np.array([load, top]))[0]) == rgb
        app.method.value = "nc"
        assert "cone too wide" in app.legend_md.content and "no front entry" not in app.legend_md.content
    finally:
        app.close()


def test_front_counters_say_which_frame_the_front_came_from():
    """A front method's counters (+added / -removed) are relative to the front its previous query
    left: the stats say from which frame, and they are those of a fresh collider fed the same
    frames; the compare table's front rows say whence their front came, a re-query of the same
    pose for the shown method."""
    import conecull

    app, F, frames = _fold_app("nc+front")
    try:
        app.frame.value = 28
        assert "since frame 0, the front is kept between queries" in app.stats_md.content
        app.frame.value = 29
        content = app.stats_md.content
        assert "since frame 28, the front is kept between queries" in content
        col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=frames.shape[1]), method="nc+front")
        for k in (0, 0, 28):
            col.dcd(frames[k])
        s = col.dcd(frames[29]).stats
        assert f"(+{s['front_added']} / -{s['front_removed']} since frame 28" in content
        app.compare.value = True
        rows = {r.split("|")[1].strip(): r.split("|")[-2].strip() for r in app.compare_md.content.splitlines()[2:]}
        assert rows["nc+front"] == "frame 29: re-query of this pose" and rows["aabb+front"] == "frame 0"
        assert rows["nc"] == rows["sct"] == "—"
        app.frame.value = 27
        assert "since frame 29" in app.stats_md.content  # the compare table's re-query at 29 was the last
        rows = {r.split("|")[1].strip(): r.split("|")[-2].strip() for r in app.compare_md.content.splitlines()[2:]}
        assert rows["aabb+front"] == "frame 29"
    finally:
        app.close()


def test_viewer_shows_ccd_steps():
    """query "CCD": frame k shows the step from frame k to k + 1 at its end pose, with the step's
    contacts (as a fresh collider finds them), a clicked triangle's partners (every triangle on
    the other side of a contact of its vertices, edges or face), no step after the last frame,
    and DCD-only sct refused."""
    import conecull
    from conecull.datasets.inputs import load_sequence
    from conecull.viz.viser_app import CCD, DCD, ViewerApp

    F, frames = load_sequence("fold")
    app = ViewerApp(F, frames, port=free_port(), method="nc", ccd=True)
    try:
        assert app.query.value == CCD
        app.method.value = "nc+front"  # its first CCD query: its front came from no earlier one (was "frame 0")
        assert "since no earlier CCD query: built from the top" in app.stats_md.content
        app.method.value = "nc"
        app.frame.value = 27
        fresh = conecull.SelfCollider(conecull.Mesh(F), method="nc")
        fresh.dcd(frames[0])
        want = fresh.ccd(frames[27], frames[28])
        assert np.array_equal(app.res.vf, want.vf) and np.array_equal(app.res.ee, want.ee) and len(want.vf)
        assert np.array_equal(app.V, frames[28])
        assert (f"step **27 → 28** (drawn at frame 28)" in app.stats_md.content
                and f"contacts **{len(want.vf)} vertex-face, {len(want.ee)} edge-edge**" in app.stats_md.content)
        # Partners, from the contacts as pairs of triangles (around a vertex x a face, around an edge x around an edge).
        mesh = fresh.mesh
        voff, vids = mesh.vertex_faces
        eoff, eids = mesh.edge_faces
        pairs = {(int(t), int(f)) for v, f in want.vf for t in vids[voff[v]:voff[v + 1]]}
        pairs |= {(int(s), int(t)) for a, b in want.ee for s in eids[eoff[a]:eoff[a + 1]] for t in eids[eoff[b]:eoff[b + 1]]}
        face = int(want.vf[0][1])
        partners = sorted({q for p in pairs if face in p for q in p if q != face})
        listed = {int(t) for t in pairs_faces(pairs)}
        shown = app.stats_md.content.split("colliding triangles: ")[1].split(" (")[0]
        assert f"({len(listed)} in all)" in app.stats_md.content and shown.startswith(
            ", ".join(str(t) for t in sorted(listed)[:12]))
        app.pick.value = face  # by id, as a click would (a contact can lie out of a click's reach)
        assert f"the {len(partners)} it collides with in black" in app.panel.content
        assert f"collides with triangles {', '.join(map(str, partners))}" in app.panel.content
        assert "(step 27 → 28)" in app.panel.content and "touches triangle" in app.panel.content
        drawn = app.selection["/selected/partners"]
        assert len(drawn.points) == 6 * len(partners)
        app.frame.value = 29  # the last frame starts no step
        assert app.frame.value == 28 and "refused" in app.stats_md.content
        app.method.value = "sct"
        assert app.method.value == "nc" and "sct is a discrete (DCD) method" in app.stats_md.content
        app.compare.value = True
        assert "| sct |" not in app.compare_md.content and "| cbc |" in app.compare_md.content
        app.query.value = DCD
        assert "frame **28**" in app.stats_md.content and "colliding pairs" in app.stats_md.content
    finally:
        app.close()


def pairs_faces(pairs):
    return {t for p in pairs for t in p}


def test_viewer_refuses_ccd_it_cannot_show():
    import pytest

    from conecull.app.cli import main
    from conecull.datasets.generated import folding_sheet
    from conecull.viz.viser_app import ViewerApp

    F, P = folding_sheet(50, 2)
    with pytest.raises(ValueError, match="method: 'sct' is a discrete"):
        ViewerApp(F, P, port=free_port(), method="sct", ccd=True)
    with pytest.raises(ValueError, match="ccd: a CCD step needs two frames, the sequence has 1"):
        ViewerApp(F, P[:1], port=free_port(), ccd=True)
    assert main(["view", "--ccd", "--method", "sct", "--port", str(free_port())]) == 2


def test_culled_patches_and_cone_axes_are_drawn():
    """The culled nodes' contours (one closed loop each) are drawn as segments, and cone arrows
    for the nodes whose cone was bounded (culled ones included): a cone too wide has no axis (its
    arrow had zero length)."""
    from conecull.viz import layers as L

    app, F, frames = _fold_app()
    try:
        app.frame.value = 28
        app.show_cones.value = True
        app.update()
        lay = L.compute(app.col, app.faces, app.V, app.res)
        culled = _node(app, "/culled")
        assert culled is not None and culled.visible
        points = np.asarray(culled._impl.props.points)
        assert len(lay.culled_strips) > 3 and len(points) == sum(len(s) - 1 for s in lay.culled_strips)
        arrows = _node(app, "/cones")
        assert arrows is not None
        assert len(np.asarray(arrows._impl.props.points)) == len(lay.axis_nodes) == app.res.stats["cone_passed"]
        app.show_culled.value = False
        assert not _node(app, "/culled").visible
        # the nodes not culled, as boxes coloured by verdict (hidden until asked for)
        boxes = _node(app, "/failed_nodes")
        assert boxes is not None and not boxes.visible
        app.show_failed.value = True
        boxes = _node(app, "/failed_nodes")
        s = app.res.stats
        n = s["cone_tests"] - s["cone_passed"] + s["contour_failed"] + s["contour_ineligible"]
        assert boxes.visible and n > 0 and len(np.asarray(boxes._impl.props.points)) == 12 * n
        colors = np.asarray(boxes._impl.props.colors).reshape(12, n, 2, 3)
        assert (colors == lay.node_colors[None, :, None, :]).all()
    finally:
        app.close()


def test_no_arrow_for_a_selected_node_whose_cone_is_too_wide():
    """A cone too wide has no axis (zero): its node gets no arrow (it drew a zero-length blob)."""
    app, F, frames = _fold_app()
    try:
        app.frame.value = 28
        app.depth.value = 1
        app.select_face(12)
        node = [n for n in app.panel.content.split("node **")[1:2]][0].split("**")[0]
        assert not np.any(app.col.cone_arrays()["axis"][int(node)])  # this node's cone is too wide
        assert _node(app, "/selected/cone") is None and _node(app, "/selected/contour") is not None
        app.depth.value = app.max_depth  # a leaf with a bounded cone: its arrow
        app.select_face(12)
        assert _node(app, "/selected/cone") is not None
    finally:
        app.close()


def test_camera_and_arrows_follow_the_meshs_size():
    """A mesh in millimetres: the camera starts outside its box, looking at its middle, and the
    arrows' radii scale with it (fixed radii were hairlines, the camera started inside the mesh)."""
    from types import SimpleNamespace

    from conecull.datasets.inputs import load_sequence
    from conecull.viz.viser_app import ViewerApp

    F, frames = load_sequence("fold")
    radii = {}
    for scale in (1.0, 1000.0):
        app = ViewerApp(F, frames * scale, port=free_port())
        try:
            client = SimpleNamespace(camera=SimpleNamespace())
            app._frame_camera(client)
            lo, hi = (frames * scale).min(axis=(0, 1)), (frames * scale).max(axis=(0, 1))
            assert np.allclose(client.camera.look_at, 0.5 * (lo + hi))
            pos = np.array(client.camera.position)
            assert ((pos < lo) | (pos > hi)).any()  # outside the box
            app.frame.value = 28
            app.show_cones.value = True
            radii[scale] = _node(app, "/cones")._impl.props.shaft_radius
        finally:
            app.close()
    assert np.isclose(radii[1000.0], 1000.0 * radii[1.0])
