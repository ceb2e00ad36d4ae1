"""Low-level culling of CCD (Sec. 5.1): the VF and EE pairs a query makes from its candidate
triangle pairs. Each vertex and edge is owned by one of its faces, so each pair is made once
without sorting; a candidate whose faces' swept boxes are apart is skipped whole. Without cones
("aabb") nothing is culled, so the pairs made must be exactly the brute-force set: every VF pair
(v not in f) and every EE pair (no shared vertex) whose swept boxes overlap, none lost and none
made twice (the counts `vf_candidates` / `ee_candidates` equal the brute-force counts, on
manifold sheets and on a non-manifold triangle soup, a third of whose edges have three to seven faces)."""

import numpy as np
import pytest

import conecull
from ccd_brute_force import generated_steps


def _swept(V0, V1, ids):
    """Swept boxes (lo, hi) of the primitives whose vertex ids are the rows of `ids`."""
    P = np.concatenate([V0[ids], V1[ids]], axis=1)
    return P.min(axis=1), P.max(axis=1)


def _overlap(lo1, hi1, lo2, hi2):
    """Closed boxes, every pair of rows of the two sets: (n1, n2) bool."""
    return ((lo1[:, None, :] <= hi2[None, :, :]) & (lo2[None, :, :] <= hi1[:, None, :])).all(axis=2)


def brute_force_pair_counts(F, V0, V1, E):
    used = np.unique(F)
    vlo, vhi = _swept(V0, V1, used[:, None])
    flo, fhi = _swept(V0, V1, F)
    vf = _overlap(vlo, vhi, flo, fhi) & ~(F[None, :, :] == used[:, None, None]).any(axis=2)
    elo, ehi = _swept(V0, V1, E)
    ee = _overlap(elo, ehi, elo, ehi) & ~(E[:, None, :, None] == E[None, :, None, :]).any(axis=(2, 3))
    return int(vf.sum()), int(np.triu(ee, 1).sum())


def _soup():
    """A non-manifold soup: 300 distinct triangles over 30 points in a unit cube, moving."""
    rng = np.random.default_rng(7)
    F = np.unique(np.sort(np.array([rng.choice(30, 3, replace=False) for _ in range(340)]), axis=1), axis=0)[:300]
    V0 = rng.random((30, 3))
    return "soup", F, V0, V0 + 0.1 * rng.standard_normal(V0.shape)


CASES = generated_steps() + [_soup()]


@pytest.mark.parametrize("name,F,V0,V1", CASES, ids=[c[0] for c in CASES])
def test_pairs_made_once_and_none_lost(name, F, V0, V1):
    mesh = conecull.Mesh(F, n_vertices=len(V0))
    n_vf, n_ee = brute_force_pair_counts(np.asarray(F), V0, V1, mesh.edges)
    assert n_vf > 0 and n_ee > 0, name  # the case has pairs to make
    if name == "soup":
        faces_per_edge = np.unique(np.sort(np.asarray(F)[:, [0, 1, 1, 2, 0, 2]].reshape(-1, 2), axis=1), axis=0,
                                   return_counts=True)[1]
        assert (faces_per_edge >= 3).mean() > 0.3  # non-manifold
    for threads in (1, 2):
        s = conecull.SelfCollider(mesh, method="aabb", threads=threads).ccd(V0, V1).stats
        assert (s["vf_candidates"], s["ee_candidates"]) == (n_vf, n_ee), (name, threads)
    # Cone culling only removes pairs (of regions proven free of contact).
    for method in conecull.CCD_METHODS:
        s = conecull.SelfCollider(mesh, method=method).ccd(V0, V1).stats
        assert s["vf_candidates"] <= n_vf and s["ee_candidates"] <= n_ee, (name, method)
