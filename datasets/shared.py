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
    if den == 0:
        raise ValueError(f"{num}/{den} has a zero denominator")
    try:
        x = float(Fraction(num, den))
    except OverflowError:
        raise ValueError(f"{num}/{den} is beyond the range of a double") from None
    if Fraction(x) != Fraction(num, den):
        raise ValueError(f"{num}/{den} is not exactly a double")
    return x


def ccd_query_files(data: Path) -> list[Path]:
    """The query CSVs of data/ccd-queries (set/kind/file.csv), sorted; [] if the folder is absent."""
    root = Path(data) / "ccd-queries"
    return sorted(root.glob("*/*/*.csv")) if root.exists() else []


def load_ccd_queries(path: Path):
    """(kind 'vf'|'ee', points (q, 8, 3) float64, truth (q,) bool) from one CSV (8 rows a query,
    the rows in the order of vertex_face_ccd / edge_edge_ccd's arguments; 7 integer columns:
    x, y, z as numerator, denominator, then the query's truth, 0 or 1, the same on its 8 rows).
    A malformed file is a ValueError naming it and the row."""
    path = Path(path)
    try:
        text = path.read_text(encoding="ascii")
    except (OSError, UnicodeDecodeError) as e:
        raise ValueError(f"path: cannot read '{path}' ({e})") from None
    lines = [ln for ln in text.splitlines() if ln.strip()]
    if not lines or len(lines) % 8:
        raise ValueError(f"path: '{path}' has {len(lines)} rows; expected a positive multiple of 8 (8 rows a query)")
    pts, truth = np.zeros((len(lines), 3)), np.zeros(len(lines) // 8, dtype=bool)
    for k, line in enumerate(lines):
        where = f"'{path}' row {k + 1}"
        cells = line.split(",")
        if len(cells) != 7:
            raise ValueError(f"path: {where} has {len(cells)} columns; expected 7")
        try:
            r = [int(c) for c in cells]
        except ValueError:
            raise ValueError(f"path: {where} holds a value that is not an integer: {line.strip()!r}") from None
        try:
            pts[k] = [exact_double(r[0], r[1]), exact_double(r[2], r[3]), exact_double(r[4], r[5])]
        except ValueError as e:
            raise ValueError(f"path: {where}: {e}") from None
        if r[6] not in (0, 1) or (k % 8 and r[6] != truth[k // 8]):  # the query's other rows agree with its first
            raise ValueError(f"path: {where}: truth {r[6]}, expected 0 or 1 and the same on the query's 8 rows")
        truth[k // 8] = r[6] == 1
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

    def number(p):  # frames are numbered by the digits after their last '_'
        digits = "".join(c for c in p.stem.split("_")[-1] if c.isdigit())
        return (0, int(digits)) if digits else (1, 0)

    frames = sorted((d / "frames").glob("*.ply"), key=lambda p: (number(p), p.name))
    k = [i for i, p in enumerate(frames) if p.stem.split("_")[-1] == step]
    if not k or k[0] + 1 >= len(frames):
        raise ValueError(f"step: no frames {step} and the next one in '{d / 'frames'}'")

    def mesh(p):
        try:
            m = trimesh.load(p, process=False)
        except Exception as e:  # trimesh raises many kinds on a damaged file
            raise ValueError(f"{p}: cannot read this frame ({type(e).__name__}: {e})") from None
        if not isinstance(m, trimesh.Trimesh) or not len(m.faces):
            raise ValueError(f"{p}: not a triangle mesh")
        return m

    m0, m1 = mesh(frames[k[0]]), mesh(frames[k[0] + 1])
    F = np.asarray(m0.faces, np.int64)
    if not np.array_equal(F, np.asarray(m1.faces)):
        raise ValueError(f"{d}: faces differ between frames {frames[k[0]].name} and {frames[k[0] + 1].name}")
    V0, V1 = np.asarray(m0.vertices, np.float64), np.asarray(m1.vertices, np.float64)
    if V0.shape != V1.shape:
        raise ValueError(f"{d}: {len(V0)} vertices in {frames[k[0]].name} but {len(V1)} in {frames[k[0] + 1].name}")
    n = len(V0)
    e = np.unique(np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1), axis=0)  # ours: (i, j)
    theirs = e[np.lexsort((e[:, 0], e[:, 1]))]  # theirs: sorted by (larger, smaller)
    ours_id = {tuple(r): i for i, r in enumerate(e.tolist())}
    their_to_ours = np.array([ours_id[tuple(r)] for r in theirs.tolist()])
    n_edges, m = len(e), len(F)

    def read_json(path):
        try:
            with open(path) as f:
                return json.load(f)
        except (OSError, ValueError) as e:  # ValueError: JSONDecodeError, bad UTF-8
            raise ValueError(f"{path}: cannot read it as JSON ({e})") from None

    def truth(kind):
        """The candidates flagged true, as ids of ours. Box ids index one array: vertices [0, n),
        then edges [n, n + n_edges) (theirs), then faces (data.md): a VF row is (vertex, face), an
        EE row (edge, edge). An id outside its range, or a flag that is not a bool, is an error
        naming the file and row, never a wrong contact set."""
        boxes_path, flags_path = d / "boxes" / f"{step}{kind}.json", d / "mma_bool" / f"{step}{kind}_mma_bool.json"
        boxes, flags = read_json(boxes_path), read_json(flags_path)
        if not isinstance(boxes, list) or not isinstance(flags, list):
            raise ValueError(f"{boxes_path if not isinstance(boxes, list) else flags_path}: expected a JSON list")
        if len(boxes) != len(flags):  # zip would drop the tail silently
            raise ValueError(f"{d}: step {step} {kind}: {len(boxes)} candidate pairs in boxes/ but {len(flags)} "
                             "flags in mma_bool/")
        first = (0, n + n_edges) if kind == "vf" else (n, n)  # where each id's range starts
        size = (n, m) if kind == "vf" else (n_edges, n_edges)
        out = set()
        for row, (pair, hit) in enumerate(zip(boxes, flags)):
            if not isinstance(hit, bool):
                raise ValueError(f"{flags_path}: entry {row} is {hit!r}, expected true or false")
            ok = isinstance(pair, list) and len(pair) == 2 and all(type(x) is int for x in pair)
            if not ok or not all(0 <= x - lo < hi for x, lo, hi in zip(pair, first, size)):
                raise ValueError(f"{boxes_path}: entry {row} is {boxes[row]!r}, expected two box ids: "
                                 + ("a vertex in [0, n) and a face in [n + n_edges, n + n_edges + m)" if kind == "vf"
                                    else "two edges in [n, n + n_edges)") + f" with n = {n}, n_edges = {n_edges}, m = {m}")
            if not hit:
                continue
            i, j = pair
            if kind == "vf":
                out.add((i, j - n - n_edges))
            else:
                a, b = their_to_ours[i - n], their_to_ours[j - n]
                out.add((int(min(a, b)), int(max(a, b))))
        return out

    return F, V0, V1, truth("vf"), truth("ee")
