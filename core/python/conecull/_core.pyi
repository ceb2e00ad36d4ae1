"""Type stubs of the private compiled module conecull._core (use the conecull package). Its submodules
are written as classes of static methods. tests/test_core_stubs.py checks these names and parameters
against the compiled module."""

from typing import Optional

import numpy as np
import numpy.typing as npt

F64 = npt.NDArray[np.float64]
I32 = npt.NDArray[np.int32]
I64 = npt.NDArray[np.int64]
I8 = npt.NDArray[np.int8]
Bool = npt.NDArray[np.bool_]

class Topology:
    n_vertices: int
    n_faces: int
    n_edges: int
    n_components: int
    faces: I32
    edges: I32
    face_edges: I32
    edge_face_offsets: I32
    edge_face_ids: I32
    vertex_face_offsets: I32
    vertex_face_ids: I32
    boundary_edges: I32
    edge_nonmanifold: npt.NDArray[np.uint8]
    vertex_nonmanifold: npt.NDArray[np.uint8]
    face_touches_nonmanifold: npt.NDArray[np.uint8]
    face_component: I32

def build_topology(faces: I32, n_vertices: int) -> Topology: ...

class SelfCollider:
    built: bool
    method: str
    threads: int
    def __init__(self, topology: Topology, method: str, leaf_size: int, threads: int = 0) -> None: ...
    def dcd(self, V: F64, trace: bool = False, threads: int = 0,
            stop_at_first: bool = False) -> tuple[I64, dict, Optional[dict]]: ...
    def ccd(self, V0: F64, V1: F64, arithmetic: str, trace: bool = False, toi: bool = False, threads: int = 0,
            stop_at_first: bool = False) -> tuple[I64, I64, dict, Optional[dict], Optional[F64]]: ...
    def bvh_arrays(self) -> dict: ...
    def cone_arrays(self) -> dict: ...
    def contour_arrays(self) -> dict: ...
    def front_arrays(self, continuous: bool) -> dict: ...

class predicates:
    @staticmethod
    def orient3d(a: F64, b: F64, c: F64, d: F64) -> I8: ...
    @staticmethod
    def orient2d(a: F64, b: F64, c: F64) -> I8: ...
    @staticmethod
    def side_sign(a: F64, b: F64, c: F64, l: F64) -> I8: ...
    @staticmethod
    def ray_side_sign(v: F64, o: F64, r: F64, l: F64) -> I8: ...

class cone:
    @staticmethod
    def triangle_cone(a: F64, b: F64, c: F64) -> tuple[F64, F64, F64]: ...
    @staticmethod
    def merge_cones(axis_p: F64, cos_p: F64, sin_p: F64, axis_q: F64, cos_q: F64, sin_q: F64) -> tuple[F64, F64, F64]: ...

class contour:
    @staticmethod
    def contour_test(loop: I32, V: F64, l: F64, r: Optional[F64] = None, o: Optional[F64] = None) -> dict: ...
    @staticmethod
    def sct_contour_test(loop: I32, V: F64, l: F64) -> dict: ...
    @staticmethod
    def cbc_contour_test(loop: I32, V: F64, l: F64) -> dict: ...
    @staticmethod
    def cbc_contour_test_ccd(loop: I32, V0: F64, V1: F64, l: F64) -> dict: ...
    @staticmethod
    def simplicity_test(loop: I32, V: F64, l: F64) -> dict: ...
    @staticmethod
    def simplicity_test_ccd(loop: I32, V0: F64, V1: F64, l: F64) -> dict: ...
    @staticmethod
    def simplicity_pass(loop: I32, V: F64, l: F64, portable: bool = False) -> tuple[F64, F64, float, float]: ...
    @staticmethod
    def simplicity_pass_vectorised() -> bool: ...
    @staticmethod
    def nc_contour_test(loop: I32, V: F64, l: F64, simplicity_first: bool = False) -> dict: ...
    @staticmethod
    def nc_contour_test_ccd(loop: I32, V0: F64, V1: F64, l: F64, simplicity_first: bool = False) -> dict: ...

class ccd:
    @staticmethod
    def triangle_cone_ccd(a0: F64, b0: F64, c0: F64, a1: F64, b1: F64, c1: F64) -> tuple[F64, F64, F64]: ...
    @staticmethod
    def csidesign1(o: F64, b0: F64, c0: F64, b1: F64, c1: F64, l: F64, o1: Optional[F64] = None) -> I8: ...
    @staticmethod
    def contour_test_ccd(loop: I32, V0: F64, V1: F64, l: F64, r: Optional[F64] = None, o: Optional[F64] = None,
                         o1: Optional[F64] = None) -> dict: ...
    @staticmethod
    def vertex_face_ccd_rows(v_t0: F64, f0_t0: F64, f1_t0: F64, f2_t0: F64, v_t1: F64, f0_t1: F64, f1_t1: F64,
                             f2_t1: F64, arithmetic: str) -> Bool: ...
    @staticmethod
    def edge_edge_ccd_rows(ea0_t0: F64, ea1_t0: F64, eb0_t0: F64, eb1_t0: F64, ea0_t1: F64, ea1_t1: F64, eb0_t1: F64,
                           eb1_t1: F64, arithmetic: str) -> Bool: ...

class elementary:
    @staticmethod
    def triangles_collide(fp: I32, P: F64, fq: I32, Q: F64) -> Bool: ...
    @staticmethod
    def triangles_collide4(faces: I32, V: F64, pairs: I32, portable: bool = False) -> Bool: ...
    @staticmethod
    def triangles_apart(faces: I32, V: F64, pairs: I32, portable: bool = False) -> Bool: ...
    @staticmethod
    def triangles_apart_vectorised() -> bool: ...

class traversal:
    @staticmethod
    def first_hit_order(right: I32, depth: I32, tasks: I32) -> I32: ...

class parallel:
    @staticmethod
    def compute_ceiling(threads: int, chunks: int = 64, iterations: int = 200000) -> float: ...
