"""Scene registry: each scene is a small declaration (mesh generator with a resolution, the
effects it needs, initial conditions, frame count and time step) and `load` caches what it
generates on disk by its parameters.

Kinematic scenes (no effects) are analytic motions. Simulated scenes (effects such as gravity,
stretch/bend constraints, colliders, self-contact) arrive with the simulator; `effects` lists
what each declares, and only those are ever computed.
"""

from __future__ import annotations

import hashlib
import json
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from conecull.datasets import generated

CACHE_VERSION = 1


@dataclass(frozen=True)
class Scene:
    name: str
    description: str
    stands_for: str                      # which paper benchmark (Sec. 5.2) it stands in for, or "teaching"
    generate: Callable                   # (resolution, frames) -> (faces (m, 3), positions (T, n, 3))
    default_resolution: int
    default_frames: int
    effects: tuple = field(default=())   # () = kinematic
    dt: float = 1.0 / 30.0


def _roll(resolution: int, frames: int):
    """A strip curling around a small cylinder until its end comes back onto the strip."""
    F, V = generated.grid_sheet(resolution, max(2, resolution // 8), width=1.0, height=0.12)
    angles = np.linspace(0.0, 2.25 * np.pi, frames)
    return F, np.stack([generated.fold(V, a, x0=0.45, radius=0.07) for a in angles])


def _fold(resolution: int, frames: int):
    n_tri = 2 * (resolution - 1) ** 2
    return generated.folding_sheet(n_triangles=n_tri, n_frames=frames)


def _crumple(resolution: int, frames: int):
    return generated.crumpling_sphere(n_lat=resolution, n_lon=2 * resolution, n_frames=frames)


def _bend(resolution: int, frames: int):
    n_tri = 2 * (resolution - 1) ** 2
    return generated.bending_sheet(n_triangles=n_tri, n_frames=frames)


def _drape(resolution: int, frames: int):
    """A sheet pinned at two corners, blowing in the wind (a small FlowingCloth)."""
    from conecull.datasets.sim import Bend, Gravity, PinnedVertices, Simulator, Stretch, Wind

    F, V = generated.grid_sheet(resolution, resolution)
    V = V[:, [0, 2, 1]] * [1.0, 1.0, -1.0] + [0.0, 0.0, 1.0]  # hang it vertically (x, z)
    corners = [resolution * (resolution - 1), resolution * resolution - 1]  # the top row's ends
    sim = Simulator(F, V, [Gravity(), Wind((0.0, 3.0, 0.0)), Stretch(), Bend(), PinnedVertices(corners)])
    return F, sim.run(frames)


def _ball(resolution: int, frames: int):
    """A sheet dropped on a rotating ball and a floor (a small Twisting)."""
    from conecull.datasets.sim import Bend, Gravity, PlaneCollider, Simulator, SphereCollider, Stretch

    F, V = generated.grid_sheet(resolution, resolution)
    V = V - [0.5, 0.5, 0.0] + [0.0, 0.0, 0.45]
    sim = Simulator(F, V, [Gravity(), Stretch(), Bend(), SphereCollider((0, 0, 0.0), 0.3, (0, 0, 4.0)),
                           PlaneCollider(-0.31)])
    return F, sim.run(frames)


def _funnel(resolution: int, frames: int):
    """A sheet falling into a funnel and folding to fit, with self-contact (a small Funnel)."""
    from conecull.datasets.sim import Bend, FunnelCollider, Gravity, SelfContact, Simulator, Stretch

    F, V = generated.grid_sheet(resolution, resolution, width=0.9, height=0.9)
    V = V - [0.45, 0.45, 0.0] + [0.0, 0.0, 0.85]
    sim = Simulator(F, V, [Gravity(), Stretch(), Bend(1e-3), FunnelCollider(z_bottom=0.0, z_top=1.2), SelfContact()])
    return F, sim.run(frames)


SCENES: dict[str, Scene] = {
    s.name: s
    for s in (
        Scene("fold", "a sheet folding onto itself until it passes through", "teaching", _fold, 33, 30),
        Scene("roll", "a strip curling into a spiral until it touches itself", "teaching", _roll, 64, 30),
        Scene("crumple", "a sphere crumpling inwards until it self-intersects", "teaching", _crumple, 22, 30),
        Scene("bend", "a gently bending sheet (never self-intersects)", "teaching", _bend, 33, 30),
        Scene("drape", "a sheet pinned at two corners in gusty wind", "FlowingCloth (small, no self-contact yet)",
              _drape, 24, 60, ("gravity", "wind", "stretch", "bend", "pinned")),
        Scene("ball", "a sheet dropped on a rotating ball over a floor", "Twisting (small, no self-contact yet)",
              _ball, 24, 60, ("gravity", "stretch", "bend", "sphere", "plane")),
        Scene("funnel", "a sheet falling into a funnel, folding to fit, with self-contact", "Funnel (small)",
              _funnel, 24, 60, ("gravity", "stretch", "bend", "funnel", "self-contact")),
    )
}


def names() -> list[str]:
    return list(SCENES)


def cache_dir() -> Path:
    """$CONECULL_CACHE, else the user's cache directory (XDG_CACHE_HOME or ~/.cache)/conecull."""
    env = os.environ.get("CONECULL_CACHE")
    if env:
        return Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "conecull"


def _code_digest() -> str:
    """The generators' source: editing a generator invalidates its cached sequences."""
    h = hashlib.sha256()
    for mod in (generated, __import__(__name__, fromlist=["_"])):
        h.update(Path(mod.__file__).read_bytes())
    return h.hexdigest()[:16]


def _key(scene: Scene, resolution: int, frames: int) -> str:
    blob = json.dumps({"v": CACHE_VERSION, "code": _code_digest(), "scene": scene.name, "res": resolution,
                       "frames": frames, "effects": list(scene.effects), "dt": scene.dt}, sort_keys=True)
    return hashlib.sha256(blob.encode()).hexdigest()[:16]


def load(name: str, resolution: int | None = None, frames: int | None = None):
    """faces (m, 3) int64 and positions (T, n, 3) float64 of a scene; cached on disk."""
    if name not in SCENES:
        raise ValueError(f"name: unknown scene '{name}'; known: {', '.join(SCENES)}")
    scene = SCENES[name]
    resolution = scene.default_resolution if resolution is None else resolution
    frames = scene.default_frames if frames is None else frames
    for arg, v, lo in (("resolution", resolution, 3), ("frames", frames, 1)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < lo:
            raise ValueError(f"{arg}: expected an integer >= {lo}, got {v!r}")
    path = cache_dir() / f"{name}-{_key(scene, int(resolution), int(frames))}.npz"
    if path.exists():
        with np.load(path) as z:
            return z["faces"], z["positions"]
    F, P = scene.generate(int(resolution), int(frames))
    F, P = np.asarray(F, np.int64), np.asarray(P, np.float64)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp.npz")
    np.savez(tmp, faces=F, positions=P)
    os.replace(tmp, path)  # atomic: a concurrent reader never sees half a file
    return F, P


def describe() -> list[str]:
    """One line per scene: name, triangles at default resolution, frames, effects, stands for."""
    lines = []
    for s in SCENES.values():
        F, _ = s.generate(s.default_resolution, 1) if not s.effects else generated.grid_sheet(s.default_resolution,
                                                                                                s.default_resolution)
        effects = ", ".join(s.effects) if s.effects else "kinematic"
        lines.append(f"{s.name:10s} {len(F):8d} triangles {s.default_frames:4d} frames  {effects:24s} "
                     f"{s.stands_for}: {s.description}")
    return lines
