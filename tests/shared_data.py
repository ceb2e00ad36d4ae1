"""Access to ../shared/data (real CCD data with exact ground truth), by path, never copied.

Tests that need it skip with a clear reason when it is absent (a user's own clone); in CI it is
present, and there they must run: `.ci/run` sets CONECULL_CI=1 (as CI=true does),
which turns the skip into an error. Nothing here raises or skips at import time, so a module that
needs the data never stops the collection of the others.
"""

from __future__ import annotations

import os
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

SHARED = Path(os.environ.get("CONECULL_SHARED", Path(__file__).resolve().parents[1].parent / "shared"))
DATA = SHARED / "data"


# What the data holds (notes/data.md): if a listing finds fewer, the data moved, and the tests
# that iterate over it must fail rather than shrink to nothing.
N_CCD_QUERY_FILES = 24
N_CCD_QUERIES = 2824
N_SCALABLE_STEPS = 4


def _missing(path: Path) -> str:
    return f"shared data not found at {path} (clone the project next to ../shared, or set CONECULL_SHARED)"


def in_ci() -> bool:
    """CI (`.ci/run` sets CONECULL_CI=1): everything optional must be present and run."""
    return _required()


def _required() -> bool:
    return bool(os.environ.get("CONECULL_CI") or os.environ.get("CI"))


def require(path: Path) -> Path:
    """Inside a test: the path, or skip (an error where the data is required)."""
    if not path.exists():
        if _required():
            raise RuntimeError(_missing(path))
        pytest.skip(_missing(path))
    return path


def import_or_skip(module: str, reason: str):
    """An optional test dependency: skip without it, except where CI requires everything."""
    try:
        return __import__(module, fromlist=["_"])
    except ImportError:
        if _required():
            raise RuntimeError(f"{module} is required in CI: {reason}")
        pytest.skip(f"{module} not installed: {reason}")


def params(items, ids, path: Path, arity: int = 1):
    """Parametrize over the data's items. When the data is absent: one case "absent" that skips
    with the reason (instead of an empty parameter set, which would pass silently), or, where the
    data is required, runs; such a test starts with require(path), which then fails."""
    if path.exists():
        return [pytest.param(*(x if arity > 1 else (x,)), id=i) for x, i in zip(items, ids)]
    marks = () if _required() else pytest.mark.skip(reason=_missing(path))
    return [pytest.param(*([None] * arity), id="absent", marks=marks)]


def exact_double(num: int, den: int) -> float:
    """num/den as a double, asserting that it is exactly representable (the data promises it)."""
    x = float(Fraction(num, den))
    if Fraction(x) != Fraction(num, den):
        raise ValueError(f"{num}/{den} is not exactly a double")
    return x


def ccd_query_files():
    """The query CSVs, [] when the data is absent (collection-safe)."""
    root = DATA / "ccd-queries"
    return sorted(root.glob("*/*/*.csv")) if root.exists() else []


def load_ccd_queries(path: Path):
    """(kind 'vf'|'ee', points (q, 8, 3) float64, truth (q,) bool) from one CSV (8 rows a query)."""
    rows = np.loadtxt(path, delimiter=",", dtype=object, ndmin=2)
    rows = np.array([[int(x) for x in r] for r in rows], dtype=object)
    pts = np.array([[exact_double(r[0], r[1]), exact_double(r[2], r[3]), exact_double(r[4], r[5])] for r in rows])
    truth = np.array([int(r[6]) for r in rows[::8]], dtype=bool)
    kind = "vf" if path.parent.name == "vertex-face" else "ee"
    return kind, pts.reshape(-1, 8, 3), truth


def scalable_ccd_steps():
    """(scene, step) of every scalable-ccd step, [] when the data is absent (collection-safe)."""
    root = DATA / "scalable-ccd"
    if not root.exists():
        return []
    steps = []
    for scene in sorted(p for p in root.iterdir() if p.is_dir()):
        for vf in sorted((scene / "boxes").glob("*vf.json")):
            steps.append((scene.name, vf.name[: -len("vf.json")]))
    return steps


def load_scalable_step(scene: str, step: str):
    """faces (m, 3), V0, V1 (n, 3), and the ground-truth sets: vf {(vertex, face)}, ee {(edge a, edge b)}
    with edge ids of conecull.Mesh(faces).edges (the data numbers edges by (larger, smaller) vertex)."""
    import json

    import trimesh

    d = require(DATA / "scalable-ccd" / scene)
    frames = sorted((d / "frames").glob("*.ply"), key=lambda p: int("".join(c for c in p.stem.split("_")[-1] if c.isdigit())))
    k = [i for i, p in enumerate(frames) if p.stem.split("_")[-1] == step]
    m0 = trimesh.load(frames[k[0]], process=False)
    m1 = trimesh.load(frames[k[0] + 1], process=False)
    F = np.asarray(m0.faces, np.int64)
    assert np.array_equal(F, np.asarray(m1.faces)), "faces differ between the two frames"
    V0, V1 = np.asarray(m0.vertices, np.float64), np.asarray(m1.vertices, np.float64)
    n = len(V0)
    e = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    e = np.unique(e, axis=0)                   # ours: sorted by (i, j), i < j
    theirs = e[np.lexsort((e[:, 0], e[:, 1]))]  # theirs: sorted by (larger, smaller)
    ours_id = {tuple(r): i for i, r in enumerate(e.tolist())}
    their_to_ours = np.array([ours_id[tuple(r)] for r in theirs.tolist()])
    nE = len(e)

    def truth(kind):
        boxes = json.load(open(d / "boxes" / f"{step}{kind}.json"))
        flags = json.load(open(d / "mma_bool" / f"{step}{kind}_mma_bool.json"))
        out = set()
        for (i, j), f in zip(boxes, flags):
            if not f:
                continue
            if kind == "vf":
                out.add((int(i), int(j) - n - nE))
            else:
                a, b = their_to_ours[i - n], their_to_ours[j - n]
                out.add((min(a, b), max(a, b)))
        return out

    return F, V0, V1, truth("vf"), truth("ee")
