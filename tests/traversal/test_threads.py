"""threads=: DCD gives identical results - the same arrays in the same order and the same
counters - for 1, 2, 3 and 7 threads, for every method, over generated sequences (fronts
evolving from query to query) and the mesh cases (with a CCD step from each); it equals the
oracle; bad values raise ValueError naming `threads`. CCD over sequences: tests/ccd/test_ccd_threads.py."""

import os

import numpy as np
import pytest

import conecull
import meshcases
from conecull.datasets.generated import grid_sheet
from oracle import brute_force_pairs
from thread_cases import THREADS, counters, sequences

def dcd_runs(F, frames, method, threads):
    col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=frames.shape[1]), method=method, threads=threads)
    return [col.dcd(V) for V in frames]


@pytest.mark.parametrize("scene", ["folding_sheet", "crumpling_sphere"])
@pytest.mark.parametrize("method", conecull.METHODS)
def test_dcd_identical_for_any_thread_count(scene, method):
    F, frames = sequences()[scene]
    ref = dcd_runs(F, frames, method, 1)
    assert sum(len(r.pairs) for r in ref) > 0  # the sequence really collides
    assert ref[-1].stats["elementary_tests"] > 2000  # ... and splits into many chunks
    for threads in THREADS[1:]:
        for k, (a, b) in enumerate(zip(ref, dcd_runs(F, frames, method, threads))):
            assert np.array_equal(a.pairs, b.pairs), f"{scene} {method} threads={threads} frame {k}: pairs differ"
            assert counters(a.stats) == counters(b.stats), f"{scene} {method} threads={threads} frame {k}: stats"


@pytest.mark.parametrize("method", ["aabb+front", "nc+front"])
def test_front_identical_for_any_thread_count(method):
    """The parallel traversal builds the front methods' BVTT front too (per task, joined in task
    order): every Front_X, entry for entry, is the one-thread front's, and so is which nodes rest,
    after DCD and CCD queries."""
    F, frames = sequences()["folding_sheet"]
    mesh = conecull.Mesh(F)

    def fronts(threads):
        """Each query's front, and whether the query found a collision."""
        col = conecull.SelfCollider(mesh, method=method, threads=threads)
        out, collided = [], []
        for V in list(frames) + [frames[0], frames[-1]] * 3:  # then far poses in turn: fronts churn and rest
            collided.append(len(col.dcd(V).pairs) > 0)
            out.append(col.front_arrays("dcd"))
        res = col.ccd(frames[-2], frames[-1])
        collided.append(len(res.vf) + len(res.ee) > 0)
        return out + [col.front_arrays("ccd")], collided

    ref, collided = fronts(1)
    # A query with a collision keeps a front (its root is not culled); 6 of these 15 have one.
    assert sum(collided) >= 4 and all(len(f["entries"]) > 0 for f, c in zip(ref, collided) if c)
    assert any(f["resting"].any() for f in ref)
    for threads in THREADS[1:]:
        for k, (a, b) in enumerate(zip(ref, fronts(threads)[0])):
            for key in ("count", "owner", "entries", "resting"):
                assert np.array_equal(a[key], b[key]), f"{method} threads={threads} query {k}: front {key} differs"


CASES = meshcases.all_cases()


def perturbed(V, seed):
    """A smooth-ish deterministic motion for a CCD step from a mesh case's pose."""
    rng = np.random.default_rng(seed)
    scale = float(np.ptp(V, axis=0).max()) if len(V) else 1.0
    return V + 0.02 * scale * np.sin(3.0 * V @ rng.standard_normal((3, 3)))


@pytest.mark.parametrize("name", [c[0] for c in CASES])
def test_mesh_cases_identical_for_any_thread_count(name):
    _, F, V = meshcases.case(name)
    mesh = conecull.Mesh(F, n_vertices=len(V))
    V1 = perturbed(V, 7)
    for method in conecull.METHODS:
        ref_d = conecull.SelfCollider(mesh, method=method, leaf_size=1, threads=1)
        ccd = method in conecull.CCD_METHODS
        ref = [ref_d.dcd(V), ref_d.dcd(V1), ref_d.ccd(V, V1) if ccd else None]
        for threads in THREADS[1:]:
            col = conecull.SelfCollider(mesh, method=method, leaf_size=1, threads=threads)
            got = [col.dcd(V), col.dcd(V1), col.ccd(V, V1) if ccd else None]
            for a, b in zip(ref[:2], got[:2]):
                assert np.array_equal(a.pairs, b.pairs) and counters(a.stats) == counters(b.stats), (name, method, threads)
            if not ccd:
                continue
            a, b = ref[2], got[2]
            assert np.array_equal(a.vf, b.vf) and np.array_equal(a.ee, b.ee)
            assert counters(a.stats) == counters(b.stats), (name, method, threads)


@pytest.mark.parametrize("name", ["fold_flat_exact_g10x10_at5", "crumple_medium_s2", "cylinder_twist_strong",
                                  "components_three_crossing", "offset_1e6_zfold_200"])
def test_dcd_equals_oracle_on_many_threads(name):
    _, F, V = meshcases.case(name)
    expect = frozenset(brute_force_pairs(F, V))
    mesh = conecull.Mesh(F, n_vertices=len(V))
    for method in conecull.METHODS:
        got = conecull.SelfCollider(mesh, method=method, leaf_size=1, threads=7).dcd(V)
        assert {tuple(p) for p in got.pairs.tolist()} == expect, (name, method)


def test_trace_is_the_same_with_threads():
    """A traced query runs on one thread: its events do not depend on the threads asked for."""
    F, frames = sequences()["folding_sheet"]
    mesh = conecull.Mesh(F)
    a = conecull.SelfCollider(mesh, method="nc", threads=1).dcd(frames[-1], trace=True)
    b = conecull.SelfCollider(mesh, method="nc", threads=3).dcd(frames[-1], trace=True)
    assert np.array_equal(a.pairs, b.pairs) and counters(a.stats) == counters(b.stats)
    for kind, key in (("elementary", "pair"), ("elementary", "result"), ("cone", "node"), ("contour", "node")):
        assert np.array_equal(getattr(a.trace, kind)[key], getattr(b.trace, kind)[key]), (kind, key)
    assert len(a.trace.elementary["pair"]) == a.stats["elementary_tests"] > 0


def test_threads_default_and_bad_values():
    F, V = grid_sheet(4, 4)
    mesh = conecull.Mesh(F)
    assert conecull.SelfCollider(mesh).threads >= 1
    assert conecull.SelfCollider(mesh).threads == (os.cpu_count() or 1) or os.cpu_count() is None
    assert conecull.SelfCollider(mesh, threads=3).threads == 3
    assert conecull.SelfCollider(mesh, threads=np.int64(2)).threads == 2
    col = conecull.SelfCollider(mesh)
    for bad in (0, -1, 1.5, "2", True, 10**6, [2]):
        with pytest.raises(ValueError, match="threads"):
            conecull.SelfCollider(mesh, threads=bad)
        with pytest.raises(ValueError, match="threads"):
            col.dcd(V, threads=bad)
        with pytest.raises(ValueError, match="threads"):
            col.ccd(V, V, threads=bad)
    with pytest.raises(ValueError, match="threads"):
        conecull._core.SelfCollider(mesh._topo, "nc", 2, -1)  # the core checks too


def test_compute_ceiling_runs_and_checks_its_arguments():
    """The loop `bench threads` times to show the machine's parallel ceiling: it runs on any thread
    count (its time is not tested), and bad counts name the argument."""
    ceiling = conecull._core.parallel.compute_ceiling
    for t in (1, 2, 3):
        assert ceiling(t, chunks=8, iterations=1000) > 0
    for kwargs, name in ((dict(threads=0), "threads"), (dict(threads=2000), "threads"),
                         (dict(threads=2, chunks=0), "chunks"), (dict(threads=2, chunks=2**21), "chunks"),
                         (dict(threads=2, iterations=0), "iterations"), (dict(threads=2, iterations=2 * 10**9), "iterations")):
        with pytest.raises(ValueError, match=name):
            ceiling(**kwargs)


def test_refit_identical_for_any_thread_count():
    """The parallel refit (subtrees below a cut in parallel, then the nodes above it) gives the
    same boxes and cones, bit for bit; the mesh is large enough for the parallel sweep."""
    F, frames = sequences()["folding_sheet"]
    mesh = conecull.Mesh(F)
    assert 2 * mesh.n_faces - 1 >= 4096  # BVH nodes with leaf_size 1: the parallel sweep's threshold
    ref = None
    for threads in THREADS:
        col = conecull.SelfCollider(mesh, method="nc", leaf_size=1, threads=threads)
        col.dcd(frames[0])
        col.dcd(frames[-1])
        dcd = (col.bvh_arrays()["box"], col.cone_arrays())
        col.ccd(frames[-2], frames[-1])
        ccd = (col.bvh_arrays()["box"], col.cone_arrays())
        got = [dcd[0], *dcd[1].values(), ccd[0], *ccd[1].values()]
        if ref is None:
            ref = got
        assert all(np.array_equal(a, b) for a, b in zip(ref, got)), threads


def test_queries_after_idle_gaps_and_from_two_threads():
    """A multi-threaded query wakes the pool's helpers before checking its input (prewake): a
    helper woken with no region to join spins, then sleeps again. After idle gaps long enough
    for the helpers to fall asleep (5 ms; they spin 0.2 ms), between queries that wake them
    with and without work to join (a traced query runs on one thread, a bad input raises after
    the wake-up), and with two Python threads querying at once, every answer is the one-thread
    answer. Run in a thread with a time limit, so that a lost wake-up fails instead of hanging."""
    import threading
    import time

    F, frames = sequences()["folding_sheet"]
    mesh = conecull.Mesh(F)
    # The one-thread answers, with the workers' history of queries: its BVH is built from
    # frames[-3], as theirs, and the contour tests' order (so contour_edges) follows the queries
    # before (FirstTest, contour_test_simple.hpp).
    one = conecull.SelfCollider(mesh, method="nc", threads=1)
    ref = []
    for _ in range(4):
        for V in frames[-3:]:
            ref.append(one.dcd(V))
            one.dcd(V, trace=True)
    errors = []

    def run(col):
        try:
            for k in range(4):
                for V, r in zip(frames[-3:], ref[3 * k:3 * k + 3]):
                    time.sleep(0.005)
                    got = col.dcd(V, threads=2)
                    assert np.array_equal(got.pairs, r.pairs) and counters(got.stats) == counters(r.stats)
                    col.dcd(V, trace=True, threads=2)
                    with pytest.raises(ValueError, match="V"):
                        col.dcd(V[:-1], threads=2)
        except BaseException as e:  # noqa: BLE001 - reported by the main thread
            errors.append(e)

    # daemon: a worker stuck in a query must not keep the test run from ending
    workers = [threading.Thread(target=run, args=(conecull.SelfCollider(mesh, method="nc", threads=2),), daemon=True)
               for _ in range(2)]
    for w in workers:
        w.start()
    for w in workers:
        w.join(timeout=120)
    assert not any(w.is_alive() for w in workers), "a query did not return within 120 s"
    assert not errors, errors[0]
    # ... and the helpers sleep again: over an idle half second the process uses next to no CPU
    # (a helper left spinning would use the whole half second)
    time.sleep(0.05)
    cpu = time.process_time()
    time.sleep(0.5)
    assert time.process_time() - cpu < 0.2, f"{time.process_time() - cpu:.3f} s of CPU while idle"


FORK_SCRIPT = r"""
import os, signal, sys, threading
import numpy as np
import conecull
sys.path.insert(0, sys.argv[1])
from thread_cases import sequences, counters
F, frames = sequences()["folding_sheet"]
mesh = conecull.Mesh(F)
ref = conecull.SelfCollider(mesh, method="nc", threads=1).dcd(frames[-1])
stop = False
def busy():  # another thread running multi-threaded queries while the main one forks
    col = conecull.SelfCollider(mesh, method="nc", threads=2)
    while not stop:
        col.dcd(frames[-1])
t = threading.Thread(target=busy, daemon=True)
t.start()
hung = wrong = 0
for _ in range(int(sys.argv[2])):
    pid = os.fork()
    if pid == 0:
        signal.alarm(20)
        got = conecull.SelfCollider(mesh, method="nc", threads=2).dcd(frames[-1])
        ok = np.array_equal(got.pairs, ref.pairs) and counters(got.stats) == counters(ref.stats)
        os._exit(0 if ok else 3)
    _, status = os.waitpid(pid, 0)
    hung += os.WIFSIGNALED(status)
    wrong += os.WIFEXITED(status) and os.WEXITSTATUS(status) != 0
stop = True
print(hung, wrong)
"""


def test_forked_children_query_with_threads():
    """A child forked while another thread runs multi-threaded queries has none of the pool's
    threads, and perhaps a pool mutex locked by one of them at the fork: it gets a fresh pool
    (pthread_atfork), so its own multi-threaded queries neither hang nor differ. In a separate
    interpreter, with a time limit. (The race is narrow: a C++ loop forking 300 times while
    regions ran hung 3-4 children before the fresh pool; from Python it is rarely hit, so this
    mostly shows that children still query correctly on several threads.)"""
    import subprocess
    import sys

    tests_dir = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    out = subprocess.run([sys.executable, "-c", FORK_SCRIPT, tests_dir, "40"], capture_output=True, text=True,
                         timeout=600)
    assert out.returncode == 0, out.stderr[-2000:]
    hung, wrong = map(int, out.stdout.split())
    assert (hung, wrong) == (0, 0), f"{hung} children hung, {wrong} answered wrongly"
