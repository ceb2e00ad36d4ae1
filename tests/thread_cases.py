"""Shared by the threads= tests (tests/traversal/test_threads.py, tests/ccd/test_ccd_threads.py)."""

import functools

import numpy as np

from conecull.datasets.generated import crumpling_sphere, folding_sheet

THREADS = (1, 2, 3, 7)


def counters(stats):
    """The deterministic part of a stats dict (everything but the seconds)."""
    return {k: v for k, v in stats.items() if not k.startswith("seconds")}


@functools.lru_cache(maxsize=None)
def sequences():
    """Large enough that every stage really splits (many traversal tasks, many chunks); the
    interesting end of each, where contacts appear."""
    F1, P1 = folding_sheet(n_triangles=4000, n_frames=24, final_angle=1.2 * np.pi)
    F2, P2 = crumpling_sphere(n_lat=24, n_lon=56, n_frames=24, strength=0.8)
    return {"folding_sheet": (F1, P1[16:]), "crumpling_sphere": (F2, P2[16:])}
