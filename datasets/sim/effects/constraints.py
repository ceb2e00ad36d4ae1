"""Constraints on predicted positions: pins, tethers, XPBD stretch and bend (two models), strain limits."""

from __future__ import annotations

import numpy as np

from conecull.datasets.sim.effects.base import Effect, _pair_mean, _vertex_mean


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
        self.e = hinges(sim)[:, 2:]
        self.rest = np.linalg.norm(sim.x[self.e[:, 1]] - sim.x[self.e[:, 0]], axis=1)

    def constrain(self, sim, dt):
        _distance_pass(sim, self.e, self.rest, self.compliance / (dt * dt))


class IsometricBend(Effect):
    """Bending of a sheet that is flat at rest, as a linear constraint per hinge (after Bergou et
    al. 2006's quadratic bending model for inextensible surfaces): for the hinge of edge (a, b)
    with opposite vertices c and d, C = K_a x_a + K_b x_b + K_c x_c + K_d x_d (a 3-vector), with K
    the affine dependency of the hinge unfolded flat (affine_dependency). C vanishes on every
    affine image of the flat hinge (any rigid motion, in-plane stretch or shear: that is Stretch's
    job) and grows linearly with the fold. Why not Bend's distance between c and d: that changes
    only with the square of the fold angle, so near flat it resists nothing, and a cloth squeezed
    in its plane (a robe gathered around a body) buckles at the scale of single triangles
    (falling's last frame: 18% of hinges beyond 45 degrees with Bend, 5% with this). Same effect
    name as Bend: a scene declares "bend" and picks the model. Raises if the rest pose is not flat
    (this model would flatten it)."""
    name = "bend"
    stages = ("constrain",)

    def __init__(self, compliance=1e-6):
        self.compliance = compliance

    def setup(self, sim):
        q = hinges(sim)
        corners = [sim.x[q[:, k]] for k in range(4)]
        a, b, c, d = corners
        # Both faces of a hinge must have an area (else no weights); such a hinge is left free.
        ok = (np.linalg.norm(np.cross(b - a, c - a), axis=1) > 0) & (np.linalg.norm(np.cross(b - a, d - a), axis=1) > 0)
        q, corners = q[ok], [x[ok] for x in corners]
        K = hinge_weights(*corners)
        rest = np.linalg.norm(np.einsum("hj,jhk->hk", K, np.stack(corners)), axis=1)
        bent = rest > 1e-6 * np.linalg.norm(corners[1] - corners[0], axis=1)
        if bent.any():
            h = int(np.flatnonzero(bent)[0])
            raise ValueError(f"positions: IsometricBend needs a flat rest pose, but the hinge of edge ({q[h, 0]}, "
                             f"{q[h, 1]}) is bent at rest ({int(bent.sum())} hinges in all); use Bend")
        self.q, self.K = q, K

    def constrain(self, sim, dt):
        q, K = self.q, self.K
        C = np.einsum("hj,hjk->hk", K, sim.p[q])
        w = sim.inv_mass[q]
        lam = -C / ((w * K * K).sum(axis=1) + self.compliance / (dt * dt) + 1e-12)[:, None]
        corr = (w * K)[:, :, None] * lam[:, None, :]  # XPBD: grad_j C = K_j I
        sim.p += 1.5 * _vertex_mean(q.ravel(), corr.reshape(-1, 3), len(sim.p))  # over-relaxed Jacobi


def hinges(sim):
    """(h, 4) vertex ids (a, b, c, d) of every edge (a, b) between two faces, with c and d the
    faces' third corners."""
    F = sim.faces
    off, ids = sim.mesh.edge_faces
    out = []
    for e, (a, b) in enumerate(sim.edges.tolist()):
        fs = ids[off[e]:off[e + 1]]
        if len(fs) != 2:
            continue
        c = [v for v in F[fs[0]] if v not in (a, b)][0]
        d = [v for v in F[fs[1]] if v not in (a, b)][0]
        out.append((a, b, c, d))
    return np.array(out, np.int64).reshape(-1, 4)


def hinge_weights(a, b, c, d):
    """K (h, 4) of IsometricBend for hinges with rest corners a, b (the edge), c, d (each (h, 3)),
    both faces with an area: the hinge unfolded flat (a at the origin, b on the x axis, c above it,
    d below), then affine_dependency of those four points."""
    e = b - a
    L = np.linalg.norm(e, axis=1)

    def unfold(p, side):  # p's coordinates along the edge and away from it (cross product: no cancellation)
        r = p - a
        return np.einsum("ij,ij->i", r, e) / L, side * np.linalg.norm(np.cross(e, r), axis=1) / L

    zero = np.zeros_like(L)
    return np.stack(affine_dependency((zero, zero), (L, zero), unfold(c, 1.0), unfold(d, -1.0)), axis=1)


def affine_dependency(a, b, c, d):
    """(K_a, K_b, K_c, K_d) with K_a + K_b + K_c + K_d = 0 and K_a a + ... + K_d d = 0 for four
    points (x, y) of a plane: the cofactors of [1 1 1 1; x; y] (Cramer), i.e. signed areas
    (A(b,c,d), -A(a,c,d), A(a,b,d), -A(a,b,c)), scaled so that K_c + K_d = 2 (both 1 when the
    faces (a,b,c) and (a,b,d) have equal areas; symmetric in c and d, so the stiffness does not
    depend on which face comes first). Needs c and d on opposite sides of line ab. Plain
    arithmetic, so that the tests can check it on fractions."""
    def area(p, q, r):
        return ((q[0] - p[0]) * (r[1] - p[1]) - (r[0] - p[0]) * (q[1] - p[1])) / 2

    s = (area(a, b, d) - area(a, b, c)) / 2
    return area(b, c, d) / s, -area(a, c, d) / s, area(a, b, d) / s, -area(a, b, c) / s


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
