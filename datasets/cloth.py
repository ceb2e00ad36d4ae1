"""Simulated cloth scenes standing in for the paper's benchmarks (Sec. 5.2). Each function
returns a scene's set-up: faces, rest positions, the effects (the simulator checks they are
exactly those the scene declares in the registry) and simulator options. `resolution` is the
number of grid vertices per side of the cloth (triangles: 2 (resolution - 1)^2, less a neck
hole for the robe)."""

from __future__ import annotations

import numpy as np

from conecull.datasets import generated
from conecull.datasets.checks import count, real
from conecull.datasets.sim import (Bend, CapsuleCollider, FunnelCollider, Gravity, IsometricBend, PinnedVertices,
                                   PlaneCollider, SelfContact, SphereCollider, StrainLimit, Stretch, Tethers, Wind,
                                   grid_skip_pairs)


def funnel(resolution: int):
    """A sheet falling into a funnel and folding to fit through it, with self-contact (Funnel)."""
    resolution = count("resolution", resolution, 2)
    F, V = generated.grid_sheet(resolution, resolution, width=0.9, height=0.9)
    V = V - [0.45, 0.45, 0.0] + [0.0, 0.0, 0.85]
    return F, V, [Gravity(), Stretch(), Bend(1e-3), FunnelCollider(z_bottom=0.0, z_top=1.2), SelfContact()], {}


def twisting(resolution: int):
    """A sheet dropped on a ball spinning about the vertical axis: friction winds it into twisted
    folds around the ball, with self-contact (Twisting)."""
    resolution = count("resolution", resolution, 2)
    F, V = generated.grid_sheet(resolution, resolution)
    V = V - [0.5, 0.5, 0.0] + [0.0, 0.0, 0.34]
    return F, V, [Gravity(), Stretch(), Bend(1e-3), SphereCollider((0, 0, 0.0), 0.3, (0, 0, 2.5), friction=0.6),
                  PlaneCollider(-0.31), SelfContact()], {}


def flowing(resolution: int):
    """A hanging sheet pinned at its two top corners, flowing in gusty wind, with self-contact
    (FlowingCloth). Tethers (long-range attachments) keep it from sagging like rubber."""
    resolution = count("resolution", resolution, 2)
    F, V = generated.grid_sheet(resolution, resolution)
    V = V[:, [0, 2, 1]]  # hang it vertically in the x-z plane, top row (pinned corners) at z = 1
    corners = [resolution * (resolution - 1), resolution * resolution - 1]  # the top row's ends
    return F, V, [Gravity(), Wind((0.0, 3.0, 0.0)), Stretch(), Bend(), PinnedVertices(corners), Tethers(corners),
                  SelfContact()], {}


def robe_sheet(resolution: int, size: float = 1.6, neck: float = 0.13, with_map: bool = False):
    """A square sheet with a round neck hole in the middle (unreferenced vertices dropped); with
    `with_map`, also the grid index -> vertex id map (-1: dropped)."""
    resolution = count("resolution", resolution, 2)
    size, neck = real("size", size, 0.0, low_open=True), real("neck", neck, 0.0)
    F, V = generated.grid_sheet(resolution, resolution, width=size, height=size)
    V = V - [size / 2, size / 2, 0.0]
    F = F[np.linalg.norm(V[F].mean(axis=1)[:, :2], axis=1) > neck]
    used = np.unique(F)
    remap = np.full(len(V), -1)
    remap[used] = np.arange(len(used))
    return (remap[F], V[used], remap) if with_map else (remap[F], V[used])


def falling(resolution: int):
    """A robe-like sheet (a square with a neck hole) thrown down fast over a body proxy (capsules
    for torso, shoulders and arms, a sphere for the head, a floor), with self-contact (Falling).
    Strain limiting keeps the fine robe from stretching down to the floor under its weight; the
    isometric bending keeps it from buckling at the scale of single triangles where it gathers
    around the body (it does with Bend, whose resistance vanishes near flat)."""
    resolution = count("resolution", resolution, 2)
    F, V, remap = robe_sheet(resolution, with_map=True)
    V = V + [0.0, 0.0, 1.75]
    skip = remap[grid_skip_pairs(resolution, resolution)]
    skip = skip[(skip >= 0).all(axis=1)]
    body = [CapsuleCollider((0, 0, 0.55), (0, 0, 1.3), 0.16),             # torso
            CapsuleCollider((-0.2, 0, 1.38), (0.2, 0, 1.38), 0.07),       # shoulders
            CapsuleCollider((-0.24, 0, 1.36), (-0.3, 0.05, 0.8), 0.05),   # arms
            CapsuleCollider((0.24, 0, 1.36), (0.3, 0.05, 0.8), 0.05),
            CapsuleCollider((-0.09, 0, 0.0), (-0.09, 0, 0.6), 0.07),      # legs
            CapsuleCollider((0.09, 0, 0.0), (0.09, 0, 0.6), 0.07),
            SphereCollider((0, 0, 1.58), 0.11)]                           # head
    return F, V, [Gravity(), Stretch(), StrainLimit(skip), IsometricBend(1e-6), *body, PlaneCollider(0.0),
                  SelfContact()], {"velocity": (0, 0, -3.0)}
