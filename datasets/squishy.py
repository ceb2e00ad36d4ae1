"""A squishy ball with many tentacles squashed on the ground (stands in for the paper's
SquishyBall, Sec. 5.2): one closed, consistently oriented mesh, animated kinematically.

The body is a cube-sphere (six N x N grid patches, welded along the cube's edges), so square
blocks of cells can be cut out of the patches; each hole's boundary loop is extruded into a
tapering tube with a pointed tip. Tubes start square (they share the hole's loop) and round
off within a few rings. The squash is a smooth deformation of space: the ball drops, and every
point is lifted above the ground by a softplus (monotone in z, so it alone never makes two
points meet) and spread outwards by how much it was compressed, which presses the tentacles
lying on the ground against each other.
"""

from __future__ import annotations

import numpy as np

from conecull.datasets.checks import count, fits_in_memory, points, real, seed as _seed

# The cube's six faces: (normal axis, sign) and the two in-face axes, ordered so that
# (u axis) x (v axis) = sign * (normal axis): every patch cell (a, b, d) is then outward.
_PATCHES = ((0, 1, (1, 2)), (0, -1, (2, 1)), (1, 1, (2, 0)), (1, -1, (0, 2)), (2, 1, (0, 1)), (2, -1, (1, 0)))


def _holes(n: int):
    """4 x 4 square blocks of a = n / 8 cells cut out of every patch (96 tentacles): block side
    and the first cell of each block (i, j)."""
    a, step = max(1, n // 8), n // 4
    starts = [k * step + (step - a) // 2 for k in range(4)]
    return a, [(i, j) for i in starts for j in starts]


def squishy_counts(n: int) -> tuple[int, int]:
    """(triangles, vertices) of `squishy_ball(n)`, without building it: the body's cells less the
    holes, and per tentacle its rings of 4a vertices (two triangles per quad) and a tip."""
    n = count("n", n, 8)
    a, rings = max(1, n // 8), max(3, n // 3)
    return 2 * (6 * n * n - 96 * a * a) + 96 * (2 * rings * 4 * a + 4 * a), 6 * n * n + 2 + 96 * (rings * 4 * a + 1)


def squishy_ball(n: int = 160, tentacle_length: float = 1.0, curl: float = 0.35, seed: int = 0):
    """faces (m, 3), rest positions (p, 3) and, per vertex, the tentacle it belongs to (-1: body)
    with its parameter s in [0, 1] (0 at the body). About 9 n^2 + 32 n^2 triangles (body, tentacles)."""
    n = count("n", n, 8)  # 8 cells per cube side: the smallest with a cell per hole and room between holes
    tentacle_length, curl = real("tentacle_length", tentacle_length, 0.0, low_open=True), real("curl", curl)
    seed = _seed("seed", seed)
    fits_in_memory("n", squishy_counts(n)[1] * 200.0, f"a squishy ball with n = {n}")
    a, holes = _holes(n)
    rings = max(3, n // 3)
    rng = np.random.default_rng(seed)
    # lattice points on the cube surface, in integer coordinates 0..n, welded by np.unique
    keys = []
    g = np.arange(n + 1)
    I, J = np.meshgrid(g, g, indexing="ij")
    for axis, sign, (ua, va) in _PATCHES:
        P = np.zeros((n + 1, n + 1, 3), np.int64)
        P[..., axis] = n if sign > 0 else 0
        P[..., ua], P[..., va] = I, J
        keys.append(P.reshape(-1, 3))
    lattice, inverse = np.unique(np.concatenate(keys), axis=0, return_inverse=True)
    inverse = inverse.reshape(6, n + 1, n + 1)
    F, loops = [], []
    for p in range(6):
        ids = inverse[p]
        keep = np.ones((n, n), bool)
        for i0, j0 in holes:
            keep[i0:i0 + a, j0:j0 + a] = False
            # the hole's boundary loop, walked the way the patch's cells turn (u, then v, then back)
            loop = ([ids[i0 + k, j0] for k in range(a)] + [ids[i0 + a, j0 + k] for k in range(a)] +
                    [ids[i0 + a - k, j0 + a] for k in range(a)] + [ids[i0, j0 + a - k] for k in range(a)])
            loops.append(np.array(loop))
        ci, cj = np.nonzero(keep)
        A, B, C, D = ids[ci, cj], ids[ci + 1, cj], ids[ci, cj + 1], ids[ci + 1, cj + 1]
        F.append(np.column_stack([A, B, D]))
        F.append(np.column_stack([A, D, C]))
    body = lattice.astype(np.float64) * (2.0 / n) - 1.0
    body /= np.linalg.norm(body, axis=1, keepdims=True)  # onto the unit sphere
    V = [body]
    tentacle = [np.full(len(body), -1)]
    param = [np.zeros(len(body))]
    nv = len(body)
    for t, loop in enumerate(loops):
        m = len(loop)
        base = body[loop]
        c = base.mean(axis=0)
        axis_dir = c / np.linalg.norm(c)
        r0 = np.linalg.norm(base - c, axis=1).mean()
        # ring k >= 1: a circle (blending from the square loop) around a centreline that curls
        # sideways (quadratically in s), all in one swirl about z with a little randomness so
        # that neighbours curl alike instead of into each other; tapering
        s = np.arange(1, rings + 1) / (rings + 1)
        radius = r0 * (1.0 - 0.6 * s)
        swirl = np.cross([0.0, 0.0, 1.0], axis_dir)
        if np.linalg.norm(swirl) < 1e-9:
            # a hole centred on the top or bottom face (n = 9, 15, ...): its axis is vertical and
            # the swirl about z is undefined (0 / 0 made every later pose NaN); any side will do
            swirl = np.cross([1.0, 0.0, 0.0], axis_dir)
        side = swirl / np.linalg.norm(swirl) + 0.25 * rng.standard_normal(3)
        side -= (side @ axis_dir) * axis_dir
        side /= np.linalg.norm(side)
        blend = np.minimum(1.0, np.arange(1, rings + 1) / 3.0)[:, None, None]
        off = base - c
        off -= np.outer(off @ axis_dir, axis_dir)
        circle = off / np.linalg.norm(off, axis=1, keepdims=True) * r0
        shape = (1.0 - blend) * off[None] + blend * circle[None]  # (rings, m, 3) at radius r0
        centre = c + np.outer(s * tentacle_length, axis_dir) + np.outer(curl * tentacle_length * s * s, side)
        ring_pts = centre[:, None, :] + shape * (radius / r0)[:, None, None]
        tip = c + axis_dir * tentacle_length + curl * tentacle_length * side
        V += [ring_pts.reshape(-1, 3), tip[None]]
        tentacle += [np.full(rings * m + 1, t)]
        param += [np.repeat(s, m), [1.0]]
        ring_ids = [loop] + [nv + k * m + np.arange(m) for k in range(rings)]
        tip_id = nv + rings * m
        nv = tip_id + 1
        for lo, hi in zip(ring_ids[:-1], ring_ids[1:]):
            # the body's cells hold the loop's edges reversed, so the tube's quads hold them as
            # the loop walks: (lo[i], lo[i+1], hi[i+1]) contains lo[i] -> lo[i+1]
            lo1, hi1 = np.roll(lo, -1), np.roll(hi, -1)
            F.append(np.column_stack([lo, lo1, hi1]))
            F.append(np.column_stack([lo, hi1, hi]))
        last = ring_ids[-1]
        F.append(np.column_stack([last, np.roll(last, -1), np.full(m, tip_id)]))
    return (np.concatenate(F).astype(np.int64), np.concatenate(V), np.concatenate(tentacle),
            np.concatenate(param))


def squash(V: np.ndarray, height: float, squeeze: float, softness: float = 0.08) -> np.ndarray:
    """The ball (unit body, centre at the origin) with its centre at `height` above the ground
    z = 0, squeezed flat by `squeeze` in [0, 1): a smooth map of space, monotone in z."""
    V = points("V", V)
    height, squeeze = real("height", height), real("squeeze", squeeze, 0.0, 1.0, high_open=True)
    softness = real("softness", softness, 0.0, low_open=True)  # the softplus divides by it
    W = V.copy()
    W[:, 2] = W[:, 2] * (1.0 - 0.35 * squeeze) + height
    r_xy = np.linalg.norm(W[:, :2], axis=1)
    # lift above the ground: softness * softplus(z / softness) > 0, increasing in z (floored so
    # that no coordinate leaves the range conecull's exact predicates accept)
    lifted = np.maximum(softness * np.logaddexp(0.0, W[:, 2] / softness), 1e-9)
    pressed = lifted - W[:, 2]  # how far the ground pushed this point up: it goes outwards as far
    W[:, :2] *= (1.0 + 0.5 * squeeze + pressed / np.maximum(r_xy, 0.05))[:, None]
    W[:, 2] = lifted
    return W


def squishy_sequence(n: int = 160, frames: int = 20, tentacle_length: float = 1.0):
    """The ball falls onto the ground (the tentacles below it touch first) and squashes."""
    n, frames = count("n", n, 8), count("frames", frames, 1)
    fits_in_memory("frames", frames * squishy_counts(n)[1] * 24.0, f"{frames} frames with n = {n}")
    F, V, _, _ = squishy_ball(n, tentacle_length)
    top = 1.0 + tentacle_length + 0.1  # the lowest tip starts just above the ground
    out = []
    for k in range(frames):
        u = k / max(1, frames - 1)
        height = top - (top - 0.9) * min(1.0, u / 0.7)
        squeeze = 0.8 * max(0.0, (u - 0.4) / 0.6)
        out.append(squash(V, height, squeeze))
    return F, np.stack(out)
