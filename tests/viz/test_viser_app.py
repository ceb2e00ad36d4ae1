"""The viser app's server side (no browser): the front-load colouring, the methods table."""

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
    the node at the chosen depth alone (here culled: the pair lies across two nodes) follows."""
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
        app.select_face(int(np.setdiff1d(np.arange(len(F)), app.res.pairs)[0]))
        assert "takes part in" not in app.panel.content
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
