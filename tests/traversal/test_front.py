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


def front_bytes(col, s):
    """What a front keeps between queries (stats.hpp): 8 bytes per entry, 24 per record (one per
    node the query reached with Collide(L, R)), 4 per BVH node (its slot)."""
    return 8 * s["front_entries"] + 24 * s["front_segments"] + 4 * len(col.bvh_arrays()["right"])


def check_front_records(col, s):
    """The records: one per node the query tracked or rested at, at most one per internal node;
    every node with entries has one. The conventional front (no cones) reaches every internal
    node, so keeps a record for each."""
    fr, right = col.front_arrays(), col.bvh_arrays()["right"]
    internal = int(np.count_nonzero(right >= 0))
    assert np.count_nonzero(fr["count"]) <= s["front_segments"] <= internal
    assert np.all(right[fr["count"] > 0] >= 0) and np.all(right[fr["resting"] > 0] >= 0)
    if col.method == "aabb+front":
        assert s["front_segments"] == internal
    assert s["front_bytes"] == front_bytes(col, s)


def test_front_stats_consistent_and_front_reused():
    """The first query builds the whole front (every entry added, none removed), later ones
    add and remove some; front_bytes counts all the front keeps (entries, records, slots); after
    the first frame of a smooth sequence the front saves box tests (resumed where the last query
    stopped instead of from the top). The waves are high enough that the cones do not cull the
    whole sheet (amplitude 0.15 is culled at the root: see below)."""
    F, frames = bending_sheet(2000, n_frames=8, amplitude=0.3)
    mesh = conecull.Mesh(F)
    cols = {m: conecull.SelfCollider(mesh, method=m) for m in conecull.METHODS}
    changed = {m: [0, 0] for m in FRONT}
    for k, V in enumerate(frames):
        res = {m: c.dcd(V) for m, c in cols.items()}
        for m, base in FRONT.items():
            s = res[m].stats
            assert s["front_entries"] > 0
            check_front_records(cols[m], s)
            assert s["front_rested"] == 0, (k, m)  # smooth motion: no sub-segment churns
            if k == 0:
                assert s["front_added"] == s["front_entries"] and s["front_removed"] == 0
            else:
                assert s["bv_tests"] < 0.75 * res[base].stats["bv_tests"], (k, m)
                assert s["front_entries"] == prev[m] + s["front_added"] - s["front_removed"], (k, m)
                changed[m][0] += s["front_added"] > 0
                changed[m][1] += s["front_removed"] > 0
        prev = {m: res[m].stats["front_entries"] for m in FRONT}
        for m in ("aabb", "nc"):
            assert res[m].stats["front_entries"] == 0 and res[m].stats["front_bytes"] == 0
    assert all(a and r for a, r in changed.values()), changed  # the fronts grew and shrank


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
        # All it keeps, records and slots included: the culled regions keep no records either.
        assert a["front_bytes"] <= ratio * b["front_bytes"], (a["front_bytes"], b["front_bytes"])
        assert a["front_segments"] < b["front_segments"] / 4


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


@pytest.mark.parametrize("threads", [1, 2])
@pytest.mark.parametrize("name", list(SEQUENCES))
def test_untraced_queries_equal_oracle_over_sequences(name, threads):
    """The tests above trace their queries, which run on one thread through the traced
    traversal; queries run untraced: the same sequences, on one and on two threads (the parallel
    traversal, whose tasks build the front in parts). Every method's pairs equal the oracle's on
    every frame, with the fronts kept from frame to frame, then across a jump back to the first
    frame and at a repeated one (the front unchanged); the fronts are really resumed (fewer box
    tests than without a front on most frames, where there is something to save)."""
    F, frames = sequence(name)
    mesh = conecull.Mesh(F)
    cols = {m: conecull.SelfCollider(mesh, method=m, threads=threads) for m in conecull.METHODS}
    n = len(frames)
    saved = {m: 0 for m in FRONT}
    for q, k in enumerate([*range(n), 0, 0, n - 1]):
        res = {m: c.dcd(frames[k]) for m, c in cols.items()}
        for m, r in res.items():
            got = as_set(r.pairs)
            assert got == oracle(name, k), f"{name} threads={threads} query {q} (frame {k}) {m}: " \
                f"missing {sorted(oracle(name, k) - got)[:5]} extra {sorted(got - oracle(name, k))[:5]}"
        for m, base in FRONT.items():
            s = res[m].stats
            assert s["elementary_tests"] == res[base].stats["elementary_tests"], (q, m)
            check_front_records(cols[m], s)
            if 0 < q < n:
                saved[m] += s["bv_tests"] < res[base].stats["bv_tests"]
            if q == n + 1:  # frame 0 again: nothing moved since the last query
                assert s["front_added"] == 0 and s["front_removed"] == 0, (m, s)
    # On the bending sheet the cones cull all but a few small Collide(L, R), where a front has
    # little to save: there only the conventional front must.
    for m in (FRONT if name != "bending" else ["aabb+front"]):
        assert saved[m] >= (n - 1) // 2, saved
