"""Bad input raises ValueError naming the argument and the problem; never a crash."""

import numpy as np
import pytest

import conecull
from conecull.datasets.generated import grid_sheet

F, V = grid_sheet(5, 5)


def col(method="nc"):
    return conecull.SelfCollider(conecull.Mesh(F), method=method)


@pytest.mark.parametrize(
    "faces,match",
    [
        (F.astype(np.float64), r"faces: expected an integer array"),
        (F.astype(bool), r"faces: expected an integer array"),
        (F[:, :2], r"faces: expected shape \(m, 3\)"),
        (F.ravel(), r"faces: expected shape \(m, 3\)"),
        (F[None], r"faces: expected shape \(m, 3\)"),
        (np.vstack([F, [[0, 1, -1]]]), r"faces: negative vertex index -1 in row 32"),
        (np.vstack([F, [[0, 1, 1]]]), r"faces: row 32 repeats a vertex"),
        (np.array([[0, 1, 2**40]]), r"faces: vertex index 1099511627776 is too large \(at most 2\^31 - 2 = 2147483646"),
        (np.array([[0, 1, 2**31 - 1]]), r"faces: vertex index 2147483647 is too large \(at most 2\^31 - 2 = 2147483646"),
        ([[0, 1, 2**70]], r"faces: vertex index 1180591620717411303424 is too large \(ids are in \[0, 2\^31 - 2\]\)"),
        ([[0, -(2**70), 1]], r"faces: vertex index -1180591620717411303424 is negative"),
        (np.array([["a", "b", "c"]]), r"faces: expected an integer array"),
        (np.zeros((0, 4), dtype=np.int64), r"faces: expected shape \(m, 3\)"),
        ([[0, 1, 2], [3, 4]], r"faces: not a rectangular array"),
        (np.ma.array(F, mask=np.eye(32, 3, dtype=bool)), r"faces: masked entries are not supported"),
    ],
)
def test_bad_faces(faces, match):
    with pytest.raises(ValueError, match=match):
        conecull.Mesh(faces)


def test_faces_as_an_object_array_of_small_ints():
    """An object array of Python ints that fit is a mesh like its int array (it was refused as a
    vertex index 'too large'); a mixed one (an int and a float) is still not integers."""
    mesh = conecull.Mesh(np.array(F.tolist(), dtype=object))
    assert np.array_equal(mesh.faces, F)
    with pytest.raises(ValueError, match=r"faces: vertex index -1 in row 0|faces: negative vertex index -1 in row 0"):
        conecull.Mesh(np.array([[0, 1, -1]], dtype=object))
    with pytest.raises(ValueError, match=r"faces: expected an integer array, got dtype object"):
        conecull.Mesh(np.array([[0, 1, 2.0]], dtype=object))


def test_face_index_out_of_range_with_n_vertices():
    with pytest.raises(ValueError, match=r"n_vertices: 10 is smaller than the largest face index \+ 1 \(25\)"):
        conecull.Mesh(F, n_vertices=10)
    with pytest.raises(ValueError, match=r"n_vertices: expected an integer"):
        conecull.Mesh(F, n_vertices=25.0)
    for n in (2**31, 2**63, np.uint64(2**64 - 1)):  # beyond the core's index type: named, not a TypeError
        with pytest.raises(ValueError, match=rf"n_vertices: {int(n)} is too large"):
            conecull.Mesh(F, n_vertices=n)


@pytest.mark.parametrize(
    "Vb,match",
    [
        (V.astype(np.int64), r"V: expected a float64 \(or float32\) array, got dtype int64"),
        (V[:, :2], r"V: expected shape \(n, 3\)"),
        (V.ravel(), r"V: expected shape \(n, 3\)"),
        (V[:-1], r"V: has 24 rows but the mesh has 25 vertices"),
        (np.vstack([V, V]), r"V: has 50 rows but the mesh has 25 vertices"),
        (np.where(np.arange(75).reshape(25, 3) == 7, np.nan, V), r"V: non-finite coordinate nan at row 2, column 1"),
        (np.where(np.arange(75).reshape(25, 3) == 4, np.inf, V), r"V: non-finite coordinate inf at row 1, column 1"),
        (np.where(np.arange(75).reshape(25, 3) == 5, 1e300, V), r"V: coordinate 1e\+300 at row 1, column 2 is outside"),
        (np.where(np.arange(75).reshape(25, 3) == 5, 1e-300, V), r"V: coordinate 1e-300 at row 1, column 2 is outside"),
        ([[0, 0, 0]], r"V: expected a float64"),
        ([[0.0, 0.0, 0.0]] * 24 + [[0.0, 1.0]], r"V: not a rectangular array"),
        # converting would round: 1 + 2^-60 becomes 1, a different pose with other exact signs
        (V.astype(np.longdouble) + np.longdouble(2.0) ** -60,
         r"V: some float128 coordinates are not exactly float64 \(rounding would move them\)"),
        (np.ma.array(V, mask=np.eye(25, 3, dtype=bool)), r"V: masked entries are not supported"),
    ],
)
def test_bad_positions(Vb, match):
    with pytest.raises(ValueError, match=match):
        col().dcd(Vb)


def test_trace_must_be_bool():
    with pytest.raises(ValueError, match=r"trace: expected True or False, got 'no'"):
        col().dcd(V, trace="no")


def test_bad_method_and_mesh():
    with pytest.raises(ValueError, match=r"method: expected one of \('aabb', 'nc', 'aabb\+front', 'nc\+front', 'sct', "
                       r"'cbc'\), got 'dc'"):
        conecull.SelfCollider(conecull.Mesh(F), method="dc")
    # "sct" is DCD only ([SPO10]); the core refuses it too
    sct = conecull.SelfCollider(conecull.Mesh(F), method="sct")
    with pytest.raises(ValueError, match=r"method: 'sct' is a discrete \(DCD\) method; CCD queries need one of"):
        sct.ccd(V, V)
    with pytest.raises(ValueError, match=r"method: 'sct' is a discrete \(DCD\) method \[SPO10\]"):
        sct._core.ccd(V, V, "exact", False, False)
    with pytest.raises(ValueError, match=r"method: expected one of .*, got 'nc\+fronts'"):
        conecull.SelfCollider(conecull.Mesh(F), method="nc+fronts")
    with pytest.raises(ValueError, match=r"mesh: expected a conecull.Mesh, got ndarray"):
        conecull.SelfCollider(F)
    with pytest.raises(ValueError, match=r"leaf_size: expected an integer in \[1, 64\]"):
        conecull.SelfCollider(conecull.Mesh(F), leaf_size=0)


def test_core_rejects_bad_shapes_too():
    """The private module validates on its own: no crash when called directly."""
    from conecull import _core

    topo = _core.build_topology(F.astype(np.int32), 25)
    c = _core.SelfCollider(topo, "nc", 1)
    with pytest.raises(ValueError, match=r"V: expected shape \(25, 3\)"):
        c.dcd(np.zeros((3, 3)))
    with pytest.raises(ValueError, match=r"faces: vertex index 99 in row 0 is out of range"):
        _core.build_topology(np.array([[0, 1, 99]], dtype=np.int32), 25)
    with pytest.raises(ValueError, match="method: unknown method"):
        _core.SelfCollider(topo, "xyz", 1)
    with pytest.raises(ValueError, match=r"method: unknown method 'front'; expected one of 'aabb', 'nc', 'aabb\+front'"):
        _core.SelfCollider(topo, "front", 1)


def test_exact_wider_types_accepted():
    """longdouble or int64 coordinates that float64 holds exactly are accepted, with the same answer
    (on a pose that has pairs)."""
    from conecull.datasets.generated import fold

    Fb, Vb = grid_sheet(12, 12)
    Vw = fold(Vb, 1.2 * np.pi, radius=0.02)
    mesh = conecull.Mesh(Fb)
    want = conecull.SelfCollider(mesh).dcd(Vw).pairs
    assert len(want) > 0
    assert np.array_equal(conecull.SelfCollider(mesh).dcd(Vw.astype(np.longdouble)).pairs, want)
    assert conecull.vertex_face_ccd(np.array([1, 0, 0], np.int64), [0, 0, 0], [1, 0, 0], [0, 1, 0],
                                    np.array([1, 0, 0], np.longdouble), [0, 0, 0], [1, 0, 0], [0, 1, 0])


@pytest.mark.filterwarnings("error")
@pytest.mark.parametrize("big", [np.array([2**64 - 1, 0, 0], np.uint64), np.array([2**63 - 1, 0, 0], np.int64)])
def test_integers_float64_cannot_hold_are_refused_without_a_warning(big):
    """2^64 - 1 rounds to 2^64, which the check's cast back to uint64 cannot hold: a RuntimeWarning
    came before the ValueError (found by review)."""
    z = np.zeros(3)
    with pytest.raises(ValueError, match=r"v_t0: some integer coordinates beyond 2\^53 are not exactly float64"):
        conecull.vertex_face_ccd(big, z, z, z, z, z, z, z)


def test_float32_accepted_and_same_result():
    """float32 positions are widened exactly: the same pairs as the same values in float64, on a
    pose that has some."""
    from conecull.datasets.generated import fold

    Fb, Vb = grid_sheet(12, 12)
    Vf = fold(Vb, 1.2 * np.pi, radius=0.02).astype(np.float32)
    mesh = conecull.Mesh(Fb)
    r32 = conecull.SelfCollider(mesh).dcd(Vf)
    r64 = conecull.SelfCollider(mesh).dcd(Vf.astype(np.float64))
    assert len(r64.pairs) > 0
    assert np.array_equal(r32.pairs, r64.pairs)


def test_float64_positions_read_in_place():
    """A float64 C-contiguous array goes to the core as it is (no per-query copy); any other
    layout or type is converted first, and a strided view still answers as its copy does."""
    from conecull._api import _as_positions

    Vc = np.ascontiguousarray(V, dtype=np.float64)
    assert _as_positions(Vc, len(Vc)) is Vc
    wide = np.zeros((len(V), 6))
    wide[:, ::2] = V
    view = wide[:, ::2]
    a = _as_positions(view, len(V))
    assert a.flags["C_CONTIGUOUS"] and not np.shares_memory(a, wide)
    assert np.array_equal(col().dcd(view).pairs, col().dcd(Vc).pairs)
    assert _as_positions(V.astype(np.float32), len(V)).dtype == np.float64


@pytest.mark.parametrize("method", conecull.METHODS)
def test_empty_mesh(method):
    for faces in (np.zeros((0, 3), dtype=np.int64), [], np.zeros((0, 3))):
        c = conecull.SelfCollider(conecull.Mesh(faces), method=method)
        res = c.dcd(np.zeros((0, 3)))
        assert res.pairs.shape == (0, 2) and res.pairs.dtype == np.int64
        assert res.stats["colliding_pairs"] == 0
    # isolated vertices only
    c = conecull.SelfCollider(conecull.Mesh(np.zeros((0, 3), dtype=int), n_vertices=4), method=method)
    assert c.dcd(np.zeros((4, 3))).pairs.shape == (0, 2)


def test_pairs_contract():
    Vb = V.copy()
    from conecull.datasets.generated import fold

    Fb, Vb = grid_sheet(12, 12)
    Vb = fold(Vb, 1.2 * np.pi, radius=0.02)
    res = conecull.SelfCollider(conecull.Mesh(Fb)).dcd(Vb)
    p = res.pairs
    assert p.dtype == np.int64 and p.ndim == 2 and p.shape[1] == 2 and len(p) > 0
    assert (p[:, 0] < p[:, 1]).all()
    assert np.array_equal(p, np.unique(p, axis=0))  # sorted lexicographically, no duplicates
    for key in ("bv_tests", "cone_tests", "contour_passed", "contour_failed", "elementary_tests", "colliding_pairs",
                "seconds_build", "seconds_refit", "seconds_traversal", "seconds_elementary"):
        assert key in res.stats


@pytest.mark.parametrize("kind", ["dcd", "ccd"])
def test_seconds_build_is_the_first_query_only(kind):
    """The query that builds the BVH and contours reports that time apart from its refit; later
    queries build nothing."""
    from conecull.datasets.generated import folding_sheet

    F, frames = folding_sheet(8000, 3)
    col = conecull.SelfCollider(conecull.Mesh(F), method="nc", threads=1)
    ask = (lambda k: col.dcd(frames[k])) if kind == "dcd" else (lambda k: col.ccd(frames[k], frames[k + 1]))
    first, second = ask(0), ask(1)
    assert first.stats["seconds_build"] > 0 and first.stats["seconds_refit"] > 0
    assert second.stats["seconds_build"] == 0 and second.stats["seconds_refit"] > 0


def test_queries_are_thread_safe():
    """Queries from several threads (same collider and separate ones) give identical results."""
    import threading

    from conecull.datasets.generated import folding_sheet

    Fb, frames = folding_sheet(3000, 6)
    mesh = conecull.Mesh(Fb)
    shared = conecull.SelfCollider(mesh)
    expected = [conecull.SelfCollider(mesh).dcd(V).pairs for V in frames]
    errors = []

    def work(col, k):
        try:
            for _ in range(3):
                for i, V in enumerate(frames):
                    if not np.array_equal(col.dcd(V).pairs, expected[i]):
                        errors.append((k, i))
        except Exception as e:  # pragma: no cover - reported below
            errors.append(e)

    threads = [threading.Thread(target=work, args=(shared if k % 2 else conecull.SelfCollider(mesh), k)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors


def _python_ran_during(call, rounds: int = 100) -> int:
    """How often the main thread ran Python while another thread was inside `call` (repeated up to
    `rounds` times, stopping once seen). The switch interval is set so long that the interpreter
    never takes the GIL from a thread: the main thread runs only if the worker releases it. So the
    answer does not depend on timing or load: 0 if `call` holds the GIL throughout, > 0 if it
    releases it (the main thread then gets it at once, or whenever the OS next schedules it)."""
    import sys
    import threading
    import time

    inside, done, stop = threading.Event(), threading.Event(), []

    def work():
        for _ in range(rounds):
            inside.set()
            call()
            inside.clear()
            if stop:
                break
        done.set()

    old = sys.getswitchinterval()
    sys.setswitchinterval(1000.0)
    seen = 0
    try:
        worker = threading.Thread(target=work)
        worker.start()
        while not done.is_set():
            if inside.is_set():
                seen += 1
                stop.append(True)
            time.sleep(0)  # lets the worker take the GIL when it wants it (between calls, or never)
        worker.join()
    finally:
        sys.setswitchinterval(old)
    return seen


def test_queries_release_the_gil():
    """While a query runs in one thread, Python keeps running in another: the main thread runs
    while the worker is inside the query, which it can only do if the query released the GIL (a
    timing version of this test, "the longest pause under half a query", failed on a loaded
    machine: 135 ms pauses during 191 ms queries). A call that holds the GIL (sorted() on a long
    list) gives 0: the test can fail."""
    from conecull.datasets.generated import folding_sheet

    F, frames = folding_sheet(64000, 2)
    c = conecull.SelfCollider(conecull.Mesh(F), method="aabb", threads=1)
    c.dcd(frames[1])
    assert _python_ran_during(lambda: c.dcd(frames[1])) > 0
    Fs, steps = folding_sheet(8000, 30)
    ccd = conecull.SelfCollider(conecull.Mesh(Fs), method="nc", threads=1)
    ccd.dcd(steps[0])
    assert _python_ran_during(lambda: ccd.ccd(steps[26], steps[27])) > 0
    big = list(range(1_000_000))[::-1]
    assert _python_ran_during(lambda: sorted(big), rounds=3) == 0


SNAPSHOT_RACE_SCRIPT = r"""
import sys, threading
import numpy as np
import conecull
from conecull.datasets.generated import folding_sheet
F, P = folding_sheet(20000, 2)
mesh = conecull.Mesh(F)
method, rounds = sys.argv[1], int(sys.argv[2])
ref = conecull.SelfCollider(mesh, method)
ref.dcd(P[1])
expected = ref.bvh_arrays()["order"]
calls = 0
for _ in range(rounds):
    col = conecull.SelfCollider(mesh, method)
    stop = []
    errors = []
    def snap():
        global calls
        try:
            while not stop:
                if method.endswith("+front"):
                    col.front_arrays(); col.front_load()
                else:
                    col.bvh_arrays(); col.cone_arrays(); col.contour_arrays(); col._core.built
                calls += 1
        except Exception as e:
            errors.append(e)
    t = threading.Thread(target=snap)
    t.start()
    col.dcd(P[1])
    stop.append(1)
    t.join()
    assert not errors, errors
    assert np.array_equal(col.bvh_arrays()["order"], expected)
assert calls >= rounds, calls  # the snapshots really ran alongside the queries
print("ok", calls)
"""


def test_snapshots_wait_for_a_running_query():
    """bvh_arrays, cone_arrays, contour_arrays, front_arrays and built, called from one thread
    while another thread's first query builds those structures (without the GIL), wait for it.
    Unlocked, bvh_arrays and contour_arrays read half-built vectors: the process died of heap
    corruption (malloc(): corrupted top size; SIGABRT or SIGSEGV) in 2 of 5 runs of 30 rounds and
    3 of 3 of 120 (about 4 s). A subprocess, so that a crash fails this test and not the run."""
    import subprocess
    import sys

    for method, rounds in (("nc", 120), ("nc+front", 30)):
        out = subprocess.run([sys.executable, "-c", SNAPSHOT_RACE_SCRIPT, method, str(rounds)], capture_output=True,
                             text=True, timeout=600)
        assert out.returncode == 0 and out.stdout.startswith("ok"), (method, out.returncode, out.stderr[-2000:])


def test_collider_attributes_are_read_only():
    """The core was made for one mesh, method and leaf size: rebinding them from Python would make
    the two sides disagree (front_arrays answering on an "nc" collider)."""
    c = col("nc")
    for name, value in (("mesh", conecull.Mesh(F)), ("method", "nc+front"), ("leaf_size", 4)):
        with pytest.raises(AttributeError):
            setattr(c, name, value)
    assert c.method == "nc" and c.leaf_size == 2 and c.mesh.n_faces == len(F)
    with pytest.raises(ValueError, match=r"method: 'nc' keeps no BVTT front; front_arrays needs"):
        c.front_arrays()
    with pytest.raises(ValueError, match=r"method: 'nc' keeps no BVTT front; front_load needs"):  # its own name
        c.front_load()


def test_mesh_too_large_for_memory_is_refused_before_building(monkeypatch):
    """A single triangle with vertex id 2^31 - 2 built a 16 GB topology in 42 s, and reading
    vertex_faces then had the process killed for lack of memory: refused up front, naming what
    asked for it. The bound is this machine's memory (patched here to 1 GiB, so that the test
    does not depend on the machine)."""
    from conecull import _api

    monkeypatch.setattr(_api, "memory_bytes", lambda: 2**30)
    with pytest.raises(ValueError, match=r"faces: 1 face whose largest vertex index, 99999999, means 100000000 "
                                         r"vertices would need about 3.73 GiB .* more than this machine's 1 GiB"):
        conecull.Mesh([[0, 1, 10**8 - 1]])
    with pytest.raises(ValueError, match=r"n_vertices: 100000000 vertices would need about 3.73 GiB"):
        conecull.Mesh([[0, 1, 2]], n_vertices=10**8)
    assert conecull.Mesh([[0, 1, 2]], n_vertices=10**6).n_vertices == 10**6  # 38 MiB: fits
    with pytest.raises(ValueError, match=r"faces: 1 face whose largest vertex index, 2147483646"):
        conecull.Mesh([[0, 1, 2**31 - 2]])


def run_script(script: str, *args, timeout: int = 600) -> tuple[list, float]:
    """A Ctrl-C script run in a fresh interpreter: the words it printed, and the latency bound
    (0.5 s; 10 s under ./dev.sh sanitize, where a test is ~15x slower)."""
    import os
    import subprocess
    import sys

    # A process started with SIGINT ignored (nohup, or `&` without job control) hands that on, and
    # Python then installs no KeyboardInterrupt handler: give the script Python's own, as a
    # terminal would (the query completed instead, and these tests failed, under `nohup ... &`).
    prelude = "import signal; signal.signal(signal.SIGINT, signal.default_int_handler)\n"
    out = subprocess.run([sys.executable, "-c", prelude + script, *map(str, args)], capture_output=True, text=True,
                         timeout=timeout)
    assert out.returncode == 0, out.stderr[-2000:]
    return out.stdout.split(), 10.0 if "libasan" in os.environ.get("LD_PRELOAD", "") else 0.5


INTERRUPT_SCRIPT = r"""
import os, signal, sys, threading, time, traceback
import numpy as np
import conecull
from conecull.datasets.generated import crumpling_sphere

F, P = crumpling_sphere(n_lat=5, n_lon=8, n_frames=2)
V0, V1 = P[0], -3 * P[0] + 0.1  # every vertex through nearly one point: ~6000 exact-engine tests, ~6 s
mode, threads = sys.argv[1], int(sys.argv[2])
mesh = conecull.Mesh(F)
col = conecull.SelfCollider(mesh, method="nc", threads=threads)
calls = []
if mode == "custom":
    signal.signal(signal.SIGINT, lambda *a: calls.append(1))
sent = []
threading.Timer(0.5, lambda: (sent.append(time.perf_counter()), os.kill(os.getpid(), signal.SIGINT))).start()
if mode == "worker":
    out, done = [], threading.Event()
    threading.Thread(target=lambda: (out.append(col.ccd(V0, V1)), done.set())).start()
    try:  # an Event, not Thread.join: a join that KeyboardInterrupt cuts short breaks the thread's later joins
        while not done.wait(0.05):
            pass
    except KeyboardInterrupt:
        calls.append(1)
    done.wait()
    print("worker", len(calls), len(out[0].vf) + len(out[0].ee))
    sys.exit(0)
try:
    res = col.ccd(V0, V1)
    print("completed", len(calls), len(res.vf) + len(res.ee))
except KeyboardInterrupt as e:
    latency = time.perf_counter() - sent[0]
    inside = traceback.extract_tb(e.__traceback__)[-1].filename.endswith("_api.py")
    W = V0 + 0.01  # the collider still answers, as a fresh one does
    a, b = col.ccd(V0, W), conecull.SelfCollider(mesh, method="nc").ccd(V0, W)
    same = np.array_equal(a.vf, b.vf) and np.array_equal(a.ee, b.ee)
    restored = signal.getsignal(signal.SIGINT) is signal.default_int_handler
    print("interrupted", inside, same, restored, latency)
"""


@pytest.mark.parametrize("threads", [1, 2])
def test_ctrl_c_interrupts_a_slow_ccd_query(threads):
    """SIGINT during a CCD query's elementary tests on the main thread raises KeyboardInterrupt
    from the query, well before it would end: 0.04-0.08 s after the signal (measured), against
    2.5-5.5 s more for the whole query (two threads, one), which is what Ctrl-C waited for
    before; asserted below 0.5 s (10 s under ./dev.sh sanitize, where a test is ~15x slower:
    1.0 s measured there, against ~50 s for the whole query). The collider then answers as a
    fresh one does, and Python's handler is back."""
    words, bound = run_script(INTERRUPT_SCRIPT, "default", threads, timeout=300)
    assert words[:4] == ["interrupted", "True", "True", "True"] and float(words[4]) < bound, words


TOI_INTERRUPT_SCRIPT = r"""
import os, signal, sys, threading, time
import numpy as np
import conecull
from conecull.datasets.generated import folding_sheet

# Every vertex starts at the origin: every pair is in contact at t = 0, float arithmetic finds
# the contacts in a fraction of a second, and their certified contact times take seconds.
F, P = folding_sheet(n_triangles=500, n_frames=4)
threads = int(sys.argv[1])
col = conecull.SelfCollider(conecull.Mesh(F), threads=threads)
V0, V1 = np.zeros_like(P[3]), P[3]
t = time.perf_counter()
fast = col.ccd(V0, V1, arithmetic="float")
without = time.perf_counter() - t
sent = []
# After the contacts (as long again as the query without contact times, and at least a second),
# so that the signal lands in the contact times (a sanitized build takes 1.7 s for the contacts).
delay = max(1.0, 2.0 * without)
threading.Timer(delay, lambda: (sent.append(time.perf_counter()), os.kill(os.getpid(), signal.SIGINT))).start()
try:
    res = col.ccd(V0, V1, arithmetic="float", toi=True)
    print("completed", without, delay)
except KeyboardInterrupt:
    print("interrupted", without, time.perf_counter() - sent[0], len(fast.vf) + len(fast.ee), delay)
"""


@pytest.mark.parametrize("threads", [1, 2])
def test_ctrl_c_interrupts_the_contact_times(threads):
    """toi=True: the certified contact times come after the query's tests, one search over the
    step per contact; SIGINT there stops them too (before, 69-75 s late on a 2000-triangle sheet
    whose vertices all start at one point: a bad-input probe). The signal comes once the
    contacts would have been found twice over (at least a second), so it lands in the contact
    times."""
    words, bound = run_script(TOI_INTERRUPT_SCRIPT, threads, timeout=300)
    assert words[0] == "interrupted" and int(words[3]) > 1000, words
    assert float(words[2]) < bound, words


FIRST_HIT_INTERRUPT_SCRIPT = r"""
import os, signal, sys, threading, time
import numpy as np
import conecull
from conecull.datasets.generated import fold, grid_sheet

# A flat sheet sliding in its own plane: no contact, so "is this step collision-free?" tests every
# candidate, and with "aabb" there are ~25M of them (every pair of faces within the slide; all
# coplanar, so none is culled by the non-penetration filter): seconds on one thread.
F, V0 = grid_sheet(72, 72)
V1 = V0 + np.array([0.3, 0.17, 0.0])
method, threads = sys.argv[1], int(sys.argv[2])
mesh = conecull.Mesh(F)
col = conecull.SelfCollider(mesh, method=method, threads=threads)
col.dcd(V0)  # build outside the timed part
sent = []
threading.Timer(0.5, lambda: (sent.append(time.perf_counter()), os.kill(os.getpid(), signal.SIGINT))).start()
try:
    res = col.ccd(V0, V1, stop_at_first=True)
    print("completed", len(res.vf) + len(res.ee))
except KeyboardInterrupt:
    latency = time.perf_counter() - sent[0]
    W = fold(V0, 1.05 * np.pi)  # the collider still answers, as a fresh one does (a step with contacts)
    a, b = col.ccd(V0, W), conecull.SelfCollider(mesh, method=method).ccd(V0, W)
    same = np.array_equal(a.vf, b.vf) and np.array_equal(a.ee, b.ee) and len(a.vf) + len(a.ee) > 0
    restored = signal.getsignal(signal.SIGINT) is signal.default_int_handler
    print("interrupted", same, restored, latency)
"""


@pytest.mark.parametrize("method", ["aabb", "aabb+front"])
@pytest.mark.parametrize("threads", [1, 2])
def test_ctrl_c_interrupts_a_first_hit_ccd_query(method, threads):
    """The same for ccd(stop_at_first=True) on a step without contact, which tests every
    candidate: "aabb" (tests inside the traversal's tasks) and "aabb+front" (a full traversal,
    then the candidates in chunks). Before, both ran whole: 3.4 s of tests on one thread on this
    step at 60 x 60 (measured), here 72 x 72."""
    words, bound = run_script(FIRST_HIT_INTERRUPT_SCRIPT, method, threads)
    assert words[:3] == ["interrupted", "True", "True"] and float(words[3]) < bound, words


DCD_INTERRUPT_SCRIPT = r"""
import os, signal, sys, threading, time
import numpy as np
import conecull
from conecull.datasets.generated import fold, grid_sheet

# A sheet crumpled into a unit cube (a bug-report mesh gone wrong: every vertex anywhere): ~14M
# intersecting pairs of ~10K triangles; seconds of traversal, tests and sorting on one thread.
F, flat = grid_sheet(72, 72)
crumpled = np.random.default_rng(0).random(flat.shape)
folded = fold(flat, 1.15 * np.pi)  # through itself: 353 pairs
method, threads, delay = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
mesh = conecull.Mesh(F)
col = conecull.SelfCollider(mesh, method=method, threads=threads)
col.dcd(folded)
col.dcd(folded)  # built, and a front method's front is kept
sent = []
threading.Timer(delay, lambda: (sent.append(time.perf_counter()), os.kill(os.getpid(), signal.SIGINT))).start()
try:
    res = col.dcd(crumpled)
    print("completed", len(res.pairs))
except KeyboardInterrupt:
    latency = time.perf_counter() - sent[0]
    # The collider still answers, as a fresh one does: after the flat pose (culled at the root
    # with cones: no node visited, so none of the nodes the interrupted query had reached), then
    # the folded one again.
    col.dcd(flat)
    a, b = col.dcd(folded), conecull.SelfCollider(mesh, method=method).dcd(folded)
    same = np.array_equal(a.pairs, b.pairs) and len(a.pairs) > 0
    restored = signal.getsignal(signal.SIGINT) is signal.default_int_handler
    print("interrupted", same, restored, latency)
"""


@pytest.mark.parametrize("method,threads,delay", [
    ("nc", 1, 0.1), ("nc+front", 1, 0.1), ("nc+front", 2, 0.1), ("aabb+front", 2, 0.1), ("sct", 1, 0.1),
    ("aabb", 1, 1.5), ("nc", 2, 1.2)])
def test_ctrl_c_interrupts_a_slow_dcd_query(method, threads, delay):
    """A DCD query on a mesh crumpled onto itself runs for seconds (the pairs grow with the
    square of the triangles): SIGINT stops it in its traversal (0.1 s in: a look every 64
    candidates emitted), its tests (1.2-1.5 s in: every 4096 tests) or its sort (slices of 2^20
    pairs), and it raises KeyboardInterrupt within 0.5 s. A front interrupted half rebuilt is
    forgotten, and the collider then answers as a fresh one: kept, "nc+front" on two threads gave
    1483 pairs instead of 353, or crashed (measured). Before, the whole query ran: 3.7-4.3 s on
    one thread (measured)."""
    words, bound = run_script(DCD_INTERRUPT_SCRIPT, method, threads, delay)
    assert words[:3] == ["interrupted", "True", "True"] and float(words[3]) < bound, words


LOCK_WAIT_SCRIPT = r"""
import os, signal, threading, time
import numpy as np
import conecull
from conecull.datasets.generated import grid_sheet

F, flat = grid_sheet(48, 48)
crumpled = np.random.default_rng(0).random(flat.shape)  # ~1 s of DCD on one thread
col = conecull.SelfCollider(conecull.Mesh(F), method="nc", threads=1)
col.dcd(flat)
ended = []
other = threading.Thread(target=lambda: (col.dcd(crumpled), ended.append(time.perf_counter())))
other.start()  # holds the collider's lock for its whole query; not interruptible (not the main thread)
time.sleep(0.05)
threading.Timer(0.2, lambda: os.kill(os.getpid(), signal.SIGINT)).start()  # while the main thread waits
try:
    col.dcd(crumpled)
    print("completed")
except KeyboardInterrupt:
    done = time.perf_counter()
    other.join()
    print("interrupted", done - ended[0])
"""


def test_ctrl_c_while_waiting_for_the_collider():
    """Ctrl-C while the main thread's query waits for the collider's lock (another thread's query
    holds it): the query stops as soon as it has the lock. Before, the signal was lost for it (our
    handler came with the lock): it ran whole, 0.76-0.82 s past the other (measured)."""
    words, bound = run_script(LOCK_WAIT_SCRIPT, timeout=300)
    assert words[0] == "interrupted" and float(words[1]) < 0.6 * bound, words


OUT_OF_MEMORY_SCRIPT = r"""
import resource
import numpy as np
import conecull
from conecull.datasets.generated import fold, grid_sheet

F, flat = grid_sheet(72, 72)
crumpled = np.random.default_rng(0).random(flat.shape)  # ~14M intersecting pairs: far beyond 60 MB more
folded = fold(flat, 1.15 * np.pi)
mesh = conecull.Mesh(F)
col = conecull.SelfCollider(mesh, method="nc+front", threads=2)
col.dcd(folded)
col.dcd(folded)  # the front kept
with open("/proc/self/statm") as f:
    used = int(f.read().split()[0]) * resource.getpagesize()
soft, hard = resource.getrlimit(resource.RLIMIT_AS)
resource.setrlimit(resource.RLIMIT_AS, (used + 60 * 2**20, hard))
try:
    col.dcd(crumpled)
    outcome = "completed"
except MemoryError:
    outcome = "MemoryError"
resource.setrlimit(resource.RLIMIT_AS, (soft, hard))
same = []
for pose in (flat, folded, fold(flat, 1.05 * np.pi), folded):  # flat first: culled at the root, no node visited
    a, b = col.dcd(pose), conecull.SelfCollider(mesh, method="nc+front", threads=1).dcd(pose)
    same.append(bool(np.array_equal(a.pairs, b.pairs)))
print(outcome, all(same))
"""


def test_a_query_out_of_memory_leaves_the_collider_whole():
    """Memory running out inside the traversal (the address space capped during a query of a
    crumpled sheet, "nc+front" on two threads) raises MemoryError, and the collider then answers
    as a fresh one: its front is forgotten as after Ctrl-C. Kept, it gave 1483 pairs instead of
    353, or a crash (a reviewer's measurement)."""
    import os

    if "libasan" in os.environ.get("LD_PRELOAD", ""):
        pytest.skip("AddressSanitizer reserves its shadow memory up front: an address-space cap breaks it")
    words, _ = run_script(OUT_OF_MEMORY_SCRIPT, timeout=300)
    assert words == ["MemoryError", "True"], words


@pytest.mark.parametrize("mode", ["custom", "worker"])
def test_ctrl_c_leaves_other_queries_whole(mode):
    """A program with a SIGINT handler of its own (custom), or a query on another thread than the
    main one (worker): the query runs to its end with its full answer, and the signal reaches
    Python as usual (the handler runs; the main thread gets KeyboardInterrupt)."""
    (what, n_calls, n_contacts), _ = run_script(INTERRUPT_SCRIPT, mode, 2, timeout=300)
    assert what == ("completed" if mode == "custom" else "worker") and n_calls == "1" and int(n_contacts) > 0


DAEMON_SCRIPT = r"""
import sys, threading, time
import numpy as np
import conecull
from conecull.datasets.generated import grid_sheet
F, V = grid_sheet(120, 120)
col = conecull.SelfCollider(conecull.Mesh(F), method="nc", threads=int(sys.argv[1]))
W = np.stack([V, V + 1e-3])
def busy():
    while True:
        col.dcd(V)
        col.ccd(W[0], W[1])
        conecull.Mesh(F)
        conecull.vertex_face_ccd(*([np.zeros(3)] * 8))
for _ in range(2):
    threading.Thread(target=busy, daemon=True).start()
time.sleep(0.3)
"""


@pytest.mark.parametrize("threads", [1, 2])
def test_interpreter_exits_while_daemon_threads_query(threads):
    """Python ends daemon threads at exit as they take the GIL back; one ending inside a query (its
    GIL release and retake) must end quietly. With py::gil_scoped_release, whose destructor takes
    the GIL back, the process aborted ("terminate called without an active exception", 5 of 5
    runs): the thread's exit unwinds, and unwinding out of a destructor terminates."""
    import subprocess
    import sys

    for _ in range(3):
        out = subprocess.run([sys.executable, "-c", DAEMON_SCRIPT, str(threads)], capture_output=True, text=True,
                             timeout=300)
        assert out.returncode == 0 and "terminate" not in out.stderr, (out.returncode, out.stderr[-2000:])


def test_mesh_and_results_pickle_a_collider_refuses():
    import copy
    import pickle

    m = conecull.Mesh(F, n_vertices=30)  # 5 isolated vertices beyond the faces' range are kept
    for m2 in (pickle.loads(pickle.dumps(m)), copy.deepcopy(m), copy.copy(m)):
        assert m2.n_vertices == 30 and np.array_equal(m2.faces, m.faces) and np.array_equal(m2.edges, m.edges)
    from conecull.datasets.generated import fold

    Fb, Vb = grid_sheet(12, 12)
    Vw = fold(Vb, 1.2 * np.pi, radius=0.02)  # folded through itself: DCD pairs and CCD contacts
    c = conecull.SelfCollider(conecull.Mesh(Fb))
    for res in (c.dcd(Vw, trace=True), c.ccd(Vb, Vw, toi=True)):  # results do pickle (from a worker), without their collider
        back = pickle.loads(pickle.dumps(res))
        assert res.collider() is c and back.collider() is None
        assert back.trace is None or back.trace.bvh == c.bvh_digest() is not None
        keys = [k for k in ("pairs", "vf", "ee", "toi") if hasattr(res, k)]
        assert sum(len(getattr(res, k)) for k in keys) > 0
        assert all(np.array_equal(getattr(back, k), getattr(res, k)) for k in keys)
    c = conecull.SelfCollider(m)
    for op in (pickle.dumps, copy.deepcopy, copy.copy):
        with pytest.raises(TypeError, match="SelfCollider cannot be pickled or copied: pickle its mesh"):
            op(c)


@pytest.mark.parametrize("bad,msg", [
    ([0.0, 1e300, 0.0], r"f1_t1: coordinate 1e\+300 \(component 1\) is outside the supported range.*rescale the input"),
    ([0.0, 0.0, 2.0**-130], r"f1_t1: coordinate .* \(component 2\) is outside the supported range"),
    ([0.0, 0.0, np.nan], r"f1_t1: non-finite coordinate nan \(component 2\)"),
    ([np.inf, 0.0, 0.0], r"f1_t1: non-finite coordinate inf \(component 0\)"),
])
def test_single_query_points_are_named_with_their_component(bad, msg):
    """One point is no mesh: the argument and the component are named, not a row of a mesh."""
    z = [0.0, 0.0, 0.0]
    with pytest.raises(ValueError, match=msg):
        conecull.vertex_face_ccd(z, z, z, z, z, z, bad, z)
    with pytest.raises(ValueError, match=msg.replace("f1_t1", "eb0_t1")):
        conecull.edge_edge_ccd(z, z, z, z, z, z, bad, z)


def test_the_packages_parts_load_on_first_use():
    """`import conecull` then `conecull.datasets.load(...)` works (it raised AttributeError), in a
    fresh interpreter where nothing else imported the part first; the core alone pulls in none of
    the viewers."""
    import subprocess
    import sys

    code = ("import sys, conecull; assert 'rerun' not in sys.modules and 'viser' not in sys.modules; "
            "F, P = conecull.datasets.load('fold'); assert F.shape == (2048, 3); "
            "assert conecull.trace.REASONS and conecull.viz.__name__ == 'conecull.viz'")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr


def test_a_mesh_is_not_rebuilt_in_place():
    """Mesh.__init__ again on a mesh a collider uses (a probe did) swapped the topology under it:
    front_load then raised an IndexError. Refused; a mesh never changes."""
    m = conecull.Mesh([[0, 1, 2], [3, 4, 5], [6, 7, 8]])
    col = conecull.SelfCollider(m, method="nc+front")
    col.dcd(np.random.default_rng(0).random((9, 3)))
    with pytest.raises(TypeError, match="Mesh: already built"):
        m.__init__([[0, 1, 2]])
    assert m.n_faces == 3 and len(col.front_load()) == 3
