"""Kinematic colliders with friction: plane, (rotating) sphere, funnel, capsule."""

from __future__ import annotations

import numpy as np

from conecull.datasets.sim.effects.base import Effect


class PlaneCollider(Effect):
    name = "plane"
    stages = ("collide",)

    def __init__(self, height=0.0, friction=0.5, offset=0.002):
        self.height, self.friction, self.offset = height, friction, offset

    def collide(self, sim, dt):
        inside = sim.p[:, 2] < self.height + self.offset
        sim.p[inside, 2] = self.height + self.offset
        slide = sim.p[inside, :2] - sim.x[inside, :2]
        sim.p[inside, :2] = sim.x[inside, :2] + (1.0 - self.friction) * slide


class SphereCollider(Effect):
    """A (possibly rotating) sphere; contact drags the cloth along the surface velocity."""
    name = "sphere"
    stages = ("collide",)

    def __init__(self, center=(0.0, 0.0, 0.0), radius=0.3, angular_velocity=(0.0, 0.0, 0.0), friction=0.6,
                 offset=0.004):
        self.c = np.asarray(center, float)
        self.r, self.w = radius, np.asarray(angular_velocity, float)
        self.friction, self.offset = friction, offset

    def collide(self, sim, dt):
        d = sim.p - self.c
        dist = np.linalg.norm(d, axis=1)
        inside = dist < self.r + self.offset
        if not inside.any():
            return
        n = d[inside] / np.maximum(dist[inside], 1e-12)[:, None]
        sim.p[inside] = self.c + n * (self.r + self.offset)
        surface_v = np.cross(self.w, sim.p[inside] - self.c)
        rel = (sim.p[inside] - sim.x[inside]) - dt * surface_v
        tangential = rel - (rel * n).sum(axis=1)[:, None] * n
        sim.p[inside] -= self.friction * tangential


class FunnelCollider(Effect):
    """A funnel: the inside of a cone around the z axis (radius r_hole at z_bottom, widening
    with slope tan(angle)); cloth inside it cannot leave through the wall, cloth below
    z_bottom has fallen through the hole."""
    name = "funnel"
    stages = ("collide",)

    def __init__(self, z_bottom=0.0, z_top=0.8, r_hole=0.08, angle=np.radians(35.0), friction=0.4, offset=0.004):
        self.z0, self.z1, self.r0, self.slope = z_bottom, z_top, r_hole, np.tan(angle)
        self.friction, self.offset = friction, offset

    def collide(self, sim, dt):
        z = sim.p[:, 2]
        r = np.linalg.norm(sim.p[:, :2], axis=1)
        R = self.r0 + (z - self.z0) * self.slope - self.offset
        zx = sim.x[:, 2]
        was_inside = np.linalg.norm(sim.x[:, :2], axis=1) <= self.r0 + (zx - self.z0) * self.slope
        hit = (z > self.z0) & (z < self.z1) & (r > R) & was_inside & (R > 0)
        if not hit.any():
            return
        # back onto the wall, then friction removes part of the motion along it
        scale = (R[hit] / np.maximum(r[hit], 1e-12))[:, None]
        on_wall = np.column_stack([sim.p[hit, :2] * scale, z[hit]])
        sim.p[hit] = sim.x[hit] + (1.0 - self.friction) * (on_wall - sim.x[hit])
        r2 = np.linalg.norm(sim.p[hit, :2], axis=1)
        R2 = self.r0 + (sim.p[hit, 2] - self.z0) * self.slope - self.offset
        over = r2 > R2  # friction pulled it back outside: keep it on the wall
        idx = np.flatnonzero(hit)[over]
        sim.p[idx, :2] *= (R2[over] / np.maximum(r2[over], 1e-12))[:, None]


class CapsuleCollider(Effect):
    """A capsule (segment a-b thickened by radius), e.g. a body proxy."""
    name = "capsule"
    stages = ("collide",)

    def __init__(self, a=(0.0, 0.0, 0.0), b=(0.0, 0.0, 1.0), radius=0.15, friction=0.5, offset=0.004):
        self.a, self.b = np.asarray(a, float), np.asarray(b, float)
        self.r, self.friction, self.offset = radius, friction, offset

    def collide(self, sim, dt):
        ab = self.b - self.a
        s = np.clip(((sim.p - self.a) @ ab) / (ab @ ab), 0.0, 1.0)
        closest = self.a + s[:, None] * ab
        d = sim.p - closest
        dist = np.linalg.norm(d, axis=1)
        inside = dist < self.r + self.offset
        if not inside.any():
            return
        n = d[inside] / np.maximum(dist[inside], 1e-12)[:, None]
        sim.p[inside] = closest[inside] + n * (self.r + self.offset)
        rel = sim.p[inside] - sim.x[inside]
        tangential = rel - (rel * n).sum(axis=1)[:, None] * n
        sim.p[inside] -= self.friction * tangential
