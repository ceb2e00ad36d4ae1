"""Forces, added to velocities before prediction."""

from __future__ import annotations

import numpy as np

from conecull.datasets.sim.effects.base import Effect


class Gravity(Effect):
    name = "gravity"
    stages = ("force",)

    def __init__(self, g=(0.0, 0.0, -9.81)):
        self.g = np.asarray(g, float)

    def force(self, sim, dt):
        sim.v += dt * self.g


class Wind(Effect):
    """Air drag towards a wind velocity, per vertex, scaled by how much the surface faces it."""
    name = "wind"
    stages = ("force",)

    def __init__(self, velocity=(2.0, 0.0, 0.0), drag=0.8, gust=0.3, seed=0):
        self.velocity = np.asarray(velocity, float)
        self.drag, self.gust = drag, gust
        self.rng = np.random.default_rng(seed)

    def force(self, sim, dt):
        w = self.velocity * (1.0 + self.gust * np.sin(2.0 * sim.t * 3.1 + self.rng.uniform(0, 0.1)))
        n = sim.vertex_normals()
        facing = np.abs(n @ (w / (np.linalg.norm(w) + 1e-12)))[:, None]
        sim.v += dt * self.drag * facing * (w - sim.v)
