"""The demo: the `fold` scene (a sheet folding onto itself until it passes through), traced
frame by frame and recorded to an .rrd; prints what was culled and what collides. Headless."""

from __future__ import annotations

import os
import shlex
import shutil
import sys
import time

from conecull.datasets.inputs import DEFAULT_SCENE, load_sequence
from conecull.viz.rerun_sink import record


def _tool(name: str) -> str:
    """A console script of this environment by absolute path (it sits next to the interpreter),
    so the printed command works from any folder; else whatever is on PATH."""
    here = os.path.join(os.path.dirname(os.path.abspath(sys.executable)), name)
    return here if os.path.exists(here) else (shutil.which(name) or name)


def rerun_command(path: str) -> str:
    """The command that opens a recording in the rerun viewer (shipped with rerun-sdk)."""
    return f"{shlex.quote(_tool('rerun'))} {shlex.quote(os.path.abspath(path))}"


def contact_face(mesh, step) -> int:
    """A triangle of a CCD step's first contact, for `explain --face`: the VF contact's face, or
    a triangle around the EE contact's first edge."""
    if len(step.vf):
        return int(step.vf[0][1])
    off, faces = mesh.edge_faces
    return int(faces[off[step.ee[0][0]]])


def first_collision_args(F, frames, hit: int, method: str, ccd: bool = False, arithmetic: str = "exact") -> str:
    """The `conecull explain` options for the first collision `method` finds at frame `hit` (CCD:
    the step from it): a colliding pair, or a triangle of the first contact; node ids from the
    first frame, as `record` and `explain` take them. (--method is the caller's to add.)"""
    import conecull

    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=frames.shape[1]), method=method)
    col.dcd(frames[0])
    if ccd:
        step = col.ccd(frames[hit], frames[hit + 1], arithmetic=arithmetic, stop_at_first=True)
        return f"--frame {hit} --ccd --face {contact_face(col.mesh, step)}" + (
            f" --arithmetic {arithmetic}" if arithmetic != "exact" else "")
    i, j = col.dcd(frames[hit], stop_at_first=True).pairs[0]
    return f"--frame {hit} --pair {i} {j}"


def run_demo(out: str = "demo.rrd", method: str = "nc") -> int:
    F, frames = load_sequence(DEFAULT_SCENE)
    print(f"conecull demo: scene '{DEFAULT_SCENE}', {len(F)} triangles, {len(frames)} frames, method={method}")
    t = time.perf_counter()
    stats = record(out, F, frames, method=method)
    secs = time.perf_counter() - t
    print(f"{'frame':>5} {'cone tests':>10} {'culled':>7} {'contour fail':>12} {'elem tests':>10} {'colliding':>9} {'query ms':>8}")
    for k, s in enumerate(stats):
        ms = 1e3 * (s["seconds_build"] + s["seconds_refit"] + s["seconds_traversal"] + s["seconds_elementary"])
        print(f"{k:5d} {s['cone_tests']:10d} {s['contour_passed']:7d} {s['contour_failed']:12d} "
              f"{s['elementary_tests']:10d} {s['colliding_pairs']:9d} {ms:8.2f}")
    print(f"wrote {out} in {secs:.1f} s (traced queries + recording).")
    print(f"open it with:   {rerun_command(out)}   (the viewer ships with rerun-sdk)")
    print(f"live view:      {shlex.quote(_tool('conecull'))} view {DEFAULT_SCENE}   (prints the http://127.0.0.1 address "
          "to open)")
    hit = next((k for k, s in enumerate(stats) if s["colliding_pairs"]), None)
    if hit is not None:  # the triage question for the first colliding frame
        print(f"why a collision was not culled away: {shlex.quote(_tool('conecull'))} explain {DEFAULT_SCENE} "
              + first_collision_args(F, frames, hit, method) + (f" --method {method}" if method != "nc" else ""))
    return 0
