"""Position-based dynamics with XPBD constraints; effects plug in by stage."""

from __future__ import annotations

from collections import Counter

import numpy as np

import conecull
from conecull.datasets.sim.effects import _scatter_add


class Simulator:
    def __init__(self, faces, positions, effects, *, dt=1.0 / 60.0, substeps=4, iterations=8, velocity=(0.0, 0.0, 0.0),
                 declared=None):
        """`declared`: the effect names a scene declares; the effects given must be exactly those."""
        if declared is not None:
            given = {e.name for e in effects}
            if given != set(declared):
                raise ValueError(f"effects: the scene declares {sorted(declared)} but builds {sorted(given)}")
        self.faces = np.asarray(faces, np.int64)
        self.x = np.asarray(positions, np.float64).copy()
        self.v = np.zeros_like(self.x) + np.asarray(velocity, np.float64)  # initial velocity
        self.p = self.x.copy()
        self.mesh = conecull.Mesh(self.faces, n_vertices=len(self.x))
        self.edges = self.mesh.edges
        self.inv_mass = np.ones(len(self.x))
        self.dt, self.substeps, self.iterations = dt, substeps, iterations
        self.t = 0.0
        self.effects = list(effects)
        self.calls = Counter()  # (effect class, stage) -> calls: what really ran
        for e in self.effects:
            e.setup(self)
            if "pin" in e.stages:
                self.inv_mass[e.indices] = 0.0

    def vertex_normals(self):
        F, X = self.faces, self.x
        fn = np.cross(X[F[:, 1]] - X[F[:, 0]], X[F[:, 2]] - X[F[:, 0]])
        n = sum(_scatter_add(F[:, k], fn, len(X)) for k in range(3))
        return n / (np.linalg.norm(n, axis=1, keepdims=True) + 1e-12)

    def _run(self, stage, *args):
        for e in self.effects:
            if stage in e.stages:
                getattr(e, stage)(self, *args)
                self.calls[(type(e).__name__, stage)] += 1

    def step(self):
        h = self.dt / self.substeps
        for _ in range(self.substeps):
            self._run("force", h)
            self.p = self.x + h * self.v
            for _ in range(self.iterations):
                self._run("constrain", h)
            self._run("collide", h)
            self._run("pin", self.t + h)
            self._run("contact", h)
            self.v = (self.p - self.x) / h
            self.x = self.p.copy()
            self.t += h

    def run(self, frames):
        out = [self.x.copy()]
        for _ in range(frames - 1):
            self.step()
            out.append(self.x.copy())
        return np.stack(out)
