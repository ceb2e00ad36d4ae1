"""Browser test of the viser app: Playwright driving Debian's chromium (never `playwright
install`). Start the app on a free port, type an out-of-range frame (set back into range), change
the frame, click the mesh, check that the selection panel changed and that the mesh under the
pointer is not outlined in yellow, save a screenshot, close everything."""

import os
import shutil
import time

import numpy as np
import pytest

from ports import free_port
from shared_data import in_ci

IN_CI = in_ci()
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
if not CHROMIUM:
    if IN_CI:
        raise RuntimeError("chromium is required in CI (.ci/run installs it with apt)")
    pytest.skip("no chromium on this machine (apt-get install chromium); CI installs it", allow_module_level=True)
try:
    import playwright.sync_api as playwright
except ImportError:
    if IN_CI:
        raise RuntimeError("playwright is required in CI (it is in the [test] extra)")
    pytest.skip("playwright is not installed (pip install 'conecull[test]')", allow_module_level=True)

ARGS = ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run", "--disable-background-networking",
        "--disable-component-update", "--disable-sync"]


def wait_for(pred, timeout=30.0, what="condition"):
    t0 = time.time()
    while time.time() - t0 < timeout:
        if pred():
            return
        time.sleep(0.1)
    raise AssertionError(f"timed out waiting for {what}")


def test_viewer_in_browser(tmp_path):
    from conecull.datasets.inputs import load_sequence
    from conecull.viz.viser_app import ViewerApp

    F, frames = load_sequence("fold")
    app = ViewerApp(F, frames, port=free_port())
    try:
        with playwright.sync_playwright() as p:
            ctx = p.chromium.launch_persistent_context(str(tmp_path / "profile"), executable_path=CHROMIUM,
                                                       headless=True, args=ARGS, viewport={"width": 1000, "height": 700})
            try:
                page = ctx.new_page()
                page.goto(f"http://127.0.0.1:{app.port}")
                page.wait_for_selector("canvas", timeout=30000)
                page.get_by_text("Click the mesh (or type a triangle id above) to select").wait_for(timeout=30000)
                wait_for(lambda: len(app.server.get_clients()) > 0, what="a client")
                # Change the frame by typing into the slider's number input: the box sends what is
                # typed, unclamped; the server sets it back into range and says so.
                frame_box = page.locator("input.mantine-NumberInput-input").first  # the frame slider's number box
                frame_box.fill("99")
                wait_for(lambda: int(app.frame.value) == 29 and "frame 99 refused" in app.stats_md.content,
                         what="frame 99 set back to 29")
                wait_for(lambda: frame_box.input_value() == "29", what="the box showing 29")
                assert "error" not in app.stats_md.content
                frame_box.fill("29")
                frame_box.press("Enter")
                wait_for(lambda: int(app.frame.value) == 29, what="frame 29 on the server")
                # Aim the camera at the middle of the sheet, then click the middle of the canvas.
                V = frames[29]
                center = V.mean(axis=0)
                for client in app.server.get_clients().values():
                    client.camera.position = tuple(center + np.array([0.0, -0.05, 1.6]))
                    client.camera.look_at = tuple(center)
                # The camera reaches the page asynchronously: click until a click selects a node.
                before = app.panel.content
                box = page.locator("canvas").first.bounding_box()

                def click_selects():
                    page.mouse.click(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
                    t0 = time.time()
                    while time.time() - t0 < 1.0:
                        if app.panel.content != before:
                            return True
                        time.sleep(0.05)
                    return False

                wait_for(click_selects, what="a click on the mesh to change the selection panel")
                assert "→ node" in app.panel.content and "verdict:" in app.panel.content
                # The page shows the new panel text too.
                page.get_by_text("path to root", exact=False).first.wait_for(timeout=15000)
                page.evaluate("() => new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
                shot = tmp_path / "viser.png"
                page.screenshot(path=str(shot))
                assert shot.stat().st_size > 10000
                # The pointer on the mesh: viser's hover outline (yellow 0xfbff00, drawn on back faces,
                # so whole flaps of the folded sheet) must not show; no face colour is that yellow.
                from PIL import Image

                page.mouse.move(box["x"] + box["width"] / 2 + 3, box["y"] + box["height"] / 2)
                page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
                time.sleep(0.5)
                page.evaluate("() => new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
                hover = tmp_path / "hover.png"
                page.screenshot(path=str(hover))
                rgb = np.asarray(Image.open(hover).convert("RGB")).astype(int)
                x, y = int(box["x"]), int(box["y"])
                scene = rgb[y + 150 : y + 650, x + 320 : x + 650]  # around the sheet, left of the panel
                yellow = (scene[..., 0] > 200) & (scene[..., 1] > 200) & (scene[..., 2] < 110)
                assert yellow.sum() < 50, f"{int(yellow.sum())} hover-outline yellow pixels"
                if os.environ.get("CONECULL_SCREENSHOT_DIR"):
                    shutil.copy(shot, os.path.join(os.environ["CONECULL_SCREENSHOT_DIR"], "viser.png"))
            finally:
                ctx.close()
    finally:
        app.close()

