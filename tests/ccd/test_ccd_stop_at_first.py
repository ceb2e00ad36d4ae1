"""ccd(V0, V1, stop_at_first=True), the "is this step collision-free?" query: on generated steps,
for every CCD method, arithmetic and thread count, it reports one contact iff the brute force in
the same arithmetic finds one, and all of it (the contact and every counter) is the same for any
thread count. A candidate's VF and EE pairs are made and tested as soon as it is reached (its VF
pairs, then its EE pairs), so the pairs of later candidates are never made. The methods that
traverse fully (front methods, cbc, traced queries) go through the candidates in traversal order:
a traced first-hit query records the tests up to the hit, no contact before it, and the untraced
query finds the same contact after as many tests. aabb and nc stop the traversal at the hit too
(tasks in first-hit order, as dcd). A step without contact runs every test."""

import numpy as np
import pytest

import conecull
from ccd_brute_force import brute_force_ccd, generated_steps
from conecull.datasets.generated import grid_sheet
from thread_cases import THREADS, counters

STEPS = generated_steps()
STOPS_TRAVERSAL = ("aabb", "nc")  # untraced: the first-hit traversal (tasks in first-hit order)


def contacts(res):
    return [("vf", tuple(p)) for p in res.vf.tolist()] + [("ee", tuple(p)) for p in res.ee.tolist()]


def traced_tests(trace):
    """The (kind, pair) of every VF / EE test a traced query ran, and their results."""
    keys = [("vf", tuple(p)) for p in trace.vf["pair"].tolist()] + [("ee", tuple(p)) for p in trace.ee["pair"].tolist()]
    return keys, np.concatenate([trace.vf["result"], trace.ee["result"]])


def check_first_hit(mesh, V0, V1, arithmetic, method, expect_contact, where):
    """One method on one step: the traced first-hit query (serial, traversal order) against the
    full traced query, then every thread count against it; the contact and the counters."""
    full = conecull.SelfCollider(mesh, method=method).ccd(V0, V1, arithmetic=arithmetic, trace=True)
    full_keys, full_results = traced_tests(full.trace)
    traced = conecull.SelfCollider(mesh, method=method).ccd(V0, V1, arithmetic=arithmetic, trace=True,
                                                            stop_at_first=True)
    keys, results = traced_tests(traced.trace)
    n_tests = traced.stats["vf_tests"] + traced.stats["ee_tests"]
    # the tests it traced are the full query's (the same pairs, each once, the same results)
    assert len(keys) == n_tests and len(set(keys)) == n_tests, where
    outcome = dict(zip(full_keys, full_results.tolist()))
    assert all(outcome.get(k) == r for k, r in zip(keys, results.tolist())), where
    if expect_contact:
        # the hit, and no other contact among the tests it ran (the trace lists VF tests, then EE
        # tests, not interleaved as they ran: candidate by candidate, so the hit need not be last)
        assert results.sum() == 1, where
        assert contacts(traced) == [keys[int(np.argmax(results))]], where
    else:
        assert not results.any() and counters(traced.stats) == counters(full.stats), where
    ref = None
    for threads in THREADS:
        res = conecull.SelfCollider(mesh, method=method).ccd(V0, V1, arithmetic=arithmetic, threads=threads,
                                                             stop_at_first=True, toi=True)
        got = contacts(res)
        at = where + (threads,)
        assert len(got) == (1 if expect_contact else 0), at
        assert res.stats["colliding_pairs"] == len(got), at
        if got:
            assert outcome.get(got[0]) is True, at  # a contact the full query finds
            assert len(res.toi) == 1 and 0.0 <= res.toi[0] <= 1.0, at
        if method not in STOPS_TRAVERSAL or not expect_contact:
            # the same candidates in the same order as the traced query: the same contact
            # after as many tests (without a contact: every test)
            assert got == contacts(traced) and counters(res.stats) == counters(traced.stats), at
        else:
            assert res.stats["vf_tests"] + res.stats["ee_tests"] <= full.stats["vf_tests"] + full.stats["ee_tests"], at
        ref = ref or (got, counters(res.stats))
        assert (got, counters(res.stats)) == ref, f"{at}: thread counts disagree"
    return full, ref


@pytest.mark.parametrize("step", [s[0] for s in STEPS])
@pytest.mark.parametrize("arithmetic", ["float", "conservative", "exact"])
def test_ccd_first_hit_matches_brute_force(step, arithmetic):
    _, F, V0, V1 = next(s for s in STEPS if s[0] == step)
    vf_ref, ee_ref = brute_force_ccd(F, V0, V1, arithmetic)
    mesh = conecull.Mesh(F, n_vertices=len(V0))
    for method in conecull.CCD_METHODS:
        _, (got, _) = check_first_hit(mesh, V0, V1, arithmetic, method, bool(vf_ref or ee_ref), (step, arithmetic, method))
        if got:
            kind, pair = got[0]
            assert pair in (vf_ref if kind == "vf" else ee_ref), (step, arithmetic, method)


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
    """Steps whose first contact comes after many tests (the steps above hit within their first
    ~100): the folding sheet's step 5 -> 6 (full traversal: its first contact after ~1300-14000
    tests, by method), and its contact-free step 4 -> 5 with one vertex pushed through the other
    layer (after ~1700-14700)."""
    from thread_cases import sequences

    F, P = sequences()["folding_sheet"]
    V1 = P[5].copy()
    V1[-1, 2] -= 0.2 * np.ptp(P[4], axis=0).max()
    return [("fold 5-6", F, P[5], P[6]), ("fold 4-5 pushed", F, P[4], V1)]


@pytest.mark.parametrize("arithmetic", ["conservative", "exact"])
def test_ccd_first_hit_in_a_late_chunk(arithmetic):
    """With 2, 3 and 7 threads the first contact lies in a late chunk of candidates (or a late
    block of tasks), where chunks after it may find their own contacts first (and are dropped):
    the same contact and counters as one thread and as the traced query; aabb and nc stop the
    traversal and the pair generation early."""
    for step, F, V0, V1 in late_hit_steps():
        mesh = conecull.Mesh(F, n_vertices=len(V0))
        for method in conecull.CCD_METHODS:
            full, (got, c) = check_first_hit(mesh, V0, V1, arithmetic, method, True, (step, arithmetic, method))
            assert len(got) == 1
            if method in STOPS_TRAVERSAL:
                n_full = full.stats["vf_candidates"] + full.stats["ee_candidates"]
                assert c["bv_tests"] < full.stats["bv_tests"] / 2, (step, method, c["bv_tests"])
                assert c["vf_candidates"] + c["ee_candidates"] < n_full / 4, (step, method)
            else:  # they must traverse fully, and reach the hit after many tests
                assert c["bv_tests"] == full.stats["bv_tests"] and c["vf_tests"] + c["ee_tests"] > 1000, (step, method)
