"""The demo: a sheet folding onto itself, queried frame by frame with DCD; prints what was
culled and what collides. Headless; the debugger issue turns it into a recording."""

from __future__ import annotations

import time

import numpy as np

import conecull
from conecull.datasets.generated import folding_sheet


def run_demo(n_triangles: int = 8000, n_frames: int = 24, method: str = "nc") -> int:
    F, frames = folding_sheet(n_triangles=n_triangles, n_frames=n_frames)
    mesh = conecull.Mesh(F)
    col = conecull.SelfCollider(mesh, method=method)
    print(f"conecull demo: folding sheet, {mesh.n_faces} triangles, {n_frames} frames, method={method}")
    print(f"{'frame':>5} {'cone tests':>10} {'culled':>7} {'contour fail':>12} {'elem tests':>10} {'colliding':>9} {'ms':>7}")
    total = 0.0
    for k, V in enumerate(frames):
        t = time.perf_counter()
        res = col.dcd(V)
        ms = 1e3 * (time.perf_counter() - t)
        total += ms
        s = res.stats
        print(f"{k:5d} {s['cone_tests']:10d} {s['contour_passed']:7d} {s['contour_failed']:12d} "
              f"{s['elementary_tests']:10d} {s['colliding_pairs']:9d} {ms:7.2f}")
    print(f"last frame stats: {res.stats}")
    print(f"colliding triangle pairs at the last frame: {len(res.pairs)} (first: {res.pairs[:3].tolist()})")
    print(f"total {total:.1f} ms for {n_frames} frames (the first includes building the BVH and contours)")
    return 0
