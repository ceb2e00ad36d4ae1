"""The demo: the `fold` scene (a sheet folding onto itself until it passes through), traced
frame by frame and recorded to an .rrd; prints what was culled and what collides. Headless."""

from __future__ import annotations

import time

from conecull.datasets.inputs import DEFAULT_SCENE, load_sequence
from conecull.viz.rerun_sink import record


def run_demo(out: str = "demo.rrd", method: str = "nc") -> int:
    F, frames = load_sequence(DEFAULT_SCENE)
    print(f"conecull demo: scene '{DEFAULT_SCENE}', {len(F)} triangles, {len(frames)} frames, method={method}")
    t = time.perf_counter()
    stats = record(out, F, frames, method=method)
    secs = time.perf_counter() - t
    print(f"{'frame':>5} {'cone tests':>10} {'culled':>7} {'contour fail':>12} {'elem tests':>10} {'colliding':>9} {'query ms':>8}")
    for k, s in enumerate(stats):
        ms = 1e3 * (s["seconds_refit"] + s["seconds_traversal"] + s["seconds_elementary"])
        print(f"{k:5d} {s['cone_tests']:10d} {s['contour_passed']:7d} {s['contour_failed']:12d} "
              f"{s['elementary_tests']:10d} {s['colliding_pairs']:9d} {ms:8.2f}")
    print(f"wrote {out} in {secs:.1f} s (traced queries + recording).")
    print(f"open it with:   .venv/bin/rerun {out}   (the viewer ships with rerun-sdk)")
    print(f"live view:      .venv/bin/conecull view {DEFAULT_SCENE}   (prints the http://127.0.0.1 address to open)")
    return 0
