"""Small analytic mesh generators and deforming sequences (kinematic: no simulation).

The kinematic scenes of the registry (registry.py) and the meshes of the demo, the benchmark
and the tests. Every function is deterministic.
"""

from __future__ import annotations

import numpy as np

from conecull.datasets.checks import count as _count, fits_in_memory, points, real, seed as _seed

# Bytes per vertex of a generated mesh, with its faces (about two per vertex) and temporaries.
_BYTES_PER_VERTEX = 24 + 2 * 24 + 48


def _frame_count(n_frames, n_vertices: int) -> int:
    """n_frames >= 1 whose positions (n_frames, n_vertices, 3) fit in memory."""
    n_frames = _count("n_frames", n_frames, 1)
    fits_in_memory("n_frames", n_frames * n_vertices * 24.0, f"{n_frames} frames of {n_vertices} vertices")
    return n_frames


def _query_ready(P: np.ndarray, args: str) -> np.ndarray:
    """P, if every coordinate is finite and within the queries' range (_api.RANGE_RULE), else a
    ValueError naming the arguments that scale it. Finite arguments can still overflow
    (crumpling_sphere(strength=1.7e308) gave inf with only NumPy's warning): a generator never
    hands out positions that every query would refuse."""
    from conecull._api import RANGE_RULE, _outside_range

    with np.errstate(invalid="ignore"):
        bad = ~np.isfinite(P) | _outside_range(P)
    if bad.any():
        v = float(P.flat[int(np.argmax(bad))])
        raise ValueError(f"{args}: the positions would reach {v!r}, which no query accepts (coordinates must be "
                         f"finite; {RANGE_RULE})")
    return P


def grid_sheet(nx: int, ny: int, width: float = 1.0, height: float = 1.0):
    """A flat (nx x ny)-vertex grid in the z = 0 plane, consistently oriented (+z normals).

    Returns faces (2 (nx-1)(ny-1), 3) int64 and positions (nx*ny, 3) float64.
    """
    nx, ny = _count("nx", nx, 2), _count("ny", ny, 2)
    width, height = real("width", width, 0.0), real("height", height, 0.0)
    fits_in_memory("nx, ny", nx * ny * _BYTES_PER_VERTEX, f"a {nx} x {ny} grid")
    xs = np.linspace(0.0, width, nx)
    ys = np.linspace(0.0, height, ny)
    X, Y = np.meshgrid(xs, ys)  # (ny, nx)
    V = np.column_stack([X.ravel(), Y.ravel(), np.zeros(nx * ny)])
    i, j = np.meshgrid(np.arange(ny - 1), np.arange(nx - 1), indexing="ij")
    a = (i * nx + j).ravel()
    b, c, d = a + 1, a + nx, a + nx + 1
    F = np.empty((2 * a.size, 3), dtype=np.int64)
    F[0::2] = np.column_stack([a, b, d])
    F[1::2] = np.column_stack([a, d, c])
    return F, _query_ready(V, "width, height")


def sheet_for_triangles(n_triangles: int):
    """A square grid sheet with about n_triangles triangles."""
    _count("n_triangles", n_triangles, 2)
    fits_in_memory("n_triangles", n_triangles / 2 * _BYTES_PER_VERTEX, f"a sheet of {n_triangles} triangles")
    side = max(2, int(round(np.sqrt(n_triangles / 2.0))) + 1)
    return grid_sheet(side, side)


def fold(V: np.ndarray, angle: float, x0: float = 0.5, radius: float = 0.05) -> np.ndarray:
    """Fold the sheet about the line x = x0 by `angle` radians (pi: flat onto itself).

    The part x > x0 wraps around a cylinder of the given radius, then continues straight, so
    the surface stays smooth; for angle > pi it passes through the other half.
    """
    V = points("V", V)  # finite and within the queries' range
    angle, x0 = real("angle", angle), real("x0", x0)
    radius = real("radius", radius, 0.0, low_open=True)  # the bend divides by it
    W = V.copy()
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is refused below, by name
        s = V[:, 0] - x0
        arc = radius * angle
        on = s > 0
        bend = on & (s <= arc)
        straight = on & (s > arc)
        t = s[bend] / radius
        W[bend, 0] = x0 + radius * np.sin(t)
        W[bend, 2] = V[bend, 2] + radius * (1.0 - np.cos(t))
        u = s[straight] - arc
        W[straight, 0] = x0 + radius * np.sin(angle) + u * np.cos(angle)
        W[straight, 2] = V[straight, 2] + radius * (1.0 - np.cos(angle)) + u * np.sin(angle)
    return _query_ready(W, "angle, x0, radius")


def folding_sheet(n_triangles: int = 2000, n_frames: int = 30, final_angle: float = 1.15 * np.pi):
    """A sheet folding onto itself: from flat to `final_angle` (past pi it self-intersects)."""
    F, V = sheet_for_triangles(n_triangles)
    n_frames = _frame_count(n_frames, len(V))
    final_angle = real("final_angle", final_angle)
    try:
        frames = np.stack([fold(V, final_angle * k / max(1, n_frames - 1)) for k in range(n_frames)])
    except ValueError as e:  # fold's angle is this final_angle's share
        raise ValueError(f"final_angle{str(e).partition(':')[1]}{str(e).partition(':')[2]}") from None
    return F, frames


def bending_sheet(n_triangles: int = 2000, n_frames: int = 30, amplitude: float = 0.15):
    """A gently bending sheet (a travelling wave): never self-intersects."""
    F, V = sheet_for_triangles(n_triangles)
    n_frames = _frame_count(n_frames, len(V))
    amplitude = real("amplitude", amplitude)
    frames = []
    for k in range(n_frames):
        phase = 2.0 * np.pi * k / max(1, n_frames)
        W = V.copy()
        W[:, 2] = amplitude * np.sin(2.0 * np.pi * V[:, 0] + phase) * np.cos(np.pi * (V[:, 1] - 0.5))
        frames.append(W)
    return F, _query_ready(np.stack(frames), "amplitude")


def uv_sphere(n_lat: int = 24, n_lon: int = 48, radius: float = 0.5):
    """A closed, consistently oriented (outward) UV sphere."""
    n_lat, n_lon = _count("n_lat", n_lat, 2), _count("n_lon", n_lon, 3)
    radius = real("radius", radius, 0.0)
    # before the Python loops below, which would run for hours before running out of memory
    fits_in_memory("n_lat, n_lon", n_lat * n_lon * 2 * _BYTES_PER_VERTEX, f"a {n_lat} x {n_lon} sphere")
    th = np.linspace(0.0, np.pi, n_lat + 1)[1:-1]
    ph = np.linspace(0.0, 2.0 * np.pi, n_lon, endpoint=False)
    T, Ph = np.meshgrid(th, ph, indexing="ij")
    ring = np.column_stack([np.sin(T).ravel() * np.cos(Ph).ravel(), np.sin(T).ravel() * np.sin(Ph).ravel(), np.cos(T).ravel()])
    V = np.vstack([[0.0, 0.0, 1.0], ring, [0.0, 0.0, -1.0]]) * radius
    south = len(V) - 1
    F = []
    for j in range(n_lon):
        F.append([0, 1 + j, 1 + (j + 1) % n_lon])
    for i in range(n_lat - 2):
        for j in range(n_lon):
            a = 1 + i * n_lon + j
            b = 1 + i * n_lon + (j + 1) % n_lon
            c = a + n_lon
            d = b + n_lon
            F.append([a, c, d])
            F.append([a, d, b])
    base = 1 + (n_lat - 2) * n_lon
    for j in range(n_lon):
        F.append([base + j, south, base + (j + 1) % n_lon])
    return np.array(F, dtype=np.int64), _query_ready(V, "radius")


def crumpling_sphere(n_lat: int = 24, n_lon: int = 48, n_frames: int = 30, strength: float = 0.6, seed: int = 0):
    """A sphere crumpling inwards under smooth random dents until it self-intersects."""
    F, V = uv_sphere(n_lat, n_lon)
    n_frames = _frame_count(n_frames, len(V))
    strength, seed = real("strength", strength), _seed("seed", seed)
    rng = np.random.default_rng(seed)
    centers = rng.standard_normal((12, 3))
    centers /= np.linalg.norm(centers, axis=1, keepdims=True)
    weights = rng.uniform(0.5, 1.0, 12)
    dirs = V / np.linalg.norm(V, axis=1, keepdims=True)
    dent = np.zeros(len(V))
    for c, w in zip(centers, weights):
        dent += w * np.exp(-((1.0 - dirs @ c) / 0.08))
    frames = []
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is refused below, by name
        for k in range(n_frames):
            s = strength * k / max(1, n_frames - 1)
            frames.append(V * (1.0 - s * dent)[:, None])
    return F, _query_ready(np.stack(frames), "strength")
