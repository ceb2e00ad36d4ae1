"""conecull: reliable self-collision culling of deforming triangle meshes.

Implements Wang et al., "Efficient and Reliable Self-Collision Culling using Unprojected
Normal Cones": an AABB BVH whose nodes carry normal cones and boundary contours, culled by the
unprojected contour test (Alg. 1, 2), with exact predicates throughout.

    mesh = conecull.Mesh(faces)                      # (m, 3) int
    col = conecull.SelfCollider(mesh, method="nc")   # "aabb" | "nc" | "aabb+front" | "nc+front" | "sct" | "cbc"
    res = col.dcd(V)                                 # (n, 3) float64 (float32 accepted)
    res.pairs                                        # (k, 2) int64, i < j, sorted
    res.stats                                        # dict of counters and seconds
    res = col.ccd(V0, V1, arithmetic="exact")        # continuous: res.vf, res.ee
    conecull.vertex_face_ccd(v_t0, f0_t0, f1_t0, f2_t0, v_t1, f0_t1, f1_t1, f2_t1)
    conecull.edge_edge_ccd(ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1, eb1_t1)
"""

from conecull._api import ARITHMETIC, CCD_METHODS, CcdResult, DcdResult, Mesh, SelfCollider, METHODS, edge_edge_ccd, vertex_face_ccd

__all__ = ["Mesh", "SelfCollider", "DcdResult", "CcdResult", "METHODS", "CCD_METHODS", "ARITHMETIC", "vertex_face_ccd",
           "edge_edge_ccd"]
__version__ = "0.1.0"

# The package's other parts load on first use (`conecull.datasets.load(...)` after only `import
# conecull`), so importing the core does not pull in trimesh, rerun or viser.
_SUBMODULES = ("datasets", "viz", "app", "trace")


def __getattr__(name):
    if name in _SUBMODULES:
        import importlib

        return importlib.import_module(f"conecull.{name}")
    raise AttributeError(f"module 'conecull' has no attribute {name!r}")
