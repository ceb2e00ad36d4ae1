"""Loaders for the real data with exact ground truth in ../shared/data (read by path, never
copied; formats in shared/notes/data.md):

- ccd-queries: single vertex-face and edge-edge CCD queries as exact rationals (CSV, 8 rows a
  query), many hand-crafted degenerate ones;
- scalable-ccd: whole simulation steps (two PLY frames) with the exact set of VF and EE contacts.

The tests (tests/shared_data.py adds their skip rules) and `conecull bench` read the data
through these functions.
"""

from __future__ import annotations

import json
import os
from fractions import Fraction
from pathlib import Path

import numpy as np


def shared_data_dir() -> Path | None:
    """The data folder: $CONECULL_SHARED/data if that variable is set, else ../shared/data beside
    the working directory or beside this source checkout; None if there is none."""
    env = os.environ.get("CONECULL_SHARED")
    if env:
        return Path(env) / "data" if (Path(env) / "data").exists() else None
    for cand in (Path.cwd().parent / "shared", Path(__file__).resolve().parents[2] / "shared"):
        if (cand / "data").exists():
            return cand / "data"
    return None


def shared_data_missing() -> str:
    """Where shared_data_dir() looked, for a message when it found nothing."""
    env = os.environ.get("CONECULL_SHARED")
    if env:
        return f"no data folder at $CONECULL_SHARED/data ({Path(env) / 'data'}; the variable, when set, replaces ../shared)"
    return "no ../shared/data beside the working directory or this checkout (or set CONECULL_SHARED to its parent)"


def exact_double(num: int, den: int) -> float:
    """num/den as a double, refusing a value the data promises to be exact but is not."""
    x = float(Fraction(num, den))
    if Fraction(x) != Fraction(num, den):
        raise ValueError(f"{num}/{den} is not exactly a double")
    return x


def ccd_query_files(data: Path) -> list[Path]:
    """The query CSVs of data/ccd-queries (set/kind/file.csv), sorted; [] if the folder is absent."""
    root = Path(data) / "ccd-queries"
    return sorted(root.glob("*/*/*.csv")) if root.exists() else []


def load_ccd_queries(path: Path):
    """(kind 'vf'|'ee', points (q, 8, 3) float64, truth (q,) bool) from one CSV (8 rows a query,
    the rows in the order of vertex_face_ccd / edge_edge_ccd's arguments)."""
    path = Path(path)
    rows = np.loadtxt(path, delimiter=",", dtype=object, ndmin=2)
    rows = [[int(x) for x in r] for r in rows]
    pts = np.array([[exact_double(r[0], r[1]), exact_double(r[2], r[3]), exact_double(r[4], r[5])] for r in rows])
    truth = np.array([r[6] for r in rows[::8]], dtype=bool)
    kind = "vf" if path.parent.name == "vertex-face" else "ee"
    return kind, pts.reshape(-1, 8, 3), truth


def scalable_ccd_steps(data: Path) -> list[tuple[str, str]]:
    """(scene, step) of every step of data/scalable-ccd; [] if the folder is absent."""
    root = Path(data) / "scalable-ccd"
    if not root.exists():
        return []
    return [(scene.name, vf.name[: -len("vf.json")]) for scene in sorted(p for p in root.iterdir() if p.is_dir())
            for vf in sorted((scene / "boxes").glob("*vf.json"))]


def load_scalable_step(data: Path, scene: str, step: str):
    """faces (m, 3), V0, V1 (n, 3), and the ground-truth contact sets: vf {(vertex, face)} and ee
    {(edge a, edge b)}, a < b, with edge ids of conecull.Mesh(faces).edges (the data numbers
    edges by (larger, smaller) vertex; see data.md)."""
    import trimesh

    d = Path(data) / "scalable-ccd" / scene
    frames = sorted((d / "frames").glob("*.ply"), key=lambda p: int("".join(c for c in p.stem.split("_")[-1] if c.isdigit())))
    k = [i for i, p in enumerate(frames) if p.stem.split("_")[-1] == step]
    if not k or k[0] + 1 >= len(frames):
        raise ValueError(f"step: no frames {step} and the next one in '{d / 'frames'}'")
    m0 = trimesh.load(frames[k[0]], process=False)
    m1 = trimesh.load(frames[k[0] + 1], process=False)
    F = np.asarray(m0.faces, np.int64)
    if not np.array_equal(F, np.asarray(m1.faces)):
        raise ValueError(f"{d}: faces differ between frames {frames[k[0]].name} and {frames[k[0] + 1].name}")
    V0, V1 = np.asarray(m0.vertices, np.float64), np.asarray(m1.vertices, np.float64)
    n = len(V0)
    e = np.unique(np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1), axis=0)  # ours: (i, j)
    theirs = e[np.lexsort((e[:, 0], e[:, 1]))]  # theirs: sorted by (larger, smaller)
    ours_id = {tuple(r): i for i, r in enumerate(e.tolist())}
    their_to_ours = np.array([ours_id[tuple(r)] for r in theirs.tolist()])
    n_edges = len(e)

    def truth(kind):
        with open(d / "boxes" / f"{step}{kind}.json") as f:
            boxes = json.load(f)
        with open(d / "mma_bool" / f"{step}{kind}_mma_bool.json") as f:
            flags = json.load(f)
        if len(boxes) != len(flags):  # zip would drop the tail silently
            raise ValueError(f"{d}: step {step} {kind}: {len(boxes)} candidate pairs in boxes/ but {len(flags)} "
                             "flags in mma_bool/")
        out = set()
        for (i, j), hit in zip(boxes, flags):
            if not hit:
                continue
            if kind == "vf":
                out.add((int(i), int(j) - n - n_edges))
            else:
                a, b = their_to_ours[i - n], their_to_ours[j - n]
                out.add((int(min(a, b)), int(max(a, b))))
        return out

    return F, V0, V1, truth("vf"), truth("ee")
