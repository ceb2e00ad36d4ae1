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
from conecull.datasets.mesh_files import check_fans, read_mesh


DEFAULT_SCENE = "fold"


def scene_names() -> list[str]:
    from conecull.datasets.registry import names

    return names()


def _check_faces(path: str, F: np.ndarray, n_vertices: int) -> None:
    """The mesh's own checks (its size against memory, ...), with the file named. Indices and
    repeated vertices were checked face by face as the file was read (mesh_files._triangles)."""
    import conecull

    try:
        conecull.Mesh(F, n_vertices=n_vertices)
    except ValueError as e:
        raise ValueError(f"{path}: {e}") from None


def _frame_key(name: str, decimals: bool = False):
    """Compares names part by part: digit runs as whole numbers (or, with `decimals`, digit runs
    with a fraction as decimal numbers), the rest as lower-case text."""
    parts = re.split(r"(\d+(?:\.\d+)?)" if decimals else r"(\d+)", name)  # numbers at odd indices
    return [Decimal(t) if i % 2 else t.lower() for i, t in enumerate(parts)]


def frame_order(names: list[str]) -> list[str]:
    """File names in frame order: by the whole numbers in their names, not their text (frame2
    before frame10), so unpadded numbering works. Names compare part by part (`_frame_key`); names
    with equal keys (frame1, frame01) keep their plain text order. A minus sign is a separator
    (frame-2 is frame 2). `load_sequence` refuses a folder whose order this leaves in doubt."""
    return sorted(names, key=lambda name: (_frame_key(name), name))


def _check_frame_order(files: list[str], folder: str) -> None:
    """files in frame_order: refused if two name the same frame (frame1, frame01; t1, t1.0), or
    if reading their numbers as decimals orders them otherwise (t0.25 after t0.5 as whole
    numbers; cloth_v2.10 before cloth_v2.2 as decimals): which is meant is not ours to guess."""
    for a, b in zip(files, files[1:]):
        if _frame_key(a) == _frame_key(b) or _frame_key(a, True) == _frame_key(b, True):
            raise ValueError(f"INPUT: '{a}' and '{b}' in folder '{folder}' have the same frame number")
    as_decimals = sorted(files, key=lambda name: (_frame_key(name, True), name))
    k = next((k for k, (a, b) in enumerate(zip(files, as_decimals)) if a != b), None)
    if k is not None:
        raise ValueError(f"INPUT: the frame order in folder '{folder}' is ambiguous: '{files[k]}' comes before "
                         f"'{as_decimals[k]}' if the numbers in their names are whole numbers, after it if they are "
                         "decimals; name the frames with whole numbers (frame_0001.obj, ...)")


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
        _check_frame_order(files, source)
        first, frames = None, []
        for name in files:
            mesh = read_mesh(os.path.join(source, name))
            if first is None:
                _check_faces(os.path.join(source, name), mesh.faces, len(mesh.vertices))
                first = mesh
            elif mesh.faces.shape != first.faces.shape or not np.array_equal(mesh.faces, first.faces):
                raise ValueError(f"INPUT: frame '{name}' has different faces than '{files[0]}' (topology must not change)")
            if frames and len(mesh.vertices) != len(frames[0]):
                raise ValueError(f"INPUT: frame '{name}' has {len(mesh.vertices)} vertices, '{files[0]}' has "
                                 f"{len(frames[0])}")
            frames.append(mesh.vertices)
        frames = np.stack(frames)
        check_fans(first, frames, [f"frame '{name}'" for name in files])
        _warn_polygons(first, files[0])
        return first.faces, frames
    mesh = read_mesh(source)
    F, V = mesh.faces, mesh.vertices
    _check_faces(source, F, len(V))
    if positions is None:
        check_fans(mesh, V[None], ["the file"])
        _warn_polygons(mesh, os.path.basename(source))
        return F, V[None]
    if not os.path.exists(positions):
        raise FileNotFoundError(f"positions: '{positions}' does not exist")
    if not positions.lower().endswith((".npz", ".npy")):
        raise ValueError(f"positions: '{positions}' is not an .npz or .npy file (the frames of a mesh file go in "
                         "a folder of frames instead)")
    checks.regular_file("positions", positions)
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
    if not isinstance(raw, np.ndarray):  # an .npz member that is no .npy
        raise ValueError(f"positions: '{shown}' is not an array")
    # real (complex would lose its imaginary part, silently), (T >= 1, n, 3), finite: each
    # message names the file (and the array read), and the frame of a non-finite coordinate
    frames = checks.frames("positions", raw, n_vertices=len(V), source=shown)
    if raw.dtype.kind in "iu":  # read exactly, but a query takes floats: integers are likely truncated ones
        warnings.warn(f"positions: '{shown}' holds integer coordinates (dtype {raw.dtype}), read as they are; if "
                      "they were rounded from floats, the collisions found are those of the rounded poses",
                      stacklevel=2)
    check_fans(mesh, frames, [f"frame {t} of '{shown}'" for t in range(len(frames))])
    _warn_polygons(mesh, os.path.basename(source))
    return F, frames


def _warn_polygons(mesh, name: str) -> None:
    polygons = len(np.unique(mesh.fans[mesh.fans >= 0]))
    if polygons:
        warnings.warn(f"INPUT: {polygons} face{'s' if polygons != 1 else ''} of '{name}' with more than 3 corners "
                      f"{'were' if polygons != 1 else 'was'} split into triangles (a fan from each face's first corner, in file order): triangle "
                      "ids count these triangles, not the file's faces", stacklevel=3)


def parse_frames(spec: str | None, n_frames: int) -> range:
    """'A:B' (B exclusive, either side optional) or 'K' -> a range of frame indices, each in
    [0, n_frames): no negative (from the end) indices and no silent clamping to the input."""
    if spec is None or spec == "":
        return range(n_frames)
    if not isinstance(spec, str):
        raise ValueError(f"--frames: expected a string A:B or K, got {type(spec).__name__}")
    # ASCII digits only (int() would take '1_0' as 10, ' 1 ', and other scripts' digits); a sign
    # reaches the check below.
    m = re.fullmatch(r"(-?[0-9]+)?:(-?[0-9]+)?|(-?[0-9]+)", spec)
    if m is None:
        raise ValueError(f"--frames: expected A:B or K, got '{spec}'")
    a, b, k = m.groups()
    if k is not None:
        start = int(k)
        stop = start + 1
    else:
        start, stop = int(a) if a else 0, int(b) if b else n_frames
    have = f"the input has {n_frames} frame{'s' if n_frames != 1 else ''} (0..{n_frames - 1})"
    if start < 0 or stop < 0:
        raise ValueError(f"--frames: '{spec}': frames are counted from 0 (not from the end); {have}")
    if start >= n_frames or start >= stop:
        raise ValueError(f"--frames: '{spec}' selects no frame: {have}")
    if stop > n_frames:
        raise ValueError(f"--frames: '{spec}' goes past the last frame: {have}")
    return range(start, stop)
