"""Mesh files (OBJ, PLY) read as the file numbers them: its vertex ids and face order, so the
triangle ids that `check` and `explain` report are the file's; coincident vertices never merged.

`read_mesh(path)` returns a `MeshFile`. Faces of more than 3 corners become fans of triangles in
file order (`MeshFile.fans` says which); a fan that is not convex at some pose would be an
intersection of our making, so `check_fans` refuses it. What a file leaves unclear (a token that
is not a number, a row longer or shorter than its header says, an unknown OBJ statement) is an
error naming the file and its line (OBJ, ASCII PLY) or face, never a guess.

Not trimesh's readers: its OBJ reader splits vertices at material groups and orders faces by
material (a flat sheet in two materials came out in two pieces, "colliding"), its PLY reader
splits vertices at per-face texture coordinates, drops faces of 2 corners, splits polygons its own
way, and reads damaged ASCII rows leniently. trimesh still decodes binary PLY (its element arrays
only: the file's own vertices and faces are taken from them).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

from conecull.datasets import checks


@dataclass
class MeshFile:
    faces: np.ndarray     # (m, 3) int64 triangles, vertex ids counted from 0
    vertices: np.ndarray  # (n, 3) float64, in file order
    fans: np.ndarray      # (m,) int64: for each triangle, the file face it came from if that had > 3 corners, else -1
    where: list           # where(k) names file face k (for fans' messages): its OBJ line, or PLY face number


def read_mesh(path: str) -> MeshFile:
    lower = path.lower()
    if lower.endswith(".obj"):
        mesh = _read_obj(path)
    elif lower.endswith(".ply"):
        mesh = _read_ply(path)
    else:  # STL has no shared vertices (every neighbour would touch), OFF went through trimesh unchecked
        raise ValueError(f"{path}: only .obj and .ply mesh files are read (convert it to one of them)")
    if len(mesh.faces) == 0:
        raise ValueError(f"{path}: no triangles in this file")
    try:  # here, where the file is known: later the same error could not say which file it is in
        mesh.vertices = checks.points("vertices", mesh.vertices)
    except ValueError as e:
        raise ValueError(f"{path}: {e}") from None
    return mesh


# --- faces -> triangles ----------------------------------------------------------------------

def _triangles(faces: list, where, n_vertices: int, first: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Faces (lists of corner ids, counted from 0) as triangles in file order, and per triangle
    the face it came from if that face had more than 3 corners (else -1): a face of k > 3
    corners becomes the fan (c0, c1, c2), (c0, c2, c3), ... of k - 2 triangles. Each face is
    checked first, where(k) naming face k in the messages (the rows of the triangles would not be
    the file's faces), with vertex ids shown counted from `first`, as the file counts them."""
    if all(len(f) == 3 for f in faces):  # the usual case, checked at once (the loop names a bad face)
        try:
            F = np.array(faces, dtype=np.int64).reshape(-1, 3)
        except OverflowError:  # an id beyond int64: the loop names it
            F = None
        if F is not None and ((F >= 0) & (F < n_vertices)).all() and (F[:, [0, 1, 2]] != F[:, [1, 2, 0]]).all():
            return F, np.full(len(F), -1, np.int64)
    out, fans = [], []
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
            out.extend((f[0], f[i], f[i + 1]) for i in range(1, len(f) - 1))
            fans.extend([k] * (len(f) - 2))
        else:
            out.append(f)
            fans.append(-1)
    return np.array(out, dtype=np.int64).reshape(-1, 3), np.array(fans, dtype=np.int64)


def check_fans(mesh: MeshFile, frames: np.ndarray, names) -> None:
    """Every fan (a face of more than 3 corners) convex at every pose: each of its triangles turns
    the way the whole face does (its normal has a positive dot product with the face's vector
    area, the sum of the fan's). Otherwise two triangles of one face would overlap, a collision
    of our making (a flat concave quad split from its reflex corner's neighbour): refused.
    frames (T, n, 3); names[t] names pose t."""
    fan = np.flatnonzero(mesh.fans >= 0)
    if len(fan) == 0:
        return
    faces = mesh.faces[fan]
    ids, owner = np.unique(mesh.fans[fan], return_inverse=True)
    for t, V in enumerate(frames):
        p = V[faces]
        n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
        area = np.zeros((len(ids), 3))
        np.add.at(area, owner, n)
        turned = np.einsum("ij,ij->i", n, area[owner]) <= 0
        if turned.any():
            k = int(ids[owner[np.argmax(turned)]])
            raise ValueError(f"{mesh.where(k)}: this face of more than 3 corners is not convex in {names[t]}: split "
                             "into a fan, two of its triangles would overlap (a collision the file does not have); "
                             "triangulate the file first")


# --- OBJ --------------------------------------------------------------------------------------

# The statements of the OBJ format (Wavefront's spec): all but v and f (fo: f's old name) carry
# nothing a triangle mesh needs. Any other word is refused: "V 0 0 0" or "v1 0 0" skipped would
# shift every later vertex id.
_OBJ_IGNORED = {b"vt", b"vn", b"vp", b"l", b"p", b"g", b"o", b"s", b"mg", b"usemtl", b"mtllib", b"usemap", b"maplib",
                b"cstype", b"deg", b"bmat", b"step", b"curv", b"curv2", b"surf", b"parm", b"trim", b"hole", b"scrv",
                b"sp", b"end", b"con", b"bevel", b"c_interp", b"d_interp", b"lod", b"shadow_obj", b"trace_obj",
                b"ctech", b"stech", b"call", b"csh"}
_INT = re.compile(rb"[+-]?\d+")


def _number(word: bytes, kind=float):
    """kind(word), refusing what Python reads but a mesh file does not mean (1_0: ten)."""
    if b"_" in word or (kind is int and not _INT.fullmatch(word)):
        raise ValueError(word)
    return kind(word)


def _shown(line: bytes) -> str:
    return repr(line.strip().decode(errors="replace")[:80])


def _obj_statements(text: bytes):
    """(line number, statement) per statement: comments cut, a line ending in a backslash (outside
    a comment) continued on the next, any line ending (LF, CRLF, CR) accepted."""
    parts, start = [], 0
    for number, raw in enumerate(text.replace(b"\r\n", b"\n").replace(b"\r", b"\n").split(b"\n"), 1):
        code = raw.split(b"#", 1)[0].rstrip()
        if not parts:
            start = number
        if code.endswith(b"\\"):
            parts.append(code[:-1])
            continue
        parts.append(code)
        yield start, b" ".join(parts)
        parts = []
    if parts:  # a continuation on the last line: nothing follows
        yield start, b" ".join(parts)


def _read_bytes(path: str) -> bytes:
    """The file's bytes, a UTF-8 byte order mark dropped (it is not part of the first word)."""
    checks.regular_file("INPUT", path)
    try:
        with open(path, "rb") as fh:
            text = fh.read()
    except OSError as e:
        raise ValueError(f"{path}: cannot read mesh ({type(e).__name__}: {e})") from None
    return text[3:] if text.startswith(b"\xef\xbb\xbf") else text


def _read_obj(path: str) -> MeshFile:
    text = _read_bytes(path)
    V, faces, lines, shown = [], [], [], {}
    for number, line in _obj_statements(text):
        words = line.split()
        if not words:
            continue
        key = words[0]
        if key == b"v":
            try:
                xyz = [_number(w) for w in words[1:4]]
            except ValueError:
                xyz = []
            if len(xyz) < 3:
                raise ValueError(f"{path}: line {number}: a vertex needs 3 numbers ({_shown(line)})")
            V.append(xyz)
        elif key in (b"f", b"fo"):
            face = []
            for w in words[1:]:
                ref = w.split(b"/", 1)[0]
                if not _INT.fullmatch(ref):
                    raise ValueError(f"{path}: line {number}: a face's vertex must be a whole number ({_shown(line)})")
                i = int(ref)
                if i == 0:  # OBJ counts from 1, and negative values back from the last vertex so far
                    raise ValueError(f"{path}: line {number}: a face refers to vertex 0, but OBJ counts vertices "
                                     f"from 1 ({_shown(line)})")
                if -i > len(V):
                    raise ValueError(f"{path}: line {number}: a face refers to vertex {i}, counted back from the "
                                     f"last one, but only {len(V)} come before it ({_shown(line)})")
                face.append(i - 1 if i > 0 else len(V) + i)
            faces.append(face)
            lines.append(number)
            shown[number] = line
        elif key not in _OBJ_IGNORED:
            raise ValueError(f"{path}: line {number}: '{key.decode(errors='replace')}' is not an OBJ statement "
                             f"({_shown(line)})")

    def where(k):
        return f"{path}: line {lines[k]} ({_shown(shown[lines[k]])})"

    # Checked once all are read: vertices listed after the faces that use them are allowed.
    F, fans = _triangles(faces, where, len(V), 1)
    return MeshFile(F, np.array(V, dtype=np.float64).reshape(-1, 3), fans, where)


# --- PLY --------------------------------------------------------------------------------------

_PLY_INTS = {"char", "uchar", "short", "ushort", "int", "uint", "int8", "uint8", "int16", "uint16", "int32", "uint32"}
_PLY_FLOATS = {"float", "double", "float32", "float64"}


def _read_ply(path: str) -> MeshFile:
    text = _read_bytes(path)
    head = re.match(rb"ply\r?\n(.*?)\bend_header[ \t]*\r?\n", text, re.S)
    if head is None:
        raise ValueError(f"{path}: not a PLY file (no 'ply' ... 'end_header' header)")
    if re.search(rb"^format[ \t]+ascii\b", head.group(1), re.M):
        return _read_ply_ascii(path, head.group(1), text[head.end():])
    return _read_ply_binary(path)


def _ply_header(path: str, header: bytes) -> list:
    """[(element, count, [(property, None | 'list', scalar or (count type, item type))])]."""
    elements = []
    for raw in header.decode(errors="replace").splitlines():
        words = raw.split()
        if not words or words[0] in ("format", "comment", "obj_info"):
            continue
        if words[0] == "element" and len(words) == 3 and words[2].isdigit():
            elements.append((words[1], int(words[2]), []))
        elif words[0] == "property" and elements and len(words) == 3 and words[1] in _PLY_INTS | _PLY_FLOATS:
            elements[-1][2].append((words[2], words[1]))
        elif (words[0] == "property" and elements and len(words) == 5 and words[1] == "list"
              and words[2] in _PLY_INTS and words[3] in _PLY_INTS | _PLY_FLOATS):
            elements[-1][2].append((words[4], ("list", words[3])))
        else:
            raise ValueError(f"{path}: header line {raw.strip()!r} is not PLY")
        if words[0] == "property" and [p for p, _ in elements[-1][2]].count(words[-1]) > 1:
            raise ValueError(f"{path}: header line {raw.strip()!r}: element '{elements[-1][0]}' already has a "
                             f"property '{words[-1]}' (which one holds the data?)")
    return elements


def _read_ply_ascii(path: str, header: bytes, body: bytes) -> MeshFile:
    """One row per line, every value where the header says: a row too long or too short, or a
    value that is not a number of its property's type, is refused (a lenient reader dropped
    values and faces of damaged files)."""
    elements = _ply_header(path, header)
    head_lines = header.count(b"\n") + 2  # "ply" and "end_header" lines
    rows = body.replace(b"\r\n", b"\n").split(b"\n")
    at = 0
    V, faces = None, None
    for name, count, props in elements:
        values = []
        for r in range(count):
            while at < len(rows) and not rows[at].strip():
                at += 1
            if at >= len(rows):
                raise ValueError(f"{path}: the header declares {count} {name} rows, the file ends after {r}")
            words, number = rows[at].split(), head_lines + at + 1
            at += 1
            row, i = [], 0
            try:
                for prop, kind in props:
                    if isinstance(kind, tuple):
                        n = _number(words[i], int)
                        row.append([_number(w, int if kind[1] in _PLY_INTS else float) for w in words[i + 1: i + 1 + n]])
                        if len(row[-1]) != n:
                            raise IndexError
                        i += 1 + n
                    else:
                        row.append(_number(words[i], int if kind in _PLY_INTS else float))
                        i += 1
            except (IndexError, ValueError):
                raise ValueError(f"{path}: line {number}: not a {name} row as the header declares it "
                                 f"({_shown(rows[at - 1])})") from None
            if i != len(words):
                raise ValueError(f"{path}: line {number}: {len(words) - i} more value(s) than the header declares for "
                                 f"a {name} row ({_shown(rows[at - 1])})")
            values.append(row)
        names = [p for p, _ in props]
        if name == "vertex":
            if not {"x", "y", "z"} <= set(names):
                raise ValueError(f"{path}: its vertices have no x, y, z properties")
            cols = [names.index(c) for c in "xyz"]
            V = np.array([[row[c] for c in cols] for row in values], dtype=np.float64).reshape(-1, 3)
        elif name == "face":
            key = next((p for p in ("vertex_indices", "vertex_index") if p in names), None)
            if key is None:
                raise ValueError(f"{path}: its faces have no vertex_indices list")
            faces = [row[names.index(key)] for row in values]
    if any(rows[k].strip() for k in range(at, len(rows))):
        raise ValueError(f"{path}: line {head_lines + at + 1}: more rows than the header declares")
    return _ply_mesh(path, V, faces)


def _read_ply_binary(path: str) -> MeshFile:
    import trimesh

    try:
        m = trimesh.load(path, process=False, force="mesh")
    except Exception as e:  # trimesh raises many types for unreadable files
        raise ValueError(f"{path}: cannot read this binary PLY ({type(e).__name__}: {e}); trimesh, which decodes it, "
                         "reads only faces of one corner count, and the file may be damaged") from None
    raw = (getattr(m, "metadata", None) or {}).get("_ply_raw") or {}
    vertex, face = raw.get("vertex", {}), raw.get("face", {})
    data = vertex.get("data")
    if data is None or face.get("data") is None:
        raise ValueError(f"{path}: no triangles in this file")
    try:  # the file's own vertices: trimesh's are split at per-face texture coordinates
        V = np.stack([np.asarray(data[c], np.float64).reshape(-1) for c in "xyz"], axis=1)
    except (KeyError, ValueError, IndexError):
        raise ValueError(f"{path}: its vertices have no x, y, z properties") from None
    corners = _binary_corners(face["data"])
    if corners is None:
        raise ValueError(f"{path}: its faces have no vertex_indices list")
    if len(V) != vertex.get("length", len(V)) or len(corners) != face.get("length", len(corners)):
        raise ValueError(f"{path}: fewer rows than its header declares (a damaged file)")
    return _ply_mesh(path, V, corners)


def _binary_corners(data):
    """The corner lists of a binary PLY's faces as trimesh decodes them: a structured array, per
    face its corner count 'f0' and corners 'f1' (trimesh reads only faces of one corner count)."""
    if isinstance(data, dict):
        return data.get("vertex_indices", data.get("vertex_index"))
    if not (isinstance(data, np.ndarray) and data.dtype.names):
        return None
    name = next((n for n in ("vertex_indices", "vertex_index") if n in data.dtype.names), None)
    if name is None:
        return None
    lists = data[name]
    if lists.dtype.names != ("f0", "f1"):
        return None
    count, corners = lists["f0"], lists["f1"].reshape(len(lists), -1)
    if (count == corners.shape[1]).all():
        return corners  # an array: _ply_mesh checks it at once
    return [list(c[:k]) for c, k in zip(corners.tolist(), count)]


def _ply_mesh(path: str, V, faces) -> MeshFile:
    if V is None or faces is None:
        raise ValueError(f"{path}: no triangles in this file")

    def where(k):
        return f"{path}: face {k} (counted from 0)"

    if isinstance(faces, np.ndarray):  # a binary file's faces of one corner count, checked at once
        if faces.dtype.kind == "f":
            bad = ~(np.isfinite(faces) & (faces == np.floor(faces)))
            if bad.any():
                k, i = (int(x) for x in np.argwhere(bad)[0])
                raise ValueError(f"{where(k)}: vertex id {float(faces[k, i])!r} is not a whole number")
        faces = faces.tolist()  # Python numbers: ids beyond int64 reach _triangles' own message
        if faces and isinstance(faces[0][0], float):
            faces = [[int(c) for c in f] for f in faces]
    else:
        faces = list(faces)
        for k, f in enumerate(faces):  # whole numbers each: a float id was truncated before
            if not isinstance(f, (list, tuple, np.ndarray)):
                raise ValueError(f"{where(k)}: its vertex_indices is one number ({f!r}), not a list of vertex ids "
                                 "(the header must declare 'property list <count type> <index type> vertex_indices')")
            for c in f:
                if not isinstance(c, (int, np.integer)) and not (math.isfinite(c) and float(c).is_integer()):
                    raise ValueError(f"{where(k)}: vertex id {c!r} is not a whole number")
            faces[k] = [int(c) for c in f]
    F, fans = _triangles(faces, where, len(V))
    return MeshFile(F, V, fans, where)
