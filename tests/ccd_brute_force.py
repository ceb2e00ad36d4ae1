"""The CCD reference of the traversal tests: every VF and EE pair of the mesh (no box, no cone,
no front), each through the single-pair CCD rows of the core in the given arithmetic. What it
checks is the culling; the primitives themselves are checked against ground truth and exact
twins elsewhere (tests/ccd/test_ccd_queries.py, test_ccd_formulas.py, the hard cases)."""

import numpy as np

import conecull
import meshcases
from conecull._core import ccd as C
from conecull.datasets.generated import fold, grid_sheet


def brute_force_ccd(F, V0, V1, arithmetic):
    mesh = conecull.Mesh(F, n_vertices=len(V0))
    E = mesh.edges
    used = np.unique(F)
    v = np.repeat(used, len(F))
    f = np.tile(np.arange(len(F)), len(used))
    keep = ~(F[f] == v[:, None]).any(axis=1)
    v, f = v[keep], f[keep]
    cols = [V0[v], V0[F[f, 0]], V0[F[f, 1]], V0[F[f, 2]], V1[v], V1[F[f, 0]], V1[F[f, 1]], V1[F[f, 2]]]
    hit = C.vertex_face_ccd_rows(*[np.ascontiguousarray(c) for c in cols], arithmetic)
    vf = {(int(a), int(b)) for a, b in zip(v[hit], f[hit])}
    i, j = np.triu_indices(len(E), 1)
    keep = ~((E[i][:, :, None] == E[j][:, None, :]).any(axis=(1, 2)))
    i, j = i[keep], j[keep]
    a, b, c, d = E[i, 0], E[i, 1], E[j, 0], E[j, 1]
    cols = [V0[a], V0[b], V0[c], V0[d], V1[a], V1[b], V1[c], V1[d]]
    hit = C.edge_edge_ccd_rows(*[np.ascontiguousarray(x) for x in cols], arithmetic)
    ee = {(int(x), int(y)) for x, y in zip(i[hit], j[hit])}
    return vf, ee


def _steps():
    F, V = grid_sheet(9, 9)
    yield "fold", F, fold(V, 0.9 * np.pi, radius=0.05), fold(V, 1.15 * np.pi, radius=0.05)
    _, F2, Va = meshcases.case("crumple_medium_s2")
    rng = np.random.default_rng(1)
    yield "crumple", F2, Va, Va + 0.02 * rng.standard_normal(Va.shape)
    _, F3, Vc = meshcases.case("cylinder_twist_mild")
    c, s = np.cos(0.3 * Vc[:, 2:3]), np.sin(0.3 * Vc[:, 2:3])
    yield "twist", F3, Vc, np.hstack([c * Vc[:, :1] - s * Vc[:, 1:2], s * Vc[:, :1] + c * Vc[:, 1:2], Vc[:, 2:]])
    Fs, Vs = grid_sheet(7, 7)
    two_F = np.vstack([Fs, Fs + len(Vs)])
    A0 = np.vstack([Vs, Vs + [0.1, 0.05, 0.3]])
    A1 = np.vstack([Vs, Vs + [0.1, 0.05, -0.3]])  # the second sheet passes through the first
    yield "two-sheets", two_F, A0, A1
    # Contours that nearly meet themselves (meshcases._near_closing), now over a step: a flat
    # spiral's arms from 1e-10 apart to 1e-10 overlapping (coplanar motion, every contact
    # degenerate), and a helix's upper turn, 1e-12 above the lower, pressed through it by 1e-6.
    Fp, P0 = meshcases.spiral_strip(54, 2.25, 0.25, 0.25 + 1e-10)
    yield "spiral-arms-close", Fp, P0, meshcases.spiral_strip(54, 2.25, 0.25, 0.25 - 1e-10)[1]
    Fh, H0 = meshcases.ring_strip(28, 1, 2 * np.pi + 0.6, 1e-12)
    H1 = H0.copy()
    H1[-2:, 2] -= 1e-6
    yield "helix-turn-pressed-through", Fh, H0, H1


def generated_steps():
    """(name, faces, V0, V1): folding, crumpling, twisting, two sheets passing through each other,
    a spiral's arms closing, a helix's turn pressed through the one below."""
    return list(_steps())
