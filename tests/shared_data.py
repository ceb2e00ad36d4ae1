"""Access to ../shared/data (real CCD data with exact ground truth), by path, never copied.

Tests that need it skip with a clear reason when it is absent (a user's own clone); in CI it is
present, and there they must run (CI=true turns the skip into an error).
"""

from __future__ import annotations

import os
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

SHARED = Path(os.environ.get("CONECULL_SHARED", Path(__file__).resolve().parents[1].parent / "shared"))
DATA = SHARED / "data"


def require(path: Path) -> Path:
    if not path.exists():
        msg = f"shared data not found at {path} (clone the project next to ../shared, or set CONECULL_SHARED)"
        if os.environ.get("CI"):
            raise RuntimeError(msg)
        pytest.skip(msg)
    return path


def exact_double(num: int, den: int) -> float:
    """num/den as a double, asserting that it is exactly representable (the data promises it)."""
    x = float(Fraction(num, den))
    if Fraction(x) != Fraction(num, den):
        raise ValueError(f"{num}/{den} is not exactly a double")
    return x


def ccd_query_files():
    root = require(DATA / "ccd-queries")
    return sorted(root.glob("*/*/*.csv"))


def load_ccd_queries(path: Path):
    """(kind 'vf'|'ee', points (q, 8, 3) float64, truth (q,) bool) from one CSV (8 rows a query)."""
    rows = np.loadtxt(path, delimiter=",", dtype=object, ndmin=2)
    rows = np.array([[int(x) for x in r] for r in rows], dtype=object)
    pts = np.array([[exact_double(r[0], r[1]), exact_double(r[2], r[3]), exact_double(r[4], r[5])] for r in rows])
    truth = np.array([int(r[6]) for r in rows[::8]], dtype=bool)
    kind = "vf" if path.parent.name == "vertex-face" else "ee"
    return kind, pts.reshape(-1, 8, 3), truth


def scalable_ccd_steps():
    root = require(DATA / "scalable-ccd")
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
