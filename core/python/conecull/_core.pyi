"""Type stubs of the private compiled module conecull._core (use the conecull package)."""

from typing import Optional

import numpy as np
import numpy.typing as npt

F64 = npt.NDArray[np.float64]
I32 = npt.NDArray[np.int32]

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
    def __init__(self, topology: Topology, method: str, leaf_size: int, threads: int = 0) -> None: ...
    def dcd(self, V: F64, trace: bool = False, threads: int = 0,
            stop_at_first: bool = False) -> tuple[npt.NDArray[np.int64], dict, Optional[dict]]: ...
    def bvh_arrays(self) -> dict: ...
    def cone_arrays(self) -> dict: ...
    def contour_arrays(self) -> dict: ...

class predicates:
    @staticmethod
    def orient3d(a: F64, b: F64, c: F64, d: F64) -> npt.NDArray[np.int8]: ...
    @staticmethod
    def orient2d(a: F64, b: F64, c: F64) -> npt.NDArray[np.int8]: ...
    @staticmethod
    def side_sign(a: F64, b: F64, c: F64, l: F64) -> npt.NDArray[np.int8]: ...
    @staticmethod
    def ray_side_sign(v: F64, o: F64, r: F64, l: F64) -> npt.NDArray[np.int8]: ...

class cone:
    @staticmethod
    def triangle_cone(a: F64, b: F64, c: F64) -> tuple[F64, F64, F64]: ...
    @staticmethod
    def merge_cones(axis_p: F64, cos_p: F64, sin_p: F64, axis_q: F64, cos_q: F64, sin_q: F64) -> tuple[F64, F64, F64]: ...

class contour:
    @staticmethod
    def contour_test(loop: I32, V: F64, l: F64, r: Optional[F64] = None) -> dict: ...
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
    def nc_contour_test(loop: I32, V: F64, l: F64, simplicity_first: bool = False) -> dict: ...
    @staticmethod
    def nc_contour_test_ccd(loop: I32, V0: F64, V1: F64, l: F64, simplicity_first: bool = False) -> dict: ...

class elementary:
    @staticmethod
    def triangles_collide(fp: I32, P: F64, fq: I32, Q: F64) -> npt.NDArray[np.bool_]: ...
