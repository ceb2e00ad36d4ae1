"""The effect interface, and the vectorised scatter every effect shares."""

from __future__ import annotations

import numpy as np

class Effect:
    name: str = ""       # what a scene declares to get this effect
    stages: tuple = ()

    def setup(self, sim) -> None:  # precomputation from the rest pose
        pass


def _scatter_add(index, values, n):
    """sum of values (k, 3) into n rows by index; np.bincount per column is ~10x np.add.at."""
    return np.column_stack([np.bincount(index, weights=values[:, c], minlength=n) for c in range(3)])


def _vertex_mean(index, values, n):
    """Jacobi averaging: vertex index[k] asks to move by values[k]; each vertex moves by the mean
    of what it is asked (0 if nothing)."""
    return _scatter_add(index, values, n) / np.maximum(np.bincount(index, minlength=n), 1)[:, None]


def _pair_mean(i, j, di, dj, n):
    """_vertex_mean for pair constraints: vertex i[k] asks to move by di[k] and j[k] by dj[k]."""
    return _vertex_mean(np.concatenate([i, j]), np.concatenate([di, dj]), n)
