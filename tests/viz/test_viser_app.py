"""The viser app's server side (no browser): the front-load colouring."""

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
