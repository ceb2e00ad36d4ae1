"""ccd(V0, V1, stop_at_first=True), the "is this step collision-free?" query: on generated steps,
for every CCD method, arithmetic and thread count, it reports one contact iff the brute force in
the same arithmetic finds one, that contact is the first one the full traced query tests (VF pairs,
then EE pairs), the test counters stop there, and all of it is the same for any thread count.
A step without contact runs every test; a traced first-hit query traces the tests up to the hit."""

import numpy as np
import pytest

import conecull
from ccd_brute_force import brute_force_ccd, generated_steps
from conecull.datasets.generated import grid_sheet
from thread_cases import THREADS, counters

STEPS = generated_steps()


def first_traced_contact(trace):
    """The first contact the traced full query tested, and the tests up to it (VF, then EE)."""
    n_vf = len(trace.vf["result"])
    hits = np.flatnonzero(np.concatenate([trace.vf["result"], trace.ee["result"]]))
    if len(hits) == 0:
        return None, n_vf + len(trace.ee["result"])
    i = int(hits[0])
    kind, events, j = ("vf", trace.vf, i) if i < n_vf else ("ee", trace.ee, i - n_vf)
    return (kind, tuple(events["pair"][j].tolist())), i + 1


def contacts(res):
    return [("vf", tuple(p)) for p in res.vf.tolist()] + [("ee", tuple(p)) for p in res.ee.tolist()]


@pytest.mark.parametrize("step", [s[0] for s in STEPS])
@pytest.mark.parametrize("arithmetic", ["float", "conservative", "exact"])
def test_ccd_first_hit_matches_brute_force_and_full_query(step, arithmetic):
    _, F, V0, V1 = next(s for s in STEPS if s[0] == step)
    vf_ref, ee_ref = brute_force_ccd(F, V0, V1, arithmetic)
    mesh = conecull.Mesh(F, n_vertices=len(V0))
    for method in conecull.CCD_METHODS:
        full = conecull.SelfCollider(mesh, method=method).ccd(V0, V1, arithmetic=arithmetic, trace=True)
        expect, tests = first_traced_contact(full.trace)
        first = None
        for threads in THREADS:
            res = conecull.SelfCollider(mesh, method=method).ccd(V0, V1, arithmetic=arithmetic, threads=threads,
                                                                 stop_at_first=True, toi=True)
            got = contacts(res)
            where = (step, arithmetic, method, threads)
            if vf_ref or ee_ref:
                assert len(got) == 1 and (got[0][1] in (vf_ref if got[0][0] == "vf" else ee_ref)), where
                assert got[0] == expect, where
                assert len(res.toi) == 1 and 0.0 <= res.toi[0] <= 1.0, where
            else:
                assert got == [] and expect is None, where
            assert res.stats["vf_tests"] + res.stats["ee_tests"] == tests, where
            assert res.stats["colliding_pairs"] == len(got), where
            c = counters(res.stats)
            first = first or (got, c)
            assert (got, c) == first, f"{where}: thread counts disagree"
        if vf_ref or ee_ref:  # tracing the first-hit query records the tests up to the hit
            rt = conecull.SelfCollider(mesh, method=method).ccd(V0, V1, arithmetic=arithmetic, trace=True,
                                                                stop_at_first=True)
            results = np.concatenate([rt.trace.vf["result"], rt.trace.ee["result"]])
            assert len(results) == tests and results[-1] and not results[:-1].any()


def test_ccd_first_hit_without_contact_runs_every_test():
    F, V = grid_sheet(12, 12)
    V1 = V.copy()
    V1[:, 2] += 0.05 * np.sin(3.0 * V[:, 0])  # a gentle bend: no contact
    mesh = conecull.Mesh(F, n_vertices=len(V))
    for method in conecull.CCD_METHODS:
        full = conecull.SelfCollider(mesh, method=method).ccd(V, V1)
        res = conecull.SelfCollider(mesh, method=method).ccd(V, V1, stop_at_first=True)
        assert len(full.vf) + len(full.ee) == 0 and len(res.vf) + len(res.ee) == 0
        assert counters(res.stats) == counters(full.stats), method


def test_ccd_stop_at_first_bad_value():
    F, V = grid_sheet(3, 3)
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=len(V)))
    with pytest.raises(ValueError, match="stop_at_first"):
        col.ccd(V, V, stop_at_first="yes")


def test_steps_cover_both_answers():
    """The steps above hold steps with contacts (in every arithmetic) and one without."""
    with_contact = {name for name, F, V0, V1 in STEPS if any(brute_force_ccd(F, V0, V1, "exact"))}
    assert len(with_contact) >= 3 and len(with_contact) < len(STEPS), with_contact


def late_hit_steps():
    """Steps whose first contact comes after many chunks of tests (the steps above hit within
    their first ~150 keys): the folding sheet's step 5 -> 6 (with nc, its first contact after
    ~740 of 16781 tests; cbc 311), and its contact-free step 4 -> 5 with one vertex pushed
    through the other layer (after ~590 of ~3000 tests)."""
    from thread_cases import sequences

    F, P = sequences()["folding_sheet"]
    V1 = P[5].copy()
    V1[-1, 2] -= 0.2 * np.ptp(P[4], axis=0).max()
    return [("fold 5-6", F, P[5], P[6]), ("fold 4-5 pushed", F, P[4], V1)]


@pytest.mark.parametrize("arithmetic", ["conservative", "exact"])
def test_ccd_first_hit_in_a_late_chunk(arithmetic):
    """With 2, 3 and 7 threads the first contact lies in a late chunk, where chunks after it may
    find their own contacts first (and are dropped): the same contact and counters as one
    thread and as the full traced query."""
    for step, F, V0, V1 in late_hit_steps():
        mesh = conecull.Mesh(F, n_vertices=len(V0))
        for method in conecull.CCD_METHODS:
            full = conecull.SelfCollider(mesh, method=method).ccd(V0, V1, arithmetic=arithmetic, trace=True)
            expect, tests = first_traced_contact(full.trace)
            total = full.stats["vf_tests"] + full.stats["ee_tests"]
            # chunks hold at least 64 keys (Chunks' grain): the hit is past the first four
            assert expect is not None and tests > 4 * 64, (step, method, tests, total)
            ref = None
            for threads in THREADS:
                res = conecull.SelfCollider(mesh, method=method).ccd(V0, V1, arithmetic=arithmetic, threads=threads,
                                                                     stop_at_first=True)
                got = contacts(res)
                assert got == [expect] and res.stats["vf_tests"] + res.stats["ee_tests"] == tests, (step, method, threads)
                ref = ref or counters(res.stats)
                assert counters(res.stats) == ref, (step, method, threads)
