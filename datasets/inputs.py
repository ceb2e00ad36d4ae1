"""Mesh sequences for the CLI and the viewers: built-in generated scenes or files on disk.

`load_sequence(INPUT)` returns (faces (m, 3) int64, frames (T, n, 3) float64). INPUT is a scene
name (`scene_names()`), a folder of OBJ/PLY frames with identical faces, or one mesh file plus
an .npz of positions (T, n, 3) given with `positions=`.
"""

from __future__ import annotations

import os
import re

import numpy as np

from conecull.datasets import checks


DEFAULT_SCENE = "fold"


def scene_names() -> list[str]:
    from conecull.datasets.registry import names

    return names()


def _load_mesh(path: str):
    import trimesh

    kwargs = {"process": False, "force": "mesh"}
    if path.lower().endswith(".obj"):
        kwargs["maintain_order"] = True  # otherwise trimesh splits/merges vertices
    try:
        m = trimesh.load(path, **kwargs)
    except Exception as e:  # trimesh raises many types for unreadable files
        raise ValueError(f"{path}: cannot read mesh ({type(e).__name__}: {e})") from None
    if not hasattr(m, "faces") or len(m.faces) == 0:
        raise ValueError(f"{path}: no triangles in this file")
    if path.lower().endswith(".obj"):
        _refuse_obj_index_zero(path)
    F = np.asarray(m.faces, dtype=np.int64)
    try:  # here, where the file is known: later the same error could not say which file it is in
        V = checks.points("vertices", m.vertices)
    except ValueError as e:
        raise ValueError(f"{path}: {e}") from None
    return F, V


# A vertex index 0 on an OBJ face line ("f 0 1 2", "f 0/4/1 ..."): OBJ counts from 1 (negative
# values count back from the end), so 0 is no vertex. trimesh reads it as -1, the last vertex,
# and the mesh then came out wrong ("repeats a vertex" at best).
_OBJ_INDEX_ZERO = re.compile(rb"^[ \t]*f[ \t](?:[^#\n]*[ \t])?0(?:/|[ \t]|\r?$)", re.M)


def _refuse_obj_index_zero(path: str) -> None:
    with open(path, "rb") as fh:
        text = fh.read()
    hit = _OBJ_INDEX_ZERO.search(text)
    if hit:
        line = text.count(b"\n", 0, hit.start()) + 1
        end = text.find(b"\n", hit.start())
        shown = text[hit.start():end if end >= 0 else len(text)].strip().decode(errors="replace")
        raise ValueError(f"{path}: line {line}: a face refers to vertex 0, but OBJ counts vertices from 1 "
                         f"({shown[:80]!r})")


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


def frame_order(names: list[str]) -> list[str]:
    """File names in frame order: by their numbers, not their text (frame2 before frame10), so
    unpadded numbering works. Names compare part by part, digit runs as numbers and the rest as
    lower-case text; names with equal keys (frame1, frame01) keep their plain text order. Names
    without a consistent numbering (a.ply, b2.ply, b10.ply) still get this one deterministic
    order, which need not be the intended one."""
    def key(name: str):
        parts = re.split(r"(\d+)", name)  # text at even indices, digit runs at odd: comparable part by part
        return [int(t) if i % 2 else t.lower() for i, t in enumerate(parts)], name

    return sorted(names, key=key)


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
        F0, frames = None, []
        for name in files:
            F, V = _load_mesh(os.path.join(source, name))
            if F0 is None:
                _check_faces(os.path.join(source, name), F, len(V))
                F0 = F
            elif F.shape != F0.shape or not np.array_equal(F, F0):
                raise ValueError(f"INPUT: frame '{name}' has different faces than '{files[0]}' (topology must not change)")
            if frames and len(V) != len(frames[0]):
                raise ValueError(f"INPUT: frame '{name}' has {len(V)} vertices, '{files[0]}' has {len(frames[0])}")
            frames.append(V)
        return F0, np.stack(frames)
    F, V = _load_mesh(source)
    _check_faces(source, F, len(V))
    if positions is None:
        return F, V[None]
    if not os.path.exists(positions):
        raise FileNotFoundError(f"positions: '{positions}' does not exist")
    try:
        loaded = np.load(positions, allow_pickle=False)
        if isinstance(loaded, np.ndarray):  # an .npy: the array itself
            raw = loaded
        else:
            with loaded as z:
                raw = z["positions" if "positions" in z.files else z.files[0]] if z.files else None
    except Exception as e:
        raise ValueError(f"positions: cannot read '{positions}' as .npz or .npy ({e})") from None
    if raw is None:
        raise ValueError(f"positions: '{positions}' holds no array")
    # real (complex would lose its imaginary part, silently), (T >= 1, n, 3), finite: each
    # message names the file, and the frame of a non-finite coordinate
    return F, checks.frames("positions", raw, n_vertices=len(V), source=positions)


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
