"""Small random meshes for property tests (the oracle cases live in meshcases.py)."""

import numpy as np

from conecull.datasets.generated import grid_sheet, uv_sphere


def wavy_sheet(n=12, amp=0.2, noise=0.0, seed=0):
    F, V = grid_sheet(n, n)
    rng = np.random.default_rng(seed)
    kx, ky = rng.uniform(1, 3, 2)
    V = V.copy()
    V[:, 2] = amp * np.sin(kx * V[:, 0] * np.pi) * np.cos(ky * V[:, 1] * np.pi)
    V += noise * rng.standard_normal(V.shape)
    return F, V


def noisy_sphere(n_lat=8, n_lon=12, noise=0.02, seed=0):
    F, V = uv_sphere(n_lat, n_lon)
    rng = np.random.default_rng(seed)
    return F, V + noise * rng.standard_normal(V.shape)


def random_meshes():
    yield "sheet-smooth", *wavy_sheet(12, 0.1, 0.0, 1)
    yield "sheet-noisy", *wavy_sheet(12, 0.3, 0.01, 2)
    yield "sheet-rough", *wavy_sheet(10, 0.5, 0.05, 3)
    yield "sphere", *noisy_sphere(8, 12, 0.0, 4)
    yield "sphere-noisy", *noisy_sphere(8, 12, 0.05, 5)
