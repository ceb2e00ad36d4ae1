"""The BVTT front methods ("aabb+front", "nc+front", Alg. 4) keep their front between queries and
must still return exactly the oracle's pairs on every frame: over deforming sequences (fronts
reused, grown and shrunk), after large jumps between unrelated poses, when motion stops, and
when DCD and CCD queries alternate on one collider. Their candidate pairs are exactly those of
the method without a front."""

import functools

import numpy as np
import pytest

import conecull
from conecull.datasets.generated import bending_sheet, crumpling_sphere, fold, sheet_for_triangles
from oracle import brute_force_pairs

FRONT = {"aabb+front": "aabb", "nc+front": "nc"}


def folding(n_triangles=400, n_frames=24):
    """A rippled sheet folding from 0.85 pi to 1.3 pi: culled flat parts, a moving fold and
    self-intersections on most frames."""
    F, V = sheet_for_triangles(n_triangles)
    V = V.copy()
    V[:, 2] = 0.01 * np.sin(9.0 * V[:, 0]) * np.sin(7.0 * V[:, 1])
    return F, np.stack([fold(V, a, radius=0.05) for a in np.linspace(0.85 * np.pi, 1.3 * np.pi, n_frames)])


SEQUENCES = {
    "folding": folding,
    "crumpling": lambda: crumpling_sphere(10, 20, n_frames=24, strength=1.0),
    "bending": lambda: bending_sheet(400, n_frames=24, amplitude=0.3),
}


@functools.lru_cache(maxsize=None)
def sequence(name):
    return SEQUENCES[name]()


@functools.lru_cache(maxsize=None)
def oracle(name, k):
    F, frames = sequence(name)
    return frozenset(brute_force_pairs(F, frames[k]))


def as_set(pairs):
    return {tuple(p) for p in pairs.tolist()}


def candidates(res):
    return as_set(res.trace.elementary["pair"])


def check_frame(cols, V, expect, where):
    """Every collider's pairs equal the oracle's; each front method's candidates (traced) equal
    those of its method without a front."""
    res = {m: c.dcd(V, trace=True) for m, c in cols.items()}
    for m, r in res.items():
        got = as_set(r.pairs)
        assert got == expect, f"{where} {m}: missing {sorted(expect - got)[:5]} extra {sorted(got - expect)[:5]}"
    for m, base in FRONT.items():
        if m in res and base in res:
            assert candidates(res[m]) == candidates(res[base]), f"{where}: {m} and {base} test different candidates"
            assert res[m].stats["elementary_tests"] == res[base].stats["elementary_tests"]
    return res


def test_sequences_collide():
    """The sequences really have collisions on many frames (else the test below proves little)."""
    for name in ("folding", "crumpling"):
        n = len(sequence(name)[1])
        assert sum(1 for k in range(n) if oracle(name, k)) >= n // 3, name


@pytest.mark.parametrize("leaf_size", [1, 2])
@pytest.mark.parametrize("name", list(SEQUENCES))
def test_all_methods_equal_oracle_over_sequences(name, leaf_size):
    F, frames = sequence(name)
    mesh = conecull.Mesh(F)
    cols = {m: conecull.SelfCollider(mesh, method=m, leaf_size=leaf_size) for m in conecull.METHODS}
    grew = shrank = 0
    for k, V in enumerate(frames):
        res = check_frame(cols, V, oracle(name, k), f"{name} frame {k}")
        if k:
            grew += sum(res[m].stats["front_added"] > 0 for m in FRONT)
            shrank += sum(res[m].stats["front_removed"] > 0 for m in FRONT)
    assert grew and shrank, "the fronts never changed: the sequence does not exercise front tracking"


def test_large_motion_permuted_frames_and_unrelated_poses():
    """Frames in random order, jumps between two unrelated sequences of the same mesh and to a
    random pose where almost every box overlaps: the fronts are far from the new pose and must
    grow (and shrink back) a lot, results stay exact."""
    F, fold_frames = sequence("folding")
    F2, bend_frames = sequence("bending")
    assert np.array_equal(F, F2)
    rng = np.random.default_rng(3)
    noisy = fold_frames[0] + 0.08 * rng.standard_normal(fold_frames[0].shape)
    expect_noisy = frozenset(brute_force_pairs(F, noisy))
    assert len(expect_noisy) > 100
    poses = [("folding", k) for k in rng.permutation(len(fold_frames))]
    poses[5:5] = [("bending", 3), ("noisy", 0), ("folding", 0), ("noisy", 0), ("bending", 17)]
    mesh = conecull.Mesh(F)
    cols = {m: conecull.SelfCollider(mesh, method=m) for m in conecull.METHODS}
    for i, (name, k) in enumerate(poses):
        V = noisy if name == "noisy" else sequence(name)[1][k]
        expect = expect_noisy if name == "noisy" else oracle(name, k)
        res = check_frame(cols, V, expect, f"pose {i} ({name} {k})")
        if name == "noisy":
            # far from every front: each grows a lot, or rests where it churned (Collide from the top)
            assert all(res[m].stats["front_added"] > 1000 or res[m].stats["front_rested"] > 0 for m in FRONT), i


@pytest.mark.parametrize("name", ["folding", "crumpling"])
def test_motion_stops(name):
    """An identical consecutive frame leaves every front unchanged (nothing added or removed),
    and the results identical."""
    F, frames = sequence(name)
    mesh = conecull.Mesh(F)
    cols = {m: conecull.SelfCollider(mesh, method=m) for m in conecull.METHODS}
    for k in (0, 11, 11, 11, 12, 23, 23):
        res = check_frame(cols, frames[k], oracle(name, k), f"{name} frame {k}")
    for m in FRONT:
        s = res[m].stats
        assert s["front_added"] == 0 and s["front_removed"] == 0 and s["front_entries"] > 0, (m, s)


def test_front_stats_consistent_and_front_reused():
    """The first query builds the whole front (every entry added, none removed), later ones
    add and remove some (never a negative count); front_bytes counts its entries (8 bytes
    each); after the first frame of a smooth sequence the front saves box tests (resumed where
    the last query stopped instead of from the top). The waves are high enough that the cones
    do not cull the whole sheet (amplitude 0.15 is culled at the root: see below)."""
    F, frames = bending_sheet(2000, n_frames=8, amplitude=0.3)
    mesh = conecull.Mesh(F)
    cols = {m: conecull.SelfCollider(mesh, method=m) for m in conecull.METHODS}
    for k, V in enumerate(frames):
        res = {m: c.dcd(V) for m, c in cols.items()}
        for m, base in FRONT.items():
            s = res[m].stats
            assert s["front_entries"] > 0 and s["front_bytes"] == 8 * s["front_entries"]
            assert s["front_added"] >= 0 and s["front_removed"] >= 0
            assert s["front_rested"] == 0, (k, m)  # smooth motion: no sub-segment churns
            if k == 0:
                assert s["front_added"] == s["front_entries"] and s["front_removed"] == 0
            else:
                assert s["bv_tests"] < 0.75 * res[base].stats["bv_tests"], (k, m)
        for m in ("aabb", "nc"):
            assert res[m].stats["front_entries"] == 0


@pytest.mark.parametrize("scene,ratio", [("bending", 0.5), ("folding", 0.4)])
def test_nc_front_smaller_than_aabb_front_on_a_smooth_sheet(scene, ratio):
    """Normal cone culling drops the front of every culled node (Sec. 4): on a smoothly bending
    sheet (no self-intersection) and on a sheet folding onto itself, the guided front is a
    fraction of the conventional one."""
    if scene == "bending":
        F, frames = bending_sheet(2000, n_frames=6, amplitude=0.3)
    else:
        F, V = sheet_for_triangles(2000)
        # Past pi: the normals span more than a hemisphere, so no cone culls the whole sheet (at
        # 0.95 pi the root is culled, and there is no front at all).
        frames = [fold(V, a, radius=0.03) for a in np.linspace(1.02 * np.pi, 1.2 * np.pi, 6)]
    mesh = conecull.Mesh(F)
    nc = conecull.SelfCollider(mesh, method="nc+front")
    aabb = conecull.SelfCollider(mesh, method="aabb+front")
    for V in frames:
        a, b = nc.dcd(V).stats, aabb.dcd(V).stats
        assert 0 < a["front_entries"] <= ratio * b["front_entries"], (a["front_entries"], b["front_entries"])
        assert a["front_bytes"] < b["front_bytes"]


def test_gently_bending_sheet_is_culled_at_the_root():
    """Waves of amplitude 0.15 keep every normal of the sheet within a hemisphere: the root's cone
    (the smallest cone holding its children's, normal_cone.hpp) is bounded, its contour passes,
    and nc+front keeps no front at all; the conventional front is there all the same."""
    F, frames = bending_sheet(2000, n_frames=6, amplitude=0.15)
    mesh = conecull.Mesh(F)
    nc = conecull.SelfCollider(mesh, method="nc+front")
    aabb = conecull.SelfCollider(mesh, method="aabb+front")
    for V in frames:
        a, b = nc.dcd(V), aabb.dcd(V)
        assert a.stats["front_entries"] == 0 and a.stats["elementary_tests"] == 0 and len(a.pairs) == 0
        assert a.stats["contour_passed"] == 1 and b.stats["front_entries"] > 0 and len(b.pairs) == 0


def test_culled_region_keeps_no_front():
    """When a folded sheet is laid flat, everything is culled: nc+front frees its whole front
    (and rebuilds it, exactly, when the fold comes back)."""
    F, frames = sequence("folding")
    flat = sheet_for_triangles(400)[1]
    mesh = conecull.Mesh(F)
    col = conecull.SelfCollider(mesh, method="nc+front")
    before = col.dcd(frames[20]).stats["front_entries"]
    assert before > 0
    s = col.dcd(flat).stats
    assert s["front_entries"] == 0 and s["front_removed"] == before and len(col.dcd(flat).pairs) == 0
    assert as_set(col.dcd(frames[20]).pairs) == oracle("folding", 20)


def check_front_is_a_cut(col, kind, stats):
    """front_arrays: each Front_X is a cut of the BVTT of Collide(X->left, X->right): its entries
    (a under X's left child, b under its right) cover every triangle pair (one in each child)
    exactly once, so their triangle pair counts add up to the children's product (entries are
    whole subtrees, disjoint by construction of a cut). front_load matches a brute-force count."""
    fr, bvh = col.front_arrays(kind), col.bvh_arrays()
    begin, end, left, right = bvh["begin"], bvh["end"], bvh["left"], bvh["right"]
    assert len(fr["entries"]) == len(fr["owner"]) == fr["count"].sum() == stats["front_entries"]
    assert np.array_equal(np.bincount(fr["owner"], minlength=len(begin)), fr["count"])
    size = (end - begin).astype(np.int64)
    for x in np.flatnonzero(fr["count"]):
        mine = fr["entries"][fr["owner"] == x]
        l, r = left[x], right[x]
        a, b = mine[:, 0], mine[:, 1]
        assert np.all((begin[l] <= begin[a]) & (end[a] <= end[l])), f"node {x}: an entry's a is not under X->left"
        assert np.all((begin[r] <= begin[b]) & (end[b] <= end[r])), f"node {x}: an entry's b is not under X->right"
        assert (size[a] * size[b]).sum() == size[l] * size[r], f"node {x}: Front_X is not a cut"
        pairs = {(i, j) for i, j in zip(a.tolist(), b.tolist())}
        assert len(pairs) == len(mine)
    load = np.zeros(col.mesh.n_faces, np.int64)
    for a, b in fr["entries"]:
        load[bvh["order"][begin[a] : end[a]]] += 1
        load[bvh["order"][begin[b] : end[b]]] += 1
    assert np.array_equal(col.front_load(kind), load)


def test_churning_front_rests_then_tracks_again():
    """Two far poses in turn (a step's two ends queried alternately): sub-segments whose update
    costs more box tests than Collide from the top rest (BvttFront::churned): they keep no entries
    while resting, the fronts stay cuts and every result stays exact. Once the motion stops,
    every resting node is tracked again and the front settles (nothing added, removed or resting)."""
    F, frames = sequence("crumpling")
    mesh = conecull.Mesh(F)
    cols = {m: conecull.SelfCollider(mesh, method=m) for m in (*FRONT, *FRONT.values())}
    rested = {m: 0 for m in FRONT}
    for q in range(12):
        k = 0 if q % 2 == 0 else len(frames) - 1
        res = check_frame(cols, frames[k], oracle("crumpling", k), f"query {q} (frame {k})")
        for m in FRONT:
            rested[m] += res[m].stats["front_rested"]
            fr = cols[m].front_arrays()
            assert not np.any(fr["count"][fr["resting"] > 0]), f"query {q} {m}: a resting node keeps entries"
            check_front_is_a_cut(cols[m], "dcd", res[m].stats)
    assert all(r > 0 for r in rested.values()), rested
    for q in range(20):  # longer than the longest rest (16 queries)
        res = check_frame(cols, frames[0], oracle("crumpling", 0), f"still, query {q}")
    for m in FRONT:
        s = res[m].stats
        assert s["front_rested"] == 0 and s["front_added"] == 0 and s["front_removed"] == 0, (m, s)
        assert not cols[m].front_arrays()["resting"].any()
        assert s["bv_tests"] <= res[FRONT[m]].stats["bv_tests"], m


@pytest.mark.parametrize("method", ["aabb+front", "nc+front"])
def test_front_arrays_are_cuts_frame_after_frame(method):
    F, frames = sequence("folding")
    mesh = conecull.Mesh(F)
    col = conecull.SelfCollider(mesh, method=method, threads=1)
    seen = 0
    for k in range(0, len(frames), 3):
        s = col.dcd(frames[k]).stats
        check_front_is_a_cut(col, "dcd", s)
        seen += s["front_entries"] > 0
    s = col.ccd(frames[10], frames[12]).stats
    check_front_is_a_cut(col, "ccd", s)
    assert seen >= 4 and s["front_entries"] > 0


def test_front_arrays_errors():
    F, frames = sequence("folding")
    mesh = conecull.Mesh(F)
    with pytest.raises(ValueError, match="method: 'nc' keeps no BVTT front"):
        conecull.SelfCollider(mesh, method="nc").front_arrays()
    col = conecull.SelfCollider(mesh, method="nc+front")
    with pytest.raises(ValueError, match="kind: expected 'dcd' or 'ccd'"):
        col.front_arrays("both")
    for kind in (np.array(["dcd", "ccd"]), np.array(["dcd"]), ["dcd"], None, 1):  # not a name: refused, never truthy
        with pytest.raises(ValueError, match="kind: expected 'dcd' or 'ccd'"):
            col.front_load(kind)
    assert len(col.front_arrays("dcd")["entries"]) == 0 and not col.front_load("ccd").any()  # before any query
