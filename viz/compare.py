"""Other methods run beside a viewer's own (`record(compare=...)`, the viser "methods at this
frame" panel, the compare screenshot): one collider per method, untraced queries, timed."""

from __future__ import annotations

import time


def compared_colliders(mesh, methods, V0) -> dict:
    """{method: collider}, each collider's BVH built from the first pose V0, as the viewer's own."""
    import conecull

    cols = {m: conecull.SelfCollider(mesh, method=m) for m in methods}
    for col in cols.values():
        col.dcd(V0)
    return cols


def timed_query(col, V, V1=None, arithmetic: str = "exact"):
    """(result, wall ms) of one untraced query: DCD at V, or CCD from V to V1."""
    t0 = time.perf_counter()
    res = col.dcd(V) if V1 is None else col.ccd(V, V1, arithmetic=arithmetic)
    return res, 1e3 * (time.perf_counter() - t0)
