"""Screenshots of both viewers for the README, with the same headless tooling as the tests
(Debian chromium driven by Playwright): `python -m conecull.viz.screenshots OUTDIR`."""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import tempfile
import time

import numpy as np

ARGS = ["--no-sandbox", "--disable-quic", "--no-first-run", "--disable-background-networking",
        "--disable-component-update", "--disable-sync"]
VIEWPORT = {"width": 960, "height": 560}


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _browser(p):
    exe = shutil.which("chromium") or shutil.which("chromium-browser")
    if not exe:
        raise RuntimeError("chromium not found (apt-get install chromium)")
    return p.chromium.launch_persistent_context(tempfile.mkdtemp(), executable_path=exe, headless=True, args=ARGS,
                                                viewport=VIEWPORT)


def _settled_screenshot(page, path: str, wait: float, limit: float = 240.0) -> None:
    """page's screenshot once it stops changing: after `wait` seconds, one every 3 s until two in a
    row are the same, or `limit` seconds have passed (then the last, with a warning). The web viewer
    ingests a large recording for tens of seconds while following the newest frame, so a capture
    after a fixed wait could show an earlier frame than the one logged last."""
    time.sleep(wait)
    t0, last = time.monotonic(), None
    while True:
        shot = page.screenshot()
        if shot == last:
            break
        if time.monotonic() - t0 > limit:
            print(f"warning: {path}: the view was still changing after {wait + limit:.0f} s", flush=True)
            break
        last = shot
        time.sleep(3.0)
    with open(path, "wb") as fh:
        fh.write(shot)


def rerun_screenshot(path: str, scene: str = "fold", frame: int = 24, resolution: int | None = None,
                     method: str = "nc", front_view: bool = False, wait: float = 12.0, compare: tuple = ()) -> None:
    """The rerun web viewer (served by the bundled `rerun` binary on 127.0.0.1), fed over gRPC.
    front_view: show the BVTT front on the mesh and its growth instead (a +front method).
    compare: also run these methods on each frame, as `record --compare` does, and show their
    contour-test time and contour tests instead of the stats."""
    import rerun as rr
    import rerun_cli
    from playwright.sync_api import sync_playwright

    import conecull
    from conecull.datasets.inputs import load_sequence
    from conecull.viz.compare import compared_colliders, timed_query
    from conecull.viz.rerun_sink import RerunRecorder, about_markdown, blueprint, compare_path

    web, grpc = _free_port(), _free_port()
    exe = os.path.join(os.path.dirname(rerun_cli.__file__), "rerun")
    proc = subprocess.Popen([exe, "--bind", "127.0.0.1", "--serve-web", "--web-viewer-port", str(web), "--port", str(grpc)],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        time.sleep(3)
        F, frames = load_sequence(scene, resolution=resolution)
        col = conecull.SelfCollider(conecull.Mesh(F), method=method)
        col.dcd(frames[0])
        stream = rr.RecordingStream("conecull", recording_id="screenshot")  # same logging, sent over gRPC
        stream.connect_grpc(f"rerun+http://127.0.0.1:{grpc}/proxy")
        deepest = int(col.bvh_arrays()["depth"].max())
        about = about_markdown(method, False, "exact", f"the scene `{scene}`", len(frames), range(frame + 1), len(F),
                               4, deepest, compare)
        rec = RerunRecorder(None, conecull.Mesh(F).faces, stream=stream, method=method, bvh_depth=4, deepest=deepest,
                            about=about, layout=False)
        if front_view:
            import rerun.blueprint as rrb

            rec.rec.send_blueprint(rrb.Blueprint(rrb.Horizontal(
                rrb.Spatial3DView(origin="/front", name="BVTT front on the mesh"),
                rrb.TimeSeriesView(origin="/stats/front", name="front entries, added, removed"),
                column_shares=[3, 2]), collapse_panels=True))
        elif compare:
            import rerun.blueprint as rrb

            rec.rec.send_blueprint(rrb.Blueprint(rrb.Horizontal(
                rrb.Spatial3DView(origin="/scene", name="mesh and culling"),
                rrb.Vertical(*(rrb.TimeSeriesView(origin="/stats/compare", name=title,
                                                  contents=[f"+ {compare_path(m)}/{key}" for m in compare])
                               for key, title in (("contour_ms", "contour-test ms per method"),
                                                  ("contour_tests", "contour tests per method")))),
                column_shares=[3, 2]), collapse_panels=True))
        else:
            rec.rec.send_blueprint(blueprint(method.endswith("+front")))
        others = compared_colliders(conecull.Mesh(F), compare, frames[0])
        for k in range(frame + 1):
            rec.log_frame(k, col, frames[k], col.dcd(frames[k], trace=True), previous=max(k - 1, 0))
            for m, other in others.items():
                r, ms = timed_query(other, frames[k])
                rec.log_compare(k, m, r.stats, ms)
        rec.rec.flush()
        with sync_playwright() as p:
            ctx = _browser(p)
            page = ctx.new_page()
            page.goto(f"http://127.0.0.1:{web}/?url=rerun%2Bhttp://127.0.0.1:{grpc}/proxy")
            _settled_screenshot(page, path, wait)  # the web viewer renders with software WebGL
            ctx.close()
        rec.rec.disconnect()
    finally:
        proc.terminate()
        proc.wait(10)


def viser_screenshot(path: str, scene: str = "crumple", frame: int = 20) -> None:
    from playwright.sync_api import sync_playwright

    from conecull.datasets.inputs import load_sequence
    from conecull.viz.viser_app import ViewerApp

    F, frames = load_sequence(scene)
    app = ViewerApp(F, frames, port=_free_port())
    try:
        with sync_playwright() as p:
            ctx = _browser(p)
            page = ctx.new_page()
            page.goto(f"http://127.0.0.1:{app.port}")
            page.wait_for_selector("canvas", timeout=30000)
            while not app.server.get_clients():
                time.sleep(0.1)
            app.frame.value = frame
            app.show_contours.value = True
            center = frames[frame].mean(axis=0)
            for client in app.server.get_clients().values():
                client.camera.position = tuple(center + np.array([0.9, -0.9, 0.7]))
                client.camera.look_at = tuple(center)
            app.select_face(int(np.argmax(frames[frame][F][:, :, 2].mean(axis=1))))
            time.sleep(3)
            page.screenshot(path=path)
            ctx.close()
    finally:
        app.close()


if __name__ == "__main__":
    import argparse

    parser = argparse.ArgumentParser(prog="python -m conecull.viz.screenshots",
                                     description="The README's screenshots of the rerun and viser views, taken with "
                                                 "headless chromium (generates the funnel scene first if not cached)")
    parser.add_argument("out", nargs="?", default=".", help="folder for the PNGs (default: the current one)")
    out = parser.parse_args().out
    os.makedirs(out, exist_ok=True)
    viser_screenshot(os.path.join(out, "viser.png"))
    rerun_screenshot(os.path.join(out, "rerun.png"), frame=28)  # the fold through itself: collisions, failing cones
    # a paper-sized simulated scene in the debugger (generates `funnel` first if not cached: minutes)
    rerun_screenshot(os.path.join(out, "rerun-funnel.png"), scene="funnel", frame=40)
    rerun_screenshot(os.path.join(out, "rerun-front.png"), scene="fold", frame=26, method="nc+front", front_view=True,
                     wait=40.0)
    rerun_screenshot(os.path.join(out, "rerun-compare.png"), scene="fold", frame=29, compare=("nc", "sct", "cbc"),
                     wait=30.0)
    print(f"wrote {out}/viser.png, {out}/rerun.png, {out}/rerun-funnel.png, {out}/rerun-front.png and "
          f"{out}/rerun-compare.png")
