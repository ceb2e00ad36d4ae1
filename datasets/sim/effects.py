"""Effects of the simulator, one class each, in three stages:
  force(sim, dt)       adds to velocities before prediction (gravity, wind);
  constrain(sim, dt)   projects predicted positions, XPBD style (stretch, bend);
  collide(sim, dt)     pushes predicted positions out of kinematic colliders, with friction;
  pin(sim, t)          overrides positions of pinned vertices;
  contact(sim, dt)     last: keeps the step free of self-contact (conecull's own CCD).
Each effect implements only the stages it needs; the simulator calls only declared effects."""

from __future__ import annotations

import numpy as np


class Effect:
    name: str = ""       # what a scene declares to get this effect
    stages: tuple = ()

    def setup(self, sim) -> None:  # precomputation from the rest pose
        pass


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
    index = np.concatenate([e0, e1])
    delta = _scatter_add(index, np.concatenate([-w0[:, None] * corr, w1[:, None] * corr]), n)
    count = np.bincount(index, minlength=n)
    sim.p += 1.5 * delta / np.maximum(count, 1)[:, None]  # over-relaxed Jacobi


# the neighbouring cells (dx, dy, dz) > (0, 0, 0) lexicographically, plus the cell itself: each
# pair of neighbouring cells is visited once
_HALF_NEIGHBOURHOOD = [o for o in np.array(np.meshgrid([-1, 0, 1], [-1, 0, 1], [-1, 0, 1])).reshape(3, -1).T.tolist()
                       if o >= [0, 0, 0]]


def _close_pairs(p, h):
    """Vertex pairs (i, j) that may be closer than h, by a spatial hash of cell size h: such a
    pair lies in the same or in neighbouring cells. A hash clash only adds candidates (the
    caller checks distances) or, rarely, repeats one."""
    cell = np.floor(p / h).astype(np.int64)
    key = lambda c: (c[:, 0] * 73856093) ^ (c[:, 1] * 19349663) ^ (c[:, 2] * 83492791)  # noqa: E731
    k = key(cell)
    order = np.argsort(k)
    ks = k[order]
    I, J = [], []
    for off in _HALF_NEIGHBOURHOOD:
        q = key(cell + off)
        lo, hi = np.searchsorted(ks, q, "left"), np.searchsorted(ks, q, "right")
        n = hi - lo
        total = int(n.sum())
        if total == 0:
            continue
        src = np.repeat(np.arange(len(p)), n)
        dst = order[np.repeat(lo - (np.cumsum(n) - n), n) + np.arange(total)]
        keep = src < dst if off == [0, 0, 0] else src != dst
        I.append(src[keep])
        J.append(dst[keep])
    if not I:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    return np.concatenate(I), np.concatenate(J)


def _scatter_add(index, values, n):
    """sum of values (k, 3) into n rows by index; np.bincount per column is ~10x np.add.at."""
    return np.column_stack([np.bincount(index, weights=values[:, c], minlength=n) for c in range(3)])


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


class SelfContact(Effect):
    """Self-contact in two layers.
    collide: a cloth thickness. Vertices closer than `thickness` (x the mean rest edge length)
      that were farther apart at rest are pushed apart (found with a spatial hash). This keeps
      layers of cloth off each other, so the fail-safe below rarely has to act.
    contact: a fail-safe with conecull's own CCD. Every vertex of a pair that touches during
      the substep (conservative arithmetic: no contact is ever missed), and its `dilate` rings
      of neighbours, keeps its previous position, and the step is checked again until no
      contact is left (freezing everything is contact-free, so this ends). From an
      intersection-free state the cloth can then never pass through itself."""
    name = "self-contact"
    stages = ("collide", "contact")

    def __init__(self, thickness=0.8, max_rounds=50, dilate=2):
        self.thickness, self.max_rounds, self.dilate = thickness, max_rounds, dilate

    def setup(self, sim):
        import conecull

        self.col = conecull.SelfCollider(sim.mesh, method="nc")
        self.rest = sim.x.copy()
        e = sim.edges
        self.h = self.thickness * float(np.linalg.norm(sim.x[e[:, 1]] - sim.x[e[:, 0]], axis=1).mean())
        self.frozen_total = self.rounds = self.pushed = 0

    def collide(self, sim, dt):
        i, j = _close_pairs(sim.p, self.h)
        if len(i) == 0:
            return
        target = np.minimum(self.h, np.linalg.norm(self.rest[i] - self.rest[j], axis=1))
        d = sim.p[j] - sim.p[i]
        dist = np.sqrt(np.einsum("ij,ij->i", d, d))
        push = (dist < target) & (dist > 0.0)
        i, j, d, dist, target = i[push], j[push], d[push], dist[push], target[push]
        if len(i) == 0:
            return
        self.pushed += len(i)
        corr = (0.5 * (target - dist) / dist)[:, None] * d
        index = np.concatenate([i, j])
        delta = _scatter_add(index, np.concatenate([-corr, corr]), len(sim.p))
        count = np.bincount(index, minlength=len(sim.p))
        sim.p += delta / np.maximum(count, 1)[:, None]

    def contact(self, sim, dt):
        E = sim.edges
        for _ in range(self.max_rounds):
            self.rounds += 1
            res = self.col.ccd(sim.x, sim.p, arithmetic="conservative")
            if len(res.vf) == 0 and len(res.ee) == 0:
                return
            mark = np.zeros(len(sim.x), bool)
            mark[res.vf[:, 0]] = True
            mark[sim.faces[res.vf[:, 1]].ravel()] = True
            mark[E[res.ee.ravel()].ravel()] = True
            for _ in range(self.dilate):
                mark[E[mark[E[:, 0]] | mark[E[:, 1]]].ravel()] = True
            moving = np.flatnonzero(mark & np.any(sim.p != sim.x, axis=1))
            if len(moving) == 0:  # contact already at the start of the step: nothing to undo
                return
            sim.p[moving] = sim.x[moving]
            self.frozen_total += len(moving)
        sim.p[:] = sim.x  # out of rounds: stand still this substep (contact-free by the start state)


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
