"""Mesh sequences for the CLI and the viewers: built-in generated scenes or files on disk.

`load_sequence(INPUT)` returns (faces (m, 3) int64, frames (T, n, 3) float64). INPUT is a scene
name (`scene_names()`), a folder of OBJ/PLY frames with identical faces, or one mesh file plus
an .npz of positions (T, n, 3) given with `positions=`.
"""

from __future__ import annotations

import os

import numpy as np


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
    return np.asarray(m.faces, dtype=np.int64), np.asarray(m.vertices, dtype=np.float64)


def load_sequence(source: str, positions: str | None = None, resolution: int | None = None):
    """Faces (m, 3) and frames (T, n, 3) from a scene name or path (see module doc)."""
    from conecull.datasets.registry import SCENES, load

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
        files = sorted(f for f in os.listdir(source) if f.lower().endswith((".obj", ".ply")))
        if not files:
            raise ValueError(f"INPUT: folder '{source}' has no .obj or .ply frames")
        F0, frames = None, []
        for name in files:
            F, V = _load_mesh(os.path.join(source, name))
            if F0 is None:
                F0 = F
            elif F.shape != F0.shape or not np.array_equal(F, F0):
                raise ValueError(f"INPUT: frame '{name}' has different faces than '{files[0]}' (topology must not change)")
            if frames and len(V) != len(frames[0]):
                raise ValueError(f"INPUT: frame '{name}' has {len(V)} vertices, '{files[0]}' has {len(frames[0])}")
            frames.append(V)
        return F0, np.stack(frames)
    F, V = _load_mesh(source)
    if positions is None:
        return F, V[None]
    if not os.path.exists(positions):
        raise FileNotFoundError(f"positions: '{positions}' does not exist")
    try:
        with np.load(positions) as z:
            key = "positions" if "positions" in z.files else z.files[0]
            raw = z[key]
    except Exception as e:
        raise ValueError(f"positions: cannot read '{positions}' as .npz ({e})") from None
    if raw.dtype.kind not in "fiu":  # complex would lose its imaginary part, silently
        raise ValueError(f"positions: expected real coordinates in '{positions}', got dtype {raw.dtype}")
    P = np.asarray(raw, dtype=np.float64)
    if P.ndim != 3 or P.shape[2] != 3:
        raise ValueError(f"positions: expected an array of shape (T, n, 3), got {P.shape}")
    if P.shape[1] != len(V):
        raise ValueError(f"positions: frames have {P.shape[1]} vertices but '{source}' has {len(V)}")
    return F, P


def parse_frames(spec: str | None, n_frames: int) -> range:
    """'A:B' (B exclusive, either side optional) or 'K' -> a range of frame indices."""
    if not spec:
        return range(n_frames)
    try:
        if ":" in spec:
            a, b = spec.split(":", 1)
            r = range(n_frames)[slice(int(a) if a else None, int(b) if b else None)]
        else:
            k = int(spec)
            r = range(k, k + 1)
    except ValueError:
        raise ValueError(f"--frames: expected A:B or K, got '{spec}'") from None
    if len(r) == 0 or r.start >= n_frames or r.start < 0:
        raise ValueError(f"--frames: '{spec}' selects no frame of the {n_frames} available")
    return r
