"""Constraints on predicted positions: pins, tethers, XPBD stretch and bend."""

from __future__ import annotations

import numpy as np

from conecull.datasets.sim.effects.base import Effect, _pair_mean


class PinnedVertices(Effect):
    name = "pinned"
    stages = ("pin",)

    def __init__(self, indices, motion=None):
        self.indices = np.asarray(indices, int)
        self.motion = motion  # optional f(t, rest positions) -> positions

    def setup(self, sim):
        self.rest = sim.x[self.indices].copy()

    def pin(self, sim, t):
        sim.p[self.indices] = self.rest if self.motion is None else self.motion(t, self.rest)


class Tethers(Effect):
    """Long-range attachments (Kim, Chentanez and Mueller 2012): no vertex may get farther from
    a pinned vertex than in the rest pose. A few Jacobi iterations cannot carry a pin's pull
    across hundreds of edges, so without these a pinned fine cloth sags like rubber."""
    name = "tethers"
    stages = ("constrain",)

    def __init__(self, pins):
        self.pins = np.asarray(pins, int)

    def setup(self, sim):
        self.rest = np.linalg.norm(sim.x[:, None, :] - sim.x[None, self.pins, :], axis=2)  # (n, pins)

    def constrain(self, sim, dt):
        for k, pin in enumerate(self.pins):
            d = sim.p - sim.p[pin]
            length = np.linalg.norm(d, axis=1)
            over = length > self.rest[:, k]
            sim.p[over] = sim.p[pin] + d[over] * (self.rest[over, k] / length[over])[:, None]


class Stretch(Effect):
    """XPBD distance constraints on the mesh edges (rest lengths from the rest pose)."""
    name = "stretch"
    stages = ("constrain",)

    def __init__(self, compliance=1e-7):
        self.compliance = compliance

    def setup(self, sim):
        self.e = sim.edges
        self.rest = np.linalg.norm(sim.x[self.e[:, 1]] - sim.x[self.e[:, 0]], axis=1)

    def constrain(self, sim, dt):
        _distance_pass(sim, self.e, self.rest, self.compliance / (dt * dt))


class Bend(Effect):
    """Bending as XPBD distances between the opposite vertices of edge-adjacent triangles."""
    name = "bend"
    stages = ("constrain",)

    def __init__(self, compliance=1e-4):
        self.compliance = compliance

    def setup(self, sim):
        F = sim.faces
        off, ids = sim.mesh.edge_faces
        pairs = []
        for e, (a, b) in enumerate(sim.edges.tolist()):
            fs = ids[off[e]:off[e + 1]]
            if len(fs) != 2:
                continue
            c = [v for v in F[fs[0]] if v not in (a, b)][0]
            d = [v for v in F[fs[1]] if v not in (a, b)][0]
            pairs.append((c, d))
        self.e = np.array(pairs, int).reshape(-1, 2)
        self.rest = np.linalg.norm(sim.x[self.e[:, 1]] - sim.x[self.e[:, 0]], axis=1)

    def constrain(self, sim, dt):
        _distance_pass(sim, self.e, self.rest, self.compliance / (dt * dt))


def _distance_pass(sim, e, rest, alpha):
    """One Jacobi-style XPBD pass over distance constraints (vectorised, averaged per vertex)."""
    p, n = sim.p, len(sim.p)
    e0, e1 = e[:, 0], e[:, 1]
    d = p[e1] - p[e0]
    length = np.sqrt(np.einsum("ij,ij->i", d, d)) + 1e-12
    w0, w1 = sim.inv_mass[e0], sim.inv_mass[e1]
    lam = -(length - rest) / (w0 + w1 + alpha + 1e-12)
    corr = (lam / length)[:, None] * d
    sim.p += 1.5 * _pair_mean(e0, e1, -w0[:, None] * corr, w1[:, None] * corr, n)  # over-relaxed Jacobi


class StrainLimit(Effect):
    """Inextensibility across scales: vertices k grid steps apart (k = 4, 16, 64 along rows and
    columns) may not get farther apart than `limit` x their rest distance (unilateral, like
    tethers, so bending stays free). Jacobi passes over mesh edges carry a pull only a few
    edges per substep, so a fine cloth hanging from a body stretches like rubber without it."""
    name = "strain-limit"
    stages = ("constrain",)

    def __init__(self, pairs, limit=1.05):
        self.e = np.asarray(pairs, np.int64).reshape(-1, 2)
        self.limit = limit

    def setup(self, sim):
        self.max_len = self.limit * np.linalg.norm(sim.x[self.e[:, 1]] - sim.x[self.e[:, 0]], axis=1)

    def constrain(self, sim, dt):
        p, e0, e1 = sim.p, self.e[:, 0], self.e[:, 1]
        d = p[e1] - p[e0]
        length = np.sqrt(np.einsum("ij,ij->i", d, d)) + 1e-12
        over = length > self.max_len
        if not over.any():
            return
        e0, e1, d, length = e0[over], e1[over], d[over], length[over]
        w0, w1 = sim.inv_mass[e0], sim.inv_mass[e1]
        corr = ((length - self.max_len[over]) / (length * np.maximum(w0 + w1, 1e-12)))[:, None] * d
        sim.p += _pair_mean(e0, e1, w0[:, None] * corr, -w1[:, None] * corr, len(p))


def grid_skip_pairs(nx: int, ny: int, steps=(4, 16, 64)):
    """Pairs of grid vertices (row-major, nx per row) `k` apart along rows and columns."""
    idx = np.arange(nx * ny).reshape(ny, nx)
    pairs = [np.column_stack([idx[:, :-k].ravel(), idx[:, k:].ravel()]) for k in steps if k < nx]
    pairs += [np.column_stack([idx[:-k].ravel(), idx[k:].ravel()]) for k in steps if k < ny]
    return np.concatenate(pairs) if pairs else np.zeros((0, 2), np.int64)
