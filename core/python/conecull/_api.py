"""The Python façade over conecull._core: validation with clear errors, NumPy in and out."""

from __future__ import annotations

import hashlib
import math
import os
import weakref
from dataclasses import dataclass, field

import numpy as np

from conecull import _core
from conecull.trace import Trace

METHODS = ("aabb", "nc", "aabb+front", "nc+front", "sct", "cbc")
# "sct" (the projected star-contour test of [SPO10]) is a DCD method only: the paper (Sec. 3.2)
# notes it is not known to extend to CCD, whose baseline is "cbc" ([TCYM09]).
CCD_METHODS = tuple(m for m in METHODS if m != "sct")

# Coordinate values are checked by the core's bindings (core/bindings/common.hpp): finite, and
# non-zero magnitudes in [2^-128, 2^128], where no product of coordinate differences in the exact
# predicates under- or overflows (degree-4 terms stay within 2^-1000 .. 2^530).


def _asarray(x, name: str) -> np.ndarray:
    """np.asarray, with NumPy's complaints about ragged or odd input naming the argument."""
    if np.ma.is_masked(x):  # np.asarray would drop the mask and use the hidden values
        raise ValueError(f"{name}: masked entries are not supported (pass the array without a mask)")
    try:
        return np.asarray(x)
    except (ValueError, TypeError) as e:
        raise ValueError(f"{name}: not a rectangular array ({e})") from None


def _as_float64(a: np.ndarray, name: str) -> np.ndarray:
    """a as float64 if that conversion is exact; otherwise a ValueError (a rounded coordinate
    would make every exact sign after it the sign of another input)."""
    b = a.astype(np.float64, copy=False)
    with np.errstate(invalid="ignore"):  # 2^64 - 1 rounds to 2^64, beyond uint64: the cast back differs, no warning
        back = b.astype(a.dtype) if a.dtype.itemsize > 4 and a.dtype != np.float64 else a
    if not np.array_equal(back, a, equal_nan=True):
        what = "integer coordinates beyond 2^53 are" if a.dtype.kind in "iu" else f"{a.dtype} coordinates are"
        raise ValueError(f"{name}: some {what} not exactly float64 (rounding would move them); pass float64")
    return np.ascontiguousarray(b)


def _as_faces(faces) -> np.ndarray:
    a = _asarray(faces, "faces")
    # An empty mesh: [] or an empty (0, 3) array (a float literal like np.zeros((0, 3)) too).
    if a.size == 0 and a.dtype.kind in "iuf" and (a.shape == (0,) or a.shape == (0, 3)):
        return np.zeros((0, 3), dtype=np.int32)
    if a.dtype.kind == "O" and a.size and all(isinstance(x, (int, np.integer)) and not isinstance(x, bool)
                                              for x in a.flat):
        # Python ints in an object array: an int array if they fit in 64 bits; beyond (NumPy keeps
        # such ints as objects), too large, not "not integers".
        try:
            a = a.astype(np.int64)
        except OverflowError:
            big = max(a.flat, key=abs)
            raise ValueError(f"faces: vertex index {big} is {'too large' if big > 0 else 'negative'} (ids are in "
                             f"[0, 2^31 - 2])") from None
    if a.dtype.kind not in "iu":
        raise ValueError(f"faces: expected an integer array, got dtype {a.dtype}")
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"faces: expected shape (m, 3), got {a.shape}")
    if a.min() < 0:
        r = int(np.argmin(a.min(axis=1)))
        raise ValueError(f"faces: negative vertex index {int(a[r].min())} in row {r}")
    if a.max() >= 2**31 - 1:
        raise ValueError(f"faces: vertex index {int(a.max())} is too large (at most 2^31 - 2 = {2**31 - 2}: the "
                         "vertex count must fit in 31 bits)")
    rep = (a[:, 0] == a[:, 1]) | (a[:, 1] == a[:, 2]) | (a[:, 0] == a[:, 2])
    if rep.any():
        r = int(np.argmax(rep))
        raise ValueError(f"faces: row {r} repeats a vertex: {a[r].tolist()}")
    return np.ascontiguousarray(a, dtype=np.int32)


def _as_positions(V, n_vertices: int, name: str = "V") -> np.ndarray:
    a = _asarray(V, name)
    if a.dtype.kind != "f":
        raise ValueError(f"{name}: expected a float64 (or float32) array, got dtype {a.dtype}")
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"{name}: expected shape (n, 3), got {a.shape}")
    if a.shape[0] != n_vertices:
        raise ValueError(f"{name}: has {a.shape[0]} rows but the mesh has {n_vertices} vertices")
    return _as_float64(a, name)  # values: checked by the core (see the top)


def memory_bytes() -> int:
    """This machine's physical memory (a bound no request may exceed), or 2^40 if unknown."""
    try:
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, OSError, ValueError):
        return 1 << 40


# What a mesh costs, for refusing one this machine cannot hold before building it (measured on
# the topology: ~8 bytes per vertex and ~150 per face; its NumPy views add 8 per vertex, and one
# (n, 3) float64 positions array, without which it cannot be queried, 24). A single triangle
# with vertex id 2^31 - 2 otherwise built for 42 s and 16 GB, and reading vertex_faces then
# got the process killed for lack of memory, with no Python error.
MESH_BYTES_PER_VERTEX, MESH_BYTES_PER_FACE = 40, 200


class Mesh:
    """Topology of a triangle mesh (any triangle soup), built once; positions come per query.

    faces: (m, 3) integer vertex ids, three distinct ids per row.
    n_vertices: number of vertices (default: largest id + 1).
    """

    def __init__(self, faces, n_vertices: int | None = None):
        if hasattr(self, "_topo"):  # colliders hold this topology: rebuilding it under them broke front_load
            raise TypeError("Mesh: already built; a mesh never changes, make a new Mesh instead")
        f = _as_faces(faces)
        needed = int(f.max()) + 1 if f.size else 0
        if n_vertices is None:
            n_vertices = needed
        elif isinstance(n_vertices, (bool, np.bool_)) or not isinstance(n_vertices, (int, np.integer)):
            raise ValueError(f"n_vertices: expected an integer, got {type(n_vertices).__name__}")
        elif n_vertices < needed:
            raise ValueError(f"n_vertices: {n_vertices} is smaller than the largest face index + 1 ({needed})")
        elif n_vertices > 2**31 - 1:
            raise ValueError(f"n_vertices: {n_vertices} is too large (at most 2^31 - 1 = {2**31 - 1})")
        need = MESH_BYTES_PER_VERTEX * int(n_vertices) + MESH_BYTES_PER_FACE * len(f)
        if need > memory_bytes():
            faces_word = "face" if len(f) == 1 else "faces"
            what = (f"faces: {len(f)} {faces_word} whose largest vertex index, {needed - 1}, means {needed} vertices"
                    if n_vertices == needed else f"n_vertices: {int(n_vertices)} vertices")
            raise ValueError(f"{what} would need about {need / 2**30:.3g} GiB (the topology and one (n, 3) float64 "
                             f"positions array), more than this machine's {memory_bytes() / 2**30:.3g} GiB of memory")
        try:
            self._topo = _core.build_topology(f, int(n_vertices))
        except MemoryError:
            raise MemoryError(f"n_vertices: {int(n_vertices)} vertices need more memory than this machine has") from None

    def __reduce__(self):
        # Pickled (and copied) as its faces and vertex count; the topology is rebuilt from them,
        # so a Mesh can go to a worker process.
        return (Mesh, (self.faces, self.n_vertices))

    @property
    def n_vertices(self) -> int:
        return self._topo.n_vertices

    @property
    def n_faces(self) -> int:
        return self._topo.n_faces

    @property
    def faces(self) -> np.ndarray:
        """(m, 3) int64 vertex ids."""
        return self._topo.faces.astype(np.int64)

    @property
    def edges(self) -> np.ndarray:
        """(E, 2) int64 unique edges, each row i < j, rows sorted; the row index is the edge id."""
        return self._topo.edges.astype(np.int64)

    @property
    def face_edges(self) -> np.ndarray:
        """(m, 3) edge ids of (f0, f1), (f1, f2), (f2, f0)."""
        return self._topo.face_edges.astype(np.int64)

    @property
    def edge_faces(self) -> tuple[np.ndarray, np.ndarray]:
        """CSR (offsets (E+1,), face ids): faces of edge e are ids[offsets[e]:offsets[e+1]]."""
        return self._topo.edge_face_offsets.astype(np.int64), self._topo.edge_face_ids.astype(np.int64)

    @property
    def vertex_faces(self) -> tuple[np.ndarray, np.ndarray]:
        """CSR (offsets (n+1,), face ids) of the faces around each vertex."""
        return self._topo.vertex_face_offsets.astype(np.int64), self._topo.vertex_face_ids.astype(np.int64)

    @property
    def boundary_edges(self) -> np.ndarray:
        """Ids of edges with exactly one face."""
        return self._topo.boundary_edges.astype(np.int64)

    @property
    def nonmanifold_edges(self) -> np.ndarray:
        """Ids of edges with more than two faces, or two faces traversing them the same way."""
        return np.flatnonzero(self._topo.edge_nonmanifold)

    @property
    def nonmanifold_vertices(self) -> np.ndarray:
        """Ids of vertices whose faces are not a single fan (or that lie on a non-manifold edge)."""
        return np.flatnonzero(self._topo.vertex_nonmanifold)

    @property
    def face_component(self) -> np.ndarray:
        """(m,) component label of each face (faces connected through shared vertices)."""
        return self._topo.face_component.astype(np.int64)

    @property
    def n_components(self) -> int:
        return self._topo.n_components

    def __repr__(self) -> str:
        return f"Mesh(n_vertices={self.n_vertices}, n_faces={self.n_faces}, n_edges={self._topo.n_edges})"


def _detached():
    """An unpickled result's `collider`: the collider is not pickled, so there is none to return."""
    return None


@dataclass
class DcdResult:
    pairs: np.ndarray
    """(k, 2) int64 colliding triangle ids, i < j, rows sorted lexicographically."""
    stats: dict = field(default_factory=dict)
    """Counters (bv_tests, cone_tests, contour_*, elementary_tests, colliding_pairs; front_entries,
    front_segments, front_bytes, front_added, front_removed, front_rested for the front methods,
    else 0; front_segments: the records kept, one per node the query reached Collide(L, R) at;
    front_bytes: all the front keeps for the next query, 8 bytes per entry, 24 per record and 4
    per BVH node; front_rested: nodes whose front churned and that ran Collide from the top
    instead) and seconds per stage."""
    trace: Trace | None = None
    """The query's events (conecull.trace schema) when queried with trace=True."""
    collider: weakref.ref | None = field(default=None, repr=False, compare=False)
    """A weak reference to the SelfCollider that answered (its node ids are the ones the trace
    names): res.collider() is that collider, or None once it is gone or the result was unpickled.
    Not pickled (the trace keeps its collider's BVH fingerprint, SelfCollider.bvh_digest)."""

    def __getstate__(self):  # a result pickles (e.g. back from a worker process), without its collider
        return {**self.__dict__, "collider": None}

    def __setstate__(self, state):
        self.__dict__.update(state, collider=_detached)


@dataclass
class CcdResult:
    vf: np.ndarray
    """(k, 2) int64 rows (vertex id, face id) in contact during the step, sorted."""
    ee: np.ndarray
    """(k, 2) int64 rows (edge a, edge b), a < b, ids of Mesh.edges, sorted."""
    stats: dict = field(default_factory=dict)
    toi: np.ndarray | None = None
    """With toi=True: per row (vf rows, then ee rows) a lower bound on the earliest contact time
    (no contact happens before it; within 2^-20 of the first time the pair comes that close)."""
    trace: Trace | None = None
    """The step's events (conecull.trace schema, with the vf and ee kinds) when traced."""
    collider: weakref.ref | None = field(default=None, repr=False, compare=False)
    """A weak reference to the SelfCollider that answered (see DcdResult.collider). Not pickled."""

    def __getstate__(self):
        return {**self.__dict__, "collider": None}

    def __setstate__(self, state):
        self.__dict__.update(state, collider=_detached)


ARITHMETIC = ("float", "conservative", "exact")
DEFAULT_LEAF_SIZE, MAX_LEAF_SIZE = 2, 64  # SelfCollider's leaf_size: default (measured fastest) and bound


class SelfCollider:
    """Self-collision queries on one mesh; keeps the BVH and contours between queries.

    The BVH is built from the first pose queried and refit afterwards (topology never changes).
    method: "aabb" (BVH only) or "nc" (normal cones + unprojected contour test, Alg. 2); or
    "aabb+front" / "nc+front" (Alg. 4): the same with a BVTT front kept between queries (one
    per query kind), so each query resumes the box tests where the previous one stopped. The
    front methods give exactly the results of their method without a front.
    The paper's baselines (Sec. 6.1), Alg. 2 with another contour test, certified like ours (so
    the same results): "sct", the projected star-contour test of Schvartzman et al. 2010 (DCD
    only; a CCD query raises ValueError), and "cbc", the O(n^2) edge-pair contour test of Tang
    et al. 2009 (CCD; on a DCD query the same test at the one pose).
    leaf_size: at most this many triangles per BVH leaf (2 measured fastest; see the benchmark).
    threads: threads per query (None: all cores); dcd and ccd can override it per query. The
    results, their order and the counters of stats are the same for any thread count (only the
    seconds differ); a traced query runs on one thread.
    """

    def __init__(self, mesh: Mesh, method: str = "nc", leaf_size: int = DEFAULT_LEAF_SIZE, threads: int | None = None):
        if not isinstance(mesh, Mesh):
            raise ValueError(f"mesh: expected a conecull.Mesh, got {type(mesh).__name__}")
        if not isinstance(method, str) or method not in METHODS:
            raise ValueError(f"method: expected one of {METHODS}, got {method!r}")
        if isinstance(leaf_size, (bool, np.bool_)) or not isinstance(leaf_size, (int, np.integer)) or not 1 <= leaf_size <= MAX_LEAF_SIZE:
            raise ValueError(f"leaf_size: expected an integer in [1, {MAX_LEAF_SIZE}], got {leaf_size!r}")
        self._mesh = mesh
        self._method = method
        self._leaf_size = int(leaf_size)
        self._core = _core.SelfCollider(mesh._topo, method, self._leaf_size, _as_threads(threads))
        self._bvh_digest = None

    # Read-only: the core was built for this mesh, method and leaf size; rebinding one would make
    # the Python side disagree with it (front_arrays on an "nc" collider, positions checked
    # against another mesh's vertex count). Make a new SelfCollider instead.
    @property
    def mesh(self) -> Mesh:
        """The mesh this collider was made for."""
        return self._mesh

    @property
    def method(self) -> str:
        """The culling method (see the class docstring)."""
        return self._method

    @property
    def leaf_size(self) -> int:
        """At most this many triangles per BVH leaf."""
        return self._leaf_size

    def __reduce__(self):
        # Its state (the BVH built from the first pose, the fronts) lives in the core and would
        # have to be rebuilt anyway; copying it silently from another pose would renumber nodes.
        raise TypeError("SelfCollider cannot be pickled or copied: pickle its mesh (a conecull.Mesh) and create "
                        "a new SelfCollider from it")

    @property
    def threads(self) -> int:
        """The queries' default thread count (all cores resolved to a number)."""
        return self._core.threads

    def dcd(self, V, trace: bool = False, threads: int | None = None, stop_at_first: bool = False) -> DcdResult:
        """Discrete self-collision query at positions V (n, 3); trace=True also records its events.
        threads: this query's thread count (None: the collider's).
        stop_at_first=True answers "is this pose intersection-free?": the query stops at a colliding
        pair, which `pairs` then holds (else it is empty); stats["elementary_tests"] counts the tests
        up to it. With "aabb" and "nc" the traversal stops there too (its counters count the tasks up
        to the one that found the hit), and the top of the BVTT is visited in traversal
        order and distant-first order taking turns, so the pair is not always the full query's first
        one; the front methods traverse fully (their front stays complete), as do "sct", "cbc" and
        traced queries, and return the first colliding candidate in traversal order (so with "aabb"
        and "nc", trace=True may give another pair and count than the untraced query). The answer
        and every counter are the same for any thread count."""
        if not isinstance(trace, (bool, np.bool_)):
            raise ValueError(f"trace: expected True or False, got {trace!r}")
        if not isinstance(stop_at_first, (bool, np.bool_)):
            raise ValueError(f"stop_at_first: expected True or False, got {stop_at_first!r}")
        t = _as_threads(threads)
        a = _as_positions(V, self.mesh.n_vertices)
        pairs, stats, raw = self._core.dcd(a, bool(trace), t, bool(stop_at_first))
        tr = Trace(raw, positions=(a.copy(),), bvh=self.bvh_digest()) if raw is not None else None
        return DcdResult(pairs=pairs, stats=stats, trace=tr,
                         collider=weakref.ref(self))

    def ccd(self, V0, V1, arithmetic: str = "exact", trace: bool = False, toi: bool = False,
            threads: int | None = None, stop_at_first: bool = False) -> CcdResult:
        """Continuous query: every vertex moves linearly from V0 to V1 over t in [0, 1].

        arithmetic: "float" (fast, may err), "conservative" (never misses a contact, may report
        a few that do not happen) or "exact" (exactly the answer for the given doubles).
        threads: this query's thread count (None: the collider's).
        stop_at_first=True answers "is this step collision-free?": each candidate triangle pair's
        VF then EE pairs are made and tested as soon as the traversal reaches it, up to the first
        contact, which `vf` or `ee` then holds (both empty: none); the counters count the pairs
        and tests up to it. "aabb" and "nc" stop traversing there too (visiting the top of the
        tree in dcd's first-hit order); the other methods traverse fully. The answer and every
        counter are the same for any thread count.
        """
        if self.method not in CCD_METHODS:
            raise ValueError(f"method: {self.method!r} is a discrete (DCD) method; CCD queries need one of {CCD_METHODS}")
        _check_arithmetic(arithmetic)
        t = _as_threads(threads)
        for name, flag in (("trace", trace), ("toi", toi), ("stop_at_first", stop_at_first)):
            if not isinstance(flag, (bool, np.bool_)):
                raise ValueError(f"{name}: expected True or False, got {flag!r}")
        a0 = _as_positions(V0, self.mesh.n_vertices, "V0")
        a1 = _as_positions(V1, self.mesh.n_vertices, "V1")
        vf, ee, stats, raw, tois = self._core.ccd(a0, a1, arithmetic, bool(trace), bool(toi), t, bool(stop_at_first))
        tr = Trace(raw, positions=(a0.copy(), a1.copy()), bvh=self.bvh_digest()) if raw is not None else None
        return CcdResult(vf=vf, ee=ee, stats=stats, toi=tois, trace=tr,
                         collider=weakref.ref(self))

    # Debug views of the acceleration structures as NumPy arrays (valid after a first query).
    def bvh_arrays(self) -> dict:
        return self._core.bvh_arrays()

    def bvh_digest(self) -> str | None:
        """A fingerprint of this collider's BVH: its nodes' children and face ranges and the face
        order, which fix what every node id means (None before the first query builds it; fixed
        after: the BVH is only refit). A traced result carries it (res.trace.bvh), so a result
        parted from its collider (pickled) is explained only with a collider whose node ids mean
        the same (viz.explain.check_result)."""
        if self._bvh_digest is None:
            b = self._core.bvh_arrays()
            if not len(b["depth"]) and self.mesh.n_faces:
                return None  # not built yet
            h = hashlib.blake2b(digest_size=16)
            for key in ("left", "right", "begin", "end", "order"):
                h.update(np.ascontiguousarray(b[key], dtype=np.int64).tobytes())
            self._bvh_digest = h.hexdigest()
        return self._bvh_digest

    def cone_arrays(self) -> dict:
        return self._core.cone_arrays()

    def contour_arrays(self) -> dict:
        return self._core.contour_arrays()

    def front_arrays(self, kind: str = "dcd") -> dict:
        """The BVTT front (Alg. 4) the last query of `kind` ("dcd" or "ccd") left, front methods only:
        "entries" (m, 2) BVTT nodes (a, b), "owner" (m,) the internal node X whose sub-segment
        Front_X holds each entry, "count" (n_nodes,) the size of Front_X (0: no front kept there),
        "resting" (n_nodes,) how many more queries X runs Collide from the top, untracked, because
        its front churned (0: tracked when visited)."""
        self._check_front("front_arrays", kind)
        return self._core.front_arrays(kind == "ccd")

    def _check_front(self, what: str, kind) -> None:
        if not self.method.endswith("+front"):
            raise ValueError(f"method: {self.method!r} keeps no BVTT front; {what} needs 'aabb+front' or 'nc+front'")
        if not isinstance(kind, str) or kind not in ("dcd", "ccd"):
            raise ValueError(f"kind: expected 'dcd' or 'ccd', got {kind!r}")

    def front_load(self, kind: str = "dcd") -> np.ndarray:
        """Per face, how many entries of the front (see front_arrays) have the face below one of
        their two BVH nodes: where on the mesh the front's work is."""
        self._check_front("front_load", kind)
        fr = self._core.front_arrays(kind == "ccd")
        bvh = self._core.bvh_arrays()
        n_faces = self.mesh.n_faces
        if not len(bvh["order"]):
            return np.zeros(n_faces, np.int64)
        # Each entry adds 1 to the faces of node a and of node b: one range add per node on the
        # BVH's face order (a difference array), then back to face ids.
        per_node = np.bincount(fr["entries"].ravel(), minlength=len(bvh["begin"]))
        diff = np.zeros(n_faces + 1, np.int64)
        np.add.at(diff, bvh["begin"], per_node)
        np.add.at(diff, bvh["end"], -per_node)
        out = np.zeros(n_faces, np.int64)
        out[bvh["order"]] = np.cumsum(diff[:-1])
        return out


MAX_THREADS = 1024  # a sanity cap (a typo should not start thousands of threads)


def _as_threads(threads) -> int:
    """None -> 0 (the default: all cores for a collider, the collider's for a query)."""
    if threads is None:
        return 0
    if isinstance(threads, (bool, np.bool_)) or not isinstance(threads, (int, np.integer)) \
            or not 1 <= threads <= MAX_THREADS:
        raise ValueError(f"threads: expected None or an integer in [1, {MAX_THREADS}], got {threads!r}")
    return int(threads)


# The exact predicates take non-zero coordinate magnitudes in [2^-128, 2^128] (the core refuses
# others); the checks that can name more than the core can (one point, a file) use these.
RANGE_RULE = "non-zero magnitudes must lie in [2^-128, 2^128] for the predicates to stay exact"


def _outside_range(a: np.ndarray) -> np.ndarray:
    """Per coordinate: non-zero and outside [2^-128, 2^128] in magnitude."""
    m = np.abs(a)
    return (m != 0) & ((m < 2.0**-128) | (m > 2.0**128))


def _as_point(x, name: str) -> np.ndarray:
    a = _asarray(x, name)
    if a.dtype.kind not in "fiu":
        raise ValueError(f"{name}: expected 3 real coordinates, got dtype {a.dtype}")
    if a.shape != (3,):
        raise ValueError(f"{name}: expected shape (3,), got {a.shape}")
    p = _as_float64(a, name)
    # The core's checks would speak of a row and of a mesh: here it is one point.
    for k, (v, outside) in enumerate(zip(p.tolist(), _outside_range(p).tolist())):
        if not math.isfinite(v):
            raise ValueError(f"{name}: non-finite coordinate {v!r} (component {k})")
        if outside:
            raise ValueError(f"{name}: coordinate {v!r} (component {k}) is outside the supported range: {RANGE_RULE} "
                             "(rescale the input)")
    return _as_positions(p.reshape(1, 3), 1, name)


def _check_arithmetic(arithmetic):
    if not isinstance(arithmetic, str) or arithmetic not in ARITHMETIC:
        raise ValueError(f"arithmetic: expected one of {ARITHMETIC}, got {arithmetic!r}")


def vertex_face_ccd(v_t0, f0_t0, f1_t0, f2_t0, v_t1, f0_t1, f1_t1, f2_t1, arithmetic: str = "exact") -> bool:
    """Does vertex v touch the closed triangle (f0, f1, f2) at some t in [0, 1], every point
    moving linearly from its t0 to its t1 position? Each argument is 3 coordinates."""
    _check_arithmetic(arithmetic)
    names = ("v_t0", "f0_t0", "f1_t0", "f2_t0", "v_t1", "f0_t1", "f1_t1", "f2_t1")
    pts = [_as_point(x, n) for x, n in zip((v_t0, f0_t0, f1_t0, f2_t0, v_t1, f0_t1, f1_t1, f2_t1), names)]
    return bool(_core.ccd.vertex_face_ccd_rows(*pts, arithmetic)[0])


def edge_edge_ccd(ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1, eb1_t1, arithmetic: str = "exact") -> bool:
    """Do the closed edges (ea0, ea1) and (eb0, eb1) touch at some t in [0, 1], every point moving
    linearly from its t0 to its t1 position? Each argument is 3 coordinates."""
    _check_arithmetic(arithmetic)
    names = ("ea0_t0", "ea1_t0", "eb0_t0", "eb1_t0", "ea0_t1", "ea1_t1", "eb0_t1", "eb1_t1")
    pts = [_as_point(x, n) for x, n in zip((ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1, eb1_t1), names)]
    return bool(_core.ccd.edge_edge_ccd_rows(*pts, arithmetic)[0])
