"""A keyframed skirt with ruffles (stands in for the paper's Flamenco, Sec. 5.2): kinematic.

The skirt is an open tube (waist ring to hem ring). Its shape is a handful of parameters
(flare, ruffle depth, twist of the hem against the waist, hem lift); a dance is a list of
keyframes of those parameters, interpolated with smoothstep in between. Deep ruffles twisted
against each other make the neighbouring folds press together, as a spinning skirt does.
"""

from __future__ import annotations

import numpy as np

from conecull.datasets.checks import count, fits_in_memory

# (time, flare, ruffle depth, hem twist [rad], hem lift, fold lean): rest, spin one way, swing
# back, settle. The folds lean over sideways (tangential shift `lean * cos`); once
# lean * folds exceeds the radius the hem's curve doubles back on itself: the folds overlap.
KEYFRAMES = ((0.00, 0.10, 0.015, 0.0, 0.00, 0.000),
             (0.30, 0.45, 0.045, 1.2, 0.10, 0.010),
             (0.55, 0.50, 0.050, -0.2, 0.16, -0.016),
             (0.80, 0.35, 0.050, -1.4, 0.08, -0.022),
             (1.00, 0.15, 0.030, -0.3, 0.00, -0.004))


def tube_grid(n_around: int, n_along: int):
    """An open tube: n_along rings of n_around vertices (ring j starts at index j * n_around),
    faces oriented outwards when rings go downwards (-z) with angle increasing anticlockwise."""
    n_around, n_along = count("n_around", n_around, 3), count("n_along", n_along, 2)
    fits_in_memory("n_around, n_along", n_around * n_along * 48.0, f"a tube of {n_around} x {n_along} vertices")
    i, j = np.meshgrid(np.arange(n_around), np.arange(n_along - 1), indexing="ij")
    a = (j * n_around + i).ravel()
    b = (j * n_around + (i + 1) % n_around).ravel()
    c, d = a + n_around, b + n_around
    F = np.empty((2 * a.size, 3), np.int64)
    F[0::2] = np.column_stack([a, c, d])
    F[1::2] = np.column_stack([a, d, b])
    return F


def _pose(n_around: int, n_along: int, flare, depth, twist, lift, lean, folds=28, waist=0.14, length=0.55):
    th = np.linspace(0.0, 2.0 * np.pi, n_around, endpoint=False)
    v = np.linspace(0.0, 1.0, n_along)
    T, Vv = np.meshgrid(th, v)  # (n_along, n_around): ring j = row j
    # ruffles deepen towards the hem; the hem lags behind the waist by `twist` (quadratically in v)
    ruffle = depth * Vv ** 1.5 * np.sin(folds * T)
    radius = waist + flare * length * Vv + ruffle
    angle = T + twist * Vv ** 2 + lean * Vv ** 1.5 * np.cos(folds * T) / radius
    z = -length * Vv * (1.0 - lift * Vv)
    return np.column_stack([(radius * np.cos(angle)).ravel(), (radius * np.sin(angle)).ravel(), z.ravel()])


def skirt_sequence(resolution: int = 70, frames: int = 60):
    """faces and positions (frames, n, 3) of the skirt: resolution+1 rings of 5*resolution
    vertices, 10 resolution^2 triangles (49,000 at the default 70)."""
    resolution, frames = count("resolution", resolution, 1), count("frames", frames, 1)
    n_around, n_along = 5 * resolution, resolution + 1
    fits_in_memory("resolution", n_around * n_along * 200.0, f"a skirt at resolution {resolution}")
    fits_in_memory("frames", frames * n_around * n_along * 24.0, f"{frames} frames at resolution {resolution}")
    F = tube_grid(n_around, n_along)
    keys = np.array(KEYFRAMES)
    out = []
    for k in range(frames):
        u = k / max(1, frames - 1)
        s = min(np.searchsorted(keys[:, 0], u, side="right") - 1, len(keys) - 2)
        w = (u - keys[s, 0]) / (keys[s + 1, 0] - keys[s, 0])
        w = w * w * (3.0 - 2.0 * w)  # smoothstep: the skirt eases in and out of each keyframe
        params = (1.0 - w) * keys[s, 1:] + w * keys[s + 1, 1:]
        out.append(_pose(n_around, n_along, *params))
    return F, np.stack(out)
