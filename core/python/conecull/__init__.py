"""conecull: reliable self-collision culling of deforming triangle meshes.

Implements Wang et al., "Efficient and Reliable Self-Collision Culling using Unprojected
Normal Cones": an AABB BVH whose nodes carry normal cones and boundary contours, culled by the
unprojected contour test (Alg. 1, 2), with exact predicates throughout.

    mesh = conecull.Mesh(faces)                      # (m, 3) int
    col = conecull.SelfCollider(mesh, method="nc")   # "aabb" | "nc"
    res = col.dcd(V)                                 # (n, 3) float64 (float32 accepted)
    res.pairs                                        # (k, 2) int64, i < j, sorted
    res.stats                                        # dict of counters and seconds
"""

from conecull._api import ARITHMETIC, CcdResult, DcdResult, Mesh, SelfCollider, METHODS

__all__ = ["Mesh", "SelfCollider", "DcdResult", "CcdResult", "METHODS", "ARITHMETIC"]
__version__ = "0.1.0"
