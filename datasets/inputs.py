"""Mesh sequences for the CLI and the viewers: built-in generated scenes or files on disk.

`load_sequence(INPUT)` returns (faces (m, 3) int64, frames (T, n, 3) float64). INPUT is a scene
name (`scene_names()`), a folder of OBJ/PLY frames with identical faces, or one mesh file plus
an .npz of positions (T, n, 3) given with `positions=`.
"""

from __future__ import annotations

import os
import re
import warnings
from decimal import Decimal

import numpy as np

from conecull.datasets import checks


DEFAULT_SCENE = "fold"


def scene_names() -> list[str]:
    from conecull.datasets.registry import names

    return names()


def _load_mesh(path: str):
    """Faces (m, 3) int64, vertices (n, 3) float64 and how many of the file's faces had more than
    3 corners (split into triangles), with the file's own vertex ids and face order."""
    if path.lower().endswith(".obj"):
        F, V, polygons = _read_obj(path)
    else:
        F, V, polygons = _read_with_trimesh(path)
    if len(F) == 0:
        raise ValueError(f"{path}: no triangles in this file")
    try:  # here, where the file is known: later the same error could not say which file it is in
        V = checks.points("vertices", V)
    except ValueError as e:
        raise ValueError(f"{path}: {e}") from None
    return F, V, polygons


def _triangles(faces: list, where, n_vertices: int, first: int = 0) -> tuple[np.ndarray, int]:
    """Faces (lists of corner ids, counted from 0) as triangles in file order, and how many had
    more than 3 corners: a face of k > 3 corners becomes the fan (c0, c1, c2), (c0, c2, c3), ...
    of k - 2 triangles. Each face is checked first, where(k) naming face k in the messages (the
    rows of the triangles would not be the file's faces), with vertex ids shown counted from
    `first`, as the file counts them."""
    if all(len(f) == 3 for f in faces):  # the usual case, checked at once (the loop names a bad face)
        F = np.array(faces, dtype=np.int64).reshape(-1, 3)
        if ((F >= 0) & (F < n_vertices)).all() and (F[:, [0, 1, 2]] != F[:, [1, 2, 0]]).all():
            return F, 0
    out, polygons = [], 0
    for k, f in enumerate(faces):
        if len(f) < 3:
            raise ValueError(f"{where(k)}: a face needs at least 3 vertices, this one has {len(f)}")
        if len(set(f)) < len(f):
            raise ValueError(f"{where(k)}: a face repeats a vertex: {[c + first for c in f]} (counted from {first})")
        bad = next((c for c in f if not 0 <= c < n_vertices), None)
        if bad is not None:
            raise ValueError(f"{where(k)}: a face refers to vertex {bad + first} (counted from {first}), but the file "
                             f"has {n_vertices} vertices")
        if len(f) > 3:
            polygons += 1
            out.extend((f[0], f[i], f[i + 1]) for i in range(1, len(f) - 1))
        else:
            out.append(f)
    return np.array(out, dtype=np.int64).reshape(-1, 3), polygons


def _shown(line: bytes) -> str:
    return repr(line.strip().decode(errors="replace")[:80])


def _read_obj(path: str):
    """An OBJ's vertices and faces as the file numbers them. Not trimesh's reader: it splits
    vertices at material groups (usemtl) and orders faces by material, so the ids reported were
    not the file's (and a flat sheet in two materials came out in two pieces, colliding)."""
    try:
        with open(path, "rb") as fh:
            text = fh.read()
    except OSError as e:
        raise ValueError(f"{path}: cannot read mesh ({type(e).__name__}: {e})") from None
    V, faces, lines = [], [], []
    continued = b""
    rows = text.split(b"\n")
    for number, raw in enumerate(rows, 1):
        line = continued + raw.rstrip(b"\r")
        if line.endswith(b"\\"):  # continued on the next line
            continued = line[:-1] + b" "
            continue
        continued = b""
        words = line.split(b"#", 1)[0].split()
        if not words:
            continue
        if words[0] == b"v":
            try:
                xyz = [float(w) for w in words[1:4]]
            except ValueError:
                xyz = []
            if len(xyz) < 3:
                raise ValueError(f"{path}: line {number}: a vertex needs 3 coordinates ({_shown(line)})")
            V.append(xyz)
        elif words[0] == b"f":
            face = []
            for w in words[1:]:
                try:
                    i = int(w.split(b"/", 1)[0])
                except ValueError:
                    raise ValueError(f"{path}: line {number}: a face's vertex must be a number ({_shown(line)})") from None
                if i == 0:  # OBJ counts from 1, and negative values back from the last vertex so far
                    raise ValueError(f"{path}: line {number}: a face refers to vertex 0, but OBJ counts vertices "
                                     f"from 1 ({_shown(line)})")
                if -i > len(V):
                    raise ValueError(f"{path}: line {number}: a face refers to vertex {i}, counted back from the "
                                     f"last one, but only {len(V)} come before it ({_shown(line)})")
                face.append(i - 1 if i > 0 else len(V) + i)
            faces.append(face)
            lines.append(number)
    # Checked once all are read: vertices listed after the faces that use them are allowed.
    F, polygons = _triangles(faces, lambda k: f"{path}: line {lines[k]} ({_shown(rows[lines[k] - 1])})", len(V), 1)
    return F, np.array(V, dtype=np.float64).reshape(-1, 3), polygons


def _ply_corners(data):
    """The corner lists of a PLY's faces as trimesh read them: a dict of arrays (ASCII), or a
    structured array (binary: per face, its corner count 'f0' and corners 'f1'); None if neither."""
    if isinstance(data, dict):
        return data.get("vertex_indices", data.get("vertex_index"))
    if isinstance(data, np.ndarray) and data.dtype.names:
        name = next((n for n in ("vertex_indices", "vertex_index") if n in data.dtype.names), None)
        lists = data[name] if name else None
        if lists is not None and lists.dtype.names == ("f0", "f1"):
            count, corners = lists["f0"], lists["f1"].reshape(len(lists), -1)
            if (count == corners.shape[1]).all():
                return corners
            return [list(c[:k]) for c, k in zip(corners, count)]
    return None


def _read_with_trimesh(path: str):
    import trimesh

    try:
        m = trimesh.load(path, process=False, force="mesh")  # process=False: no vertex merged
    except Exception as e:  # trimesh raises many types for unreadable files
        raise ValueError(f"{path}: cannot read mesh ({type(e).__name__}: {e})") from None
    if not hasattr(m, "faces") or len(m.faces) == 0:
        raise ValueError(f"{path}: no triangles in this file")
    # A PLY's faces as the file lists them: trimesh drops faces of 2 corners and splits polygons
    # its own way, silently.
    face = (m.metadata.get("_ply_raw") or {}).get("face", {})
    corners = _ply_corners(face.get("data"))
    if corners is None:  # not a PLY, or a layout not known here: trimesh's faces, if one per face of the file
        if "length" in face and face["length"] != len(m.faces):
            raise ValueError(f"{path}: {face['length']} faces in the file but {len(m.faces)} triangles read: "
                             "cannot tell which triangle is which face; triangulate the file first")
        return np.asarray(m.faces, dtype=np.int64), np.asarray(m.vertices), 0
    if isinstance(corners, np.ndarray) and corners.ndim == 2 and corners.shape[1] == 3:  # all triangles
        return corners.astype(np.int64), np.asarray(m.vertices), 0
    F, polygons = _triangles([[int(c) for c in f] for f in corners], lambda k: f"{path}: face {k} (counted from 0)",
                             len(m.vertices))
    return F, np.asarray(m.vertices), polygons


def _check_faces(path: str, F: np.ndarray, n_vertices: int) -> None:
    """The mesh's own checks (indices, repeated vertices), with the file named."""
    import conecull

    if F.size and F.max() >= n_vertices:  # else Mesh would blame its n_vertices, which no one passed here
        r = int(np.argmax(F.max(axis=1)))
        raise ValueError(f"{path}: faces: row {r} refers to vertex {int(F[r].max())} (counted from 0), but the file "
                         f"has {n_vertices} vertices")
    try:
        conecull.Mesh(F, n_vertices=n_vertices)
    except ValueError as e:
        raise ValueError(f"{path}: {e}") from None


def _frame_key(name: str):
    """Compares names part by part: numbers (digit runs, with a decimal fraction if they have
    one) as numbers, the rest as lower-case text."""
    parts = re.split(r"(\d+(?:\.\d+)?)", name)  # text at even indices, numbers at odd: comparable part by part
    return [Decimal(t) if i % 2 else t.lower() for i, t in enumerate(parts)]


def frame_order(names: list[str]) -> list[str]:
    """File names in frame order: by their numbers, not their text (frame2 before frame10, and
    t0.25 before t0.5), so unpadded and time-stamped numbering work. Names compare part by part
    (`_frame_key`); names with equal keys (frame1, frame01) keep their plain text order, and a
    folder holding such names is refused by `load_sequence`. Names without a consistent numbering
    (a.ply, b2.ply, b10.ply) still get this one deterministic order, which need not be the
    intended one."""
    return sorted(names, key=lambda name: (_frame_key(name), name))


def load_sequence(source: str, positions: str | None = None, resolution: int | None = None):
    """Faces (m, 3) and frames (T, n, 3) from a scene name or path (see module doc). A folder's
    frames are its .obj/.ply files in `frame_order` (by the numbers in their names)."""
    from conecull.datasets.registry import SCENES, load

    if isinstance(source, os.PathLike):
        source = os.fspath(source)
    if isinstance(positions, os.PathLike):
        positions = os.fspath(positions)
    if not isinstance(source, str):
        raise ValueError(f"INPUT: expected a scene name or a path, got {type(source).__name__}")
    if source in SCENES and not os.path.exists(source):
        if positions is not None:
            raise ValueError(f"positions: only with a single mesh file, not with the scene '{source}'")
        return load(source, resolution=resolution)
    if not os.path.exists(source):
        raise FileNotFoundError(f"INPUT: '{source}' is neither a scene ({', '.join(SCENES)}) nor an existing path")
    if resolution is not None:
        raise ValueError(f"resolution: only for a built-in scene, not for '{source}'")
    if os.path.isdir(source):
        if positions is not None:
            raise ValueError("positions: only with a single mesh file, not with a folder of frames")
        files = frame_order([f for f in os.listdir(source) if f.lower().endswith((".obj", ".ply"))])
        if not files:
            raise ValueError(f"INPUT: folder '{source}' has no .obj or .ply frames")
        kinds = {os.path.splitext(f)[1].lower() for f in files}
        if len(kinds) > 1:  # one sequence twice over, or two sequences: which is meant is not ours to guess
            raise ValueError(f"INPUT: folder '{source}' holds both .obj and .ply files; put one sequence of one "
                             "format in a folder")
        for a, b in zip(files, files[1:]):
            if _frame_key(a) == _frame_key(b):
                raise ValueError(f"INPUT: '{a}' and '{b}' in folder '{source}' have the same frame number")
        F0, frames = None, []
        for name in files:
            F, V, polygons = _load_mesh(os.path.join(source, name))
            if F0 is None:
                _check_faces(os.path.join(source, name), F, len(V))
                _warn_polygons(polygons, name)
                F0 = F
            elif F.shape != F0.shape or not np.array_equal(F, F0):
                raise ValueError(f"INPUT: frame '{name}' has different faces than '{files[0]}' (topology must not change)")
            if frames and len(V) != len(frames[0]):
                raise ValueError(f"INPUT: frame '{name}' has {len(V)} vertices, '{files[0]}' has {len(frames[0])}")
            frames.append(V)
        return F0, np.stack(frames)
    F, V, polygons = _load_mesh(source)
    _check_faces(source, F, len(V))
    _warn_polygons(polygons, os.path.basename(source))
    if positions is None:
        return F, V[None]
    if not os.path.exists(positions):
        raise FileNotFoundError(f"positions: '{positions}' does not exist")
    if not positions.lower().endswith((".npz", ".npy")):
        raise ValueError(f"positions: '{positions}' is not an .npz or .npy file (the frames of a mesh file go in "
                         "a folder of frames instead)")
    try:
        loaded = np.load(positions, allow_pickle=False)
        if isinstance(loaded, np.ndarray):  # an .npy: the array itself
            raw, shown = loaded, positions
        else:
            with loaded as z:
                if len(z.files) > 1 and "positions" not in z.files:
                    raise LookupError(f"positions: '{positions}' holds the arrays {', '.join(z.files)}, none named "
                                      "'positions': name the frames (T, n, 3) 'positions'")
                key = "positions" if "positions" in z.files else z.files[0] if z.files else None
                raw = z[key] if key else None
                shown = positions if key == "positions" else f"{positions}' array '{key}"  # the one array, named
    except LookupError as e:
        raise ValueError(str(e)) from None
    except Exception as e:
        raise ValueError(f"positions: cannot read '{positions}' as .npz or .npy ({e})") from None
    if raw is None:
        raise ValueError(f"positions: '{positions}' holds no array")
    # real (complex would lose its imaginary part, silently), (T >= 1, n, 3), finite: each
    # message names the file (and the array read), and the frame of a non-finite coordinate
    return F, checks.frames("positions", raw, n_vertices=len(V), source=shown)


def _warn_polygons(polygons: int, name: str) -> None:
    if polygons:
        warnings.warn(f"INPUT: {polygons} face{'s' if polygons != 1 else ''} of '{name}' with more than 3 corners "
                      f"{'were' if polygons != 1 else 'was'} split into triangles (a fan from each face's first corner, in file order): triangle "
                      "ids count these triangles, not the file's faces", stacklevel=3)


def parse_frames(spec: str | None, n_frames: int) -> range:
    """'A:B' (B exclusive, either side optional) or 'K' -> a range of frame indices, each in
    [0, n_frames): no negative (from the end) indices and no silent clamping to the input."""
    if not spec:
        return range(n_frames)
    try:
        if ":" in spec:
            a, b = spec.split(":", 1)
            start, stop = int(a) if a.strip() else 0, int(b) if b.strip() else n_frames
        else:
            start = int(spec)
            stop = start + 1
    except ValueError:
        raise ValueError(f"--frames: expected A:B or K, got '{spec}'") from None
    have = f"the input has {n_frames} frame{'s' if n_frames != 1 else ''} (0..{n_frames - 1})"
    if start < 0 or stop < 0:
        raise ValueError(f"--frames: '{spec}': frames are counted from 0 (not from the end); {have}")
    if start >= n_frames or start >= stop:
        raise ValueError(f"--frames: '{spec}' selects no frame: {have}")
    if stop > n_frames:
        raise ValueError(f"--frames: '{spec}' goes past the last frame: {have}")
    return range(start, stop)
