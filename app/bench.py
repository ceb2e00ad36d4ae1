"""Benchmarks (not tests): print markdown tables and write JSON. One thread unless told
(--threads; the threads suite compares thread counts); medians of several timed runs per frame,
then the median over frames."""

from __future__ import annotations

import json
import os
import platform
import statistics
import time

import numpy as np

import conecull
from conecull.datasets.generated import fold, sheet_for_triangles

STAGES = ("seconds_refit", "seconds_traversal", "seconds_elementary")


def _folded_sheet_frames(n_triangles: int, n_frames: int):
    """The DCD benchmark scene: a sheet folding from 0.9 pi to 1.2 pi (flat onto itself and
    through), so every frame has both large culled regions and real self-intersections."""
    F, V = sheet_for_triangles(n_triangles)
    angles = np.linspace(0.9 * np.pi, 1.2 * np.pi, n_frames)
    # A small smooth ripple keeps the flat parts from being exactly coplanar (real cloth).
    V = V.copy()
    V[:, 2] = 0.002 * np.sin(9.0 * V[:, 0]) * np.sin(7.0 * V[:, 1])
    return F, [fold(V, a, radius=0.03) for a in angles]


def _answer(res):
    """A query's result arrays: DCD pairs, or CCD vf and ee (each sorted, so equal answers are
    equal arrays)."""
    return (res.vf, res.ee) if hasattr(res, "vf") else (res.pairs,)


def _same_answer(a, b) -> bool:
    return all(np.array_equal(x, y) for x, y in zip(_answer(a), _answer(b)))


def _disagree(suite: str, who: str, ref: str, where: str) -> RuntimeError:
    # Raised, not asserted: `python -O` strips asserts, and a benchmark of a wrong answer is worthless.
    return RuntimeError(f"bench {suite}: {who} disagrees with {ref} {where}; please report this as a bug")


def _size_label(n: int) -> str:
    """A triangle count for a label: '64K', '1.5K', or the count itself below 100 ('0K' said nothing)."""
    if n >= 10000:
        return f"{n // 1000}K"
    return f"{n / 1000:.1f}K" if n >= 100 else str(n)


def _cfg_name(cfg, threads) -> str:
    return f"{cfg[0]} (leaf {cfg[1]}, {cfg[2] if len(cfg) > 2 else threads} thread(s))"


def _time_methods(mesh, frames, configs, repeats, threads=1, suite="dcd"):
    """Per frame k >= 1 and per run, every (method, leaf size) answers an untimed query of frame
    k - 1, then a timed one of frame k: a front method starts from the front frame k - 1 left,
    as in a simulation (timing the same frame twice in a row would hand it a perfect front).
    The configurations take turns within each run, so load on a shared machine hits all alike.
    Every timed answer (each configuration, each run) is checked equal, pair for pair, to the
    first configuration's first run of that frame."""
    cols, build_s = {}, {}
    for cfg in configs:
        cols[cfg] = conecull.SelfCollider(mesh, method=cfg[0], leaf_size=cfg[1], threads=cfg[2] if len(cfg) > 2 else threads)
        t0 = time.perf_counter()
        cols[cfg].dcd(frames[0])  # builds the BVH and contours
        build_s[cfg] = time.perf_counter() - t0
    per_frame = {cfg: [] for cfg in configs}
    first = configs[0]
    for k, (prev, V) in enumerate(zip(frames[:-1], frames[1:]), start=1):
        runs = {cfg: [] for cfg in configs}
        for r in range(repeats):
            for cfg, col in cols.items():
                col.dcd(prev)
                t = time.perf_counter()
                res = col.dcd(V)
                runs[cfg].append((time.perf_counter() - t, res))
                if not _same_answer(res, runs[first][0][1]):
                    raise _disagree(suite, f"{_cfg_name(cfg, threads)} in run {r + 1}",
                                    f"{_cfg_name(first, threads)} in run 1", f"on the colliding pairs of frame {k}")
        for cfg, rs in runs.items():
            per_frame[cfg].append({
                "wall_ms": statistics.median(1e3 * w for w, _ in rs),
                **{s: statistics.median(1e3 * r.stats[s] for _, r in rs) for s in STAGES},
                "stats": {k: v for k, v in rs[0][1].stats.items() if not k.startswith("seconds")},
                "pairs": len(rs[0][1].pairs),
            })
    return build_s, per_frame


def run_dcd_bench(n_triangles: int = 64000, n_frames: int = 8, repeats: int = 5, out: str = "bench-results",
                  threads: int = 1) -> int:
    F, frames = _folded_sheet_frames(n_triangles, n_frames)
    mesh = conecull.Mesh(F)
    print(f"# DCD benchmark: folded sheet, {mesh.n_faces} triangles, {n_frames} frames ({n_frames - 1} timed), "
          f"{repeats} runs per frame (medians), {threads} thread(s), {platform.processor() or platform.machine()}")
    print()
    print("| method | leaf | build s | query ms | refit ms | traversal ms | elementary ms | box tests | cone tests | "
          "contour tests | culled | elementary tests | colliding pairs | front entries | front records | front KiB |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    configs = [(method, leaf) for method in conecull.METHODS for leaf in (1, 2, 4)]
    build, timed = _time_methods(mesh, frames, configs, repeats, threads)
    results = []
    for method, leaf in configs:  # their pairs were checked equal, frame by frame, by _time_methods
        pf = timed[method, leaf]
        med = lambda key: statistics.median(f[key] for f in pf)  # noqa: E731
        medstat = lambda key: statistics.median(f["stats"][key] for f in pf)  # noqa: E731
        pairs = [f["pairs"] for f in pf]
        row = {
            "method": method, "leaf_size": leaf, "build_s": build[method, leaf], "query_ms": med("wall_ms"),
            "refit_ms": med("seconds_refit"), "traversal_ms": med("seconds_traversal"),
            "elementary_ms": med("seconds_elementary"), "bv_tests": medstat("bv_tests"),
            "cone_tests": medstat("cone_tests"),
            "contour_tests": medstat("contour_tests"), "contour_passed": medstat("contour_passed"),
            "elementary_tests": medstat("elementary_tests"), "colliding_pairs": statistics.median(pairs),
            "front_entries": medstat("front_entries"), "front_segments": medstat("front_segments"),
            "front_bytes": medstat("front_bytes"), "per_frame": pf,
        }
        results.append(row)
        print(f"| {method} | {leaf} | {row['build_s']:.2f} | {row['query_ms']:.2f} | {row['refit_ms']:.2f} | "
              f"{row['traversal_ms']:.2f} | {row['elementary_ms']:.2f} | {row['bv_tests']:.0f} | "
              f"{row['cone_tests']:.0f} | {row['contour_tests']:.0f} | {row['contour_passed']:.0f} | "
              f"{row['elementary_tests']:.0f} | {row['colliding_pairs']:.0f} | {row['front_entries']:.0f} | "
              f"{row['front_segments']:.0f} | {row['front_bytes'] / 1024:.0f} |")
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, "dcd.json")
    with open(path, "w") as fh:
        json.dump({"scene": "folded sheet", "triangles": mesh.n_faces, "frames": n_frames, "repeats": repeats,
                   "results": results}, fh, indent=1)
    print()
    print(f"(medians over frames of the per-frame median of {repeats} runs; front entries and records: kept after "
          f"the query, a record per node the query reached Collide(L, R) at; front KiB: all the front keeps, "
          f"8 bytes per entry, 24 per record, 4 per BVH node; "
          f"every method's colliding pairs checked equal, frame by frame and run by run; JSON: {path})")
    return 0


def run_trace_bench(n_triangles: int = 64000, n_frames: int = 8, repeats: int = 7, out: str = "bench-results",
                    threads: int = 1) -> int:
    """Trace off vs trace on vs a build without any hook call site (conecull._core_nohooks),
    on the DCD scene with method nc. The three variants run interleaved, frame by frame, on one
    thread (a traced query always runs on one)."""
    from conecull import _core

    try:
        from conecull import _core_nohooks
    except ImportError:
        print("conecull._core_nohooks is not built: reinstall with "
              "`pip install --no-build-isolation -e . -Ccmake.define.CONECULL_NOHOOKS_MODULE=ON` "
              "(./dev.sh bench does this)")
        return 1
    F, frames = _folded_sheet_frames(n_triangles, n_frames)
    F32 = np.ascontiguousarray(F, dtype=np.int32)
    n = frames[0].shape[0]
    variants = {}
    for name, mod, trace in (("hook-free build", _core_nohooks, False), ("trace off", _core, False),
                             ("trace on", _core, True)):
        col = mod.SelfCollider(mod.build_topology(F32, n), "nc", 2, 1)
        col.dcd(frames[0], False)
        variants[name] = (col, trace)
    times = {name: [] for name in variants}
    for k, V in enumerate(frames):
        runs = {name: [] for name in variants}
        names = list(variants)
        ref = None
        for r in range(repeats):
            for name in names[r % 3:] + names[: r % 3]:  # rotate the order: no position bias
                col, trace = variants[name]
                t = time.perf_counter()
                pairs = col.dcd(V, trace)[0]  # the core's (pairs, stats, trace events)
                runs[name].append(1e3 * (time.perf_counter() - t))
                if ref is None:
                    ref = (name, pairs)
                elif not np.array_equal(pairs, ref[1]):
                    raise _disagree("trace", f"{name} in run {r + 1}", f"{ref[0]} in run 1",
                                    f"on the colliding pairs of frame {k}")
        for name in variants:
            times[name].append(statistics.median(runs[name]))
    med = {name: statistics.median(v) for name, v in times.items()}
    base = med["hook-free build"]
    print(f"# Tracing overhead: folded sheet, {len(F)} triangles, {n_frames} frames, method nc, leaf 2, "
          f"{repeats} interleaved runs per frame (medians), one thread")
    print()
    print("| variant | query ms | vs hook-free | vs trace off |")
    print("|---|---|---|---|")
    for name, ms in med.items():
        print(f"| {name} | {ms:.2f} | {ms / base:.3f}x | {ms / med['trace off']:.3f}x |")
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, "trace.json")
    with open(path, "w") as fh:
        json.dump({"triangles": len(F), "frames": n_frames, "repeats": repeats, "median_ms": med,
                   "per_frame_ms": times}, fh, indent=1)
    print()
    print(f"targets: trace off within 2% of the hook-free build ({med['trace off'] / base - 1:+.1%}), "
          f"trace on within 2x of trace off ({med['trace on'] / med['trace off']:.2f}x); JSON: {path}")
    return 0


def run_ccd_bench(n_triangles: int = 64000, n_frames: int = 0, repeats: int = 3, out: str = "bench-results",
                  threads: int = 1) -> int:
    """What accuracy costs in time: per arithmetic mode, on the shared real steps and a generated
    64K cloth step, ms per step, us per elementary test, FN and FP against ground truth; and the
    same for the single-query sets. Method nc, one thread (or `threads`), medians of `repeats` runs."""
    from conecull.datasets.shared import ccd_query_files, load_ccd_queries, shared_data_dir, shared_data_missing

    data = shared_data_dir()
    if data is None:
        print(f"{shared_data_missing()}: only the generated step is measured")

    steps = [(f"{name} ({_size_label(len(F))})", F, *rest) for name, F, *rest in shared_steps()]
    steps.extend(_generated_ccd_steps(n_triangles))

    print(f"# CCD: what accuracy costs in time (method nc, {threads} thread(s), median of {repeats} runs)")
    print()
    print("| step | mode | ms per step | elementary tests | us per test | FN | FP |")
    print("|---|---|---|---|---|---|---|")
    rows = []
    for name, F, V0, V1, vf_t, ee_t in steps:
        mesh = conecull.Mesh(F, n_vertices=len(V0))
        col = conecull.SelfCollider(mesh, method="nc", threads=threads)
        col.dcd(V0)  # build
        # the modes take turns within each repeat, so load on a shared machine hits them alike
        times, runs = {m: [] for m in ("float", "conservative", "exact")}, {}
        for r in range(repeats):
            for mode in times:
                t = time.perf_counter()
                res = col.ccd(V0, V1, arithmetic=mode)
                times[mode].append(time.perf_counter() - t)
                runs.setdefault(mode, []).append(res)
                if not _same_answer(res, runs[mode][0]):
                    raise _disagree("ccd", f"{mode} (run {r + 1})", f"{mode} (run 1)",
                                    f"on the VF / EE contacts of {name}")
        results = {m: (statistics.median(times[m]), runs[m][-1]) for m in times}
        generated = vf_t is None
        if generated:  # no ground truth: exact mode is the reference, so its own FN / FP say nothing
            ex = results["exact"][1]
            vf_t = {tuple(r) for r in ex.vf.tolist()}
            ee_t = {tuple(r) for r in ex.ee.tolist()}
        for mode, (secs, res) in results.items():
            vf = {tuple(r) for r in res.vf.tolist()}
            ee = {tuple(r) for r in res.ee.tolist()}
            fn = len(vf_t - vf) + len(ee_t - ee)
            fp = len(vf - vf_t) + len(ee - ee_t)
            if generated and mode == "exact":
                fn = fp = None
            tests = res.stats["elementary_tests"]
            # the median of the runs, as the header says (the counts are the same in every run)
            us = statistics.median(1e6 * x.stats["seconds_elementary"] / max(1, tests) for x in runs[mode])
            rows.append({"step": name, "mode": mode, "ms": 1e3 * secs, "elementary_tests": tests, "us_per_test": us,
                         "fn": fn, "fp": fp, "stats": {k: v for k, v in res.stats.items() if not isinstance(v, dict)}})
            fn_fp = "= ref | = ref" if fn is None else f"{fn} | {fp}"
            print(f"| {name} | {mode} | {1e3 * secs:.1f} | {tests} | {us:.2f} | {fn_fp} |")
        ratio = results["exact"][0] / results["float"][0]
        print(f"| {name} | exact / float | {ratio:.2f}x | | | | |")

    if data is not None:
        from conecull._core import ccd as C

        print()
        print("| single-query sets | mode | queries | ms total | us per query | FN | FP |")
        print("|---|---|---|---|---|---|---|")
        files = ccd_query_files(data)
        loaded = [load_ccd_queries(p) for p in files]
        for mode in ("float", "conservative", "exact"):
            total = fn = fp = 0
            secs = 0.0
            for kind, pts, truth in loaded:
                fnc = C.vertex_face_ccd_rows if kind == "vf" else C.edge_edge_ccd_rows
                cols = [np.ascontiguousarray(pts[:, i]) for i in range(8)]
                ts = []
                for _ in range(repeats):
                    t = time.perf_counter()
                    got = fnc(*cols, mode)
                    ts.append(time.perf_counter() - t)
                secs += statistics.median(ts)
                total += len(truth)
                fn += int((truth & ~got).sum())
                fp += int((~truth & got).sum())
            rows.append({"step": "ccd-queries", "mode": mode, "queries": total, "ms": 1e3 * secs, "fn": fn, "fp": fp})
            print(f"| ccd-queries (all sets) | {mode} | {total} | {1e3 * secs:.1f} | {1e6 * secs / total:.2f} | {fn} | {fp} |")
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, "ccd.json")
    with open(path, "w") as fh:
        json.dump({"repeats": repeats, "rows": rows}, fh, indent=1, default=float)
    print()
    print("(FN / FP: against the ground truth on the real steps; the generated steps have none, so there the "
          "reference is exact CCD itself: its own row says '= ref', the other modes are counted against it; "
          "us per test: seconds in the elementary tests / tests, median of the runs)")
    print(f"JSON: {path}")
    return 0


def run_contour_bench(n_triangles: int = 64000, n_frames: int = 8, repeats: int = 5, out: str = "bench-results") -> int:
    """Fig. 9: time inside the contour tests per query, ours vs the baselines (Sec. 6.1): nc vs
    sct (and cbc at one pose) on the DCD folded sheet of `bench dcd`; nc vs cbc on generated CCD
    steps of the same sheet folding on (as `bench ccd`, jittered). stats["seconds_contour"] is a
    steady clock around each contour test call. Per frame, the methods take turns within each
    run (load hits all alike); medians over runs, then over frames. One thread, leaf size 2."""
    F, frames = _folded_sheet_frames(n_triangles, n_frames)
    mesh = conecull.Mesh(F)
    rng = np.random.default_rng(0)
    J = 1e-5 * rng.standard_normal(frames[0].shape)  # as `bench ccd`: no exact symmetries
    suites = (("DCD", ("nc", "sct", "cbc"), [(V, None) for V in frames[1:]]),
              ("CCD", ("nc", "cbc"), [(A + J, B + J) for A, B in zip(frames[:-1], frames[1:])]))
    print(f"# Contour tests (Fig. 9): folded sheet, {mesh.n_faces} triangles, {n_frames - 1} queries per kind, "
          f"{repeats} runs each (medians), one thread, leaf 2")
    print()
    print("| query | method | contour tests | passed | edges visited | contour ms | us per test | traversal ms | "
          "query ms | contour ms vs nc |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    rows = []
    for kind, methods, queries in suites:
        cols = {m: conecull.SelfCollider(mesh, method=m, threads=1) for m in methods}
        for col in cols.values():
            col.dcd(frames[0])  # builds the BVH and contours
        per = {m: [] for m in methods}
        results = {}
        for k, q in enumerate(queries, start=1):
            runs = {m: [] for m in methods}
            for r in range(repeats):
                for m, col in cols.items():
                    t = time.perf_counter()
                    res = col.dcd(q[0]) if q[1] is None else col.ccd(q[0], q[1])
                    runs[m].append((time.perf_counter() - t, res))
                    if not _same_answer(res, runs[methods[0]][0][1]):
                        where = f"frame {k}" if kind == "DCD" else f"step {k - 1} -> {k}"
                        raise _disagree("contour", f"{m} in run {r + 1}", f"{methods[0]} in run 1",
                                        f"on the {kind} answer at {where}")
            for m, rs in runs.items():
                st = rs[0][1].stats
                per[m].append({
                    "contour_ms": statistics.median(1e3 * r.stats["seconds_contour"] for _, r in rs),
                    "traversal_ms": statistics.median(1e3 * r.stats["seconds_traversal"] for _, r in rs),
                    "query_ms": statistics.median(1e3 * w for w, _ in rs),
                    "contour_tests": st["contour_tests"], "contour_passed": st["contour_passed"],
                    "contour_edges": st["contour_edges"], "colliding_pairs": st["colliding_pairs"],
                })
        for m in methods:  # their answers were checked equal above, query by query
            med = {k: statistics.median(f[k] for f in per[m]) for k in per[m][0]}
            us = 1e3 * sum(f["contour_ms"] for f in per[m]) / max(1, sum(f["contour_tests"] for f in per[m]))
            results[m] = med
            ratio = med["contour_ms"] / results[methods[0]]["contour_ms"]
            rows.append({"query": kind, "method": m, "us_per_test": us, "contour_ms_vs_nc": ratio, **med, "per_frame": per[m]})
            print(f"| {kind} | {m} | {med['contour_tests']:.0f} | {med['contour_passed']:.0f} | {med['contour_edges']:.0f} | "
                  f"{med['contour_ms']:.3f} | {us:.2f} | {med['traversal_ms']:.2f} | {med['query_ms']:.2f} | {ratio:.2f}x |")
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, "contour.json")
    with open(path, "w") as fh:
        json.dump({"scene": "folded sheet", "triangles": mesh.n_faces, "frames": n_frames, "repeats": repeats,
                   "rows": rows}, fh, indent=1)
    print()
    print("(contour ms: per query, inside the contour tests, two steady-clock reads per test included; "
          "methods cull different nodes, so their test counts differ; paper targets: sct >= 3x nc, cbc >= 10x nc; "
          f"JSON: {path})")
    return 0


def shared_steps():
    """Every step of ../shared/data/scalable-ccd as (scene, F, V0, V1, vf truth, ee truth); [] without the data."""
    from conecull.datasets.shared import load_scalable_step, scalable_ccd_steps, shared_data_dir

    data = shared_data_dir()
    if data is None:
        return []
    return [(scene, *load_scalable_step(data, scene, step)) for scene, step in scalable_ccd_steps(data)]


def _generated_ccd_steps(n_triangles: int):
    """The generated CCD steps: the DCD scene's sheet folding from 1.10 pi to 1.13 pi."""
    F, V = sheet_for_triangles(n_triangles)
    V = V.copy()
    V[:, 2] = 0.002 * np.sin(9.0 * V[:, 0]) * np.sin(7.0 * V[:, 1])
    G0, G1 = fold(V, 1.10 * np.pi, radius=0.03), fold(V, 1.13 * np.pi, radius=0.03)
    # The same step with every vertex jittered by 1e-5: no exact symmetries, as in a simulation.
    rng = np.random.default_rng(0)
    J = 1e-5 * rng.standard_normal(V.shape)
    return [(f"generated fold ({_size_label(len(F))}, exact grid)", F, G0, G1, None, None),
            (f"generated fold ({_size_label(len(F))}, jittered)", F, G0 + J, G1 + J, None, None)]


def _compute_ceiling(threads: int, pairs: int = 5) -> float:
    """The machine's parallel ceiling now: the core's compute loop (no memory traffic) through its
    own thread pool, 1 thread against `threads`, taking turns; the median of `pairs` ratios. On a
    VM a vCPU can be taken away for seconds; a run where this is low says so."""
    from conecull import _core

    _core.parallel.compute_ceiling(threads)  # the pool's threads start on first use
    ratios = []
    for _ in range(pairs):
        one = _core.parallel.compute_ceiling(1)
        ratios.append(one / _core.parallel.compute_ceiling(threads))
    return statistics.median(ratios)


def run_threads_bench(n_triangles: int = 64000, n_frames: int = 8, repeats: int = 5, out: str = "bench-results",
                      threads: int = 2) -> int:
    """One thread against `threads` on the same queries: DCD on the `bench dcd` scene (per
    method, leaf 2, frames as there, fronts kept from frame to frame) and CCD on the jittered
    generated fold step (method nc, per arithmetic mode). The two thread counts take turns
    within each run; results are checked identical. Medians; the machine's other load shows."""
    counts = (1, threads)
    ceiling_before = _compute_ceiling(threads)
    F, frames = _folded_sheet_frames(n_triangles, n_frames)
    mesh = conecull.Mesh(F)
    cpu = platform.processor() or platform.machine()
    print(f"# Threads: 1 vs {threads} threads, {mesh.n_faces} triangles, {os.cpu_count()} cores, {cpu}")
    print()
    print("DCD: folded sheet, leaf 2, {} frames ({} timed), {} runs per frame (medians)".format(
        n_frames, n_frames - 1, repeats))
    print()
    print("| query | threads | query ms | refit ms | traversal ms | elementary ms | speed-up |")
    print("|---|---|---|---|---|---|---|")
    methods = ("aabb", "nc", "aabb+front", "nc+front")
    configs = [(m, 2, t) for m in methods for t in counts]
    _, timed = _time_methods(mesh, frames, configs, repeats, suite="threads")  # checks every answer's pairs
    rows = []
    for m in methods:
        base = None
        for t in counts:
            pf = timed[m, 2, t]
            for k, (f, f1) in enumerate(zip(pf, timed[m, 2, 1]), start=1):
                if f["stats"] != f1["stats"]:  # the counters too are the same for any thread count
                    raise _disagree("threads", f"{m} on {t} threads", "1 thread", f"on the counters of frame {k}")
            med = {k: statistics.median(f[k] for f in pf) for k in ("wall_ms", *STAGES)}
            base = base or med["wall_ms"]
            row = {"kind": "dcd", "query": m, "threads": t, "query_ms": med["wall_ms"], "refit_ms": med["seconds_refit"],
                   "traversal_ms": med["seconds_traversal"], "elementary_ms": med["seconds_elementary"],
                   "speedup": base / med["wall_ms"]}
            rows.append(row)
            print(f"| dcd {m} | {t} | {row['query_ms']:.2f} | {row['refit_ms']:.2f} | {row['traversal_ms']:.2f} | "
                  f"{row['elementary_ms']:.2f} | {row['speedup']:.2f}x |")
    print()
    name, F2, V0, V1, _, _ = _generated_ccd_steps(n_triangles)[1]
    print(f"CCD: {name}, method nc, {repeats} runs (medians)")
    print()
    print("| query | threads | query ms | refit ms | traversal ms | pairs ms | elementary ms | speed-up |")
    print("|---|---|---|---|---|---|---|---|")
    cols = {t: conecull.SelfCollider(conecull.Mesh(F2, n_vertices=len(V0)), method="nc", threads=t) for t in counts}
    for col in cols.values():
        col.dcd(V0)  # build
    for mode in ("float", "conservative", "exact"):
        runs = {t: [] for t in counts}
        for r in range(repeats):
            for t, col in cols.items():
                w = time.perf_counter()
                res = col.ccd(V0, V1, arithmetic=mode)
                runs[t].append((time.perf_counter() - w, res))
                if not _same_answer(res, runs[1][0][1]):
                    raise _disagree("threads", f"ccd {mode} on {t} threads (run {r + 1})", "1 thread (run 1)",
                                    f"on the VF / EE contacts of {name}")
        base = None
        for t in counts:
            res = runs[t][0][1]
            med = {k: statistics.median(r.stats[k] for _, r in runs[t]) for k in (*STAGES, "seconds_pairs")}
            wall = statistics.median(w for w, _ in runs[t])
            base = base or wall
            row = {"kind": "ccd", "query": f"ccd {mode}", "threads": t, "query_ms": 1e3 * wall,
                   "refit_ms": 1e3 * med["seconds_refit"], "traversal_ms": 1e3 * med["seconds_traversal"],
                   "pairs_ms": 1e3 * med["seconds_pairs"], "elementary_ms": 1e3 * med["seconds_elementary"],
                   "speedup": base / wall, "elementary_tests": res.stats["elementary_tests"]}
            rows.append(row)
            print(f"| ccd nc {mode} | {t} | {row['query_ms']:.1f} | {row['refit_ms']:.1f} | {row['traversal_ms']:.1f} | "
                  f"{row['pairs_ms']:.1f} | {row['elementary_ms']:.1f} | {row['speedup']:.2f}x |")
    ceiling = (ceiling_before, _compute_ceiling(threads))
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, "threads.json")
    with open(path, "w") as fh:
        json.dump({"triangles": mesh.n_faces, "frames": n_frames, "repeats": repeats, "threads": counts,
                   "cores": os.cpu_count(), "load_avg": os.getloadavg(), "compute_ceiling": ceiling, "rows": rows},
                  fh, indent=1)
    print()
    print(f"(speed-up: 1-thread query ms / this; load average {os.getloadavg()[0]:.2f} at the end; JSON: {path})")
    print(f"(the machine's ceiling, a compute loop through the same thread pool, {threads} threads against 1: "
          f"{ceiling[0]:.2f}x before the queries, {ceiling[1]:.2f}x after)")
    return 0


# The sections each suite can leave out with --skip.
SKIPPABLE = {"all": ("scenes", "steps", "ipctk", "contour", "ccd", "scaling", "threads"), "first-hit": ("steps",)}


def check_skip(suite: str, skip: str | None) -> set:
    """--skip's comma-separated sections for `suite`, each one it can leave out (None: none)."""
    sections = set(filter(None, (skip or "").split(",")))
    if skip is not None and not sections:  # `--skip ""` or `--skip ,`: a typo, not "skip nothing"
        raise ValueError(f"skip: expected comma-separated sections to leave out ({', '.join(SKIPPABLE[suite])}), "
                         f"got {skip!r}")
    unknown = sections - set(SKIPPABLE[suite])
    if unknown:
        raise ValueError(f"skip: {suite} can leave out {', '.join(repr(x) for x in SKIPPABLE[suite])}, "
                         f"got {sorted(unknown)}")
    return sections


def run_first_hit_bench(n_triangles: int = 64000, n_frames: int = 8, repeats: int = 5, out: str = "bench-results",
                        threads: int = 1, skip: str | None = None) -> int:
    """The one-bit questions of a simulator's line search, against the full queries that list
    every collision: "is the end pose intersection-free?" (dcd(V1, stop_at_first=True)) and "is
    the step collision-free?" (ccd(V0, V1, stop_at_first=True), exact), on the shared real steps
    and the jittered generated fold step, for nc and nc+front. Each collider first answers the full
    query once (a front method then starts from its own front); full and first-hit runs take
    turns; medians. Checked: the first hit is one of the full query's collisions, or there are none."""
    del n_frames  # single steps
    want_steps = "steps" not in check_skip("first-hit", skip)
    real = shared_steps() if want_steps else []
    if want_steps and not real:  # said, as `bench ccd` says it
        from conecull.datasets.shared import shared_data_missing

        print(f"{shared_data_missing()}: only the generated step is measured")
    steps = real + [_generated_ccd_steps(n_triangles)[1]]
    print(f"# First hit against the full query: {len(steps)} steps, {repeats} runs (medians), {threads} thread(s), "
          "CCD in exact arithmetic")
    print()
    print("| step | triangles | method | DCD full ms | DCD first-hit ms | DCD tests (full / first-hit) | "
          "CCD full ms | CCD first-hit ms | CCD pairs made (full / first-hit) | CCD tests (full / first-hit) | "
          "colliding |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    rows = []
    for name, F, V0, V1, _, _ in steps:
        mesh = conecull.Mesh(F, n_vertices=len(V0))
        for method in ("nc", "nc+front"):
            col = conecull.SelfCollider(mesh, method=method, threads=threads)
            col.dcd(V0)
            col.dcd(V1)
            col.ccd(V0, V1)
            t = {"dcd": [], "dcd1": [], "ccd": [], "ccd1": []}
            for _ in range(repeats):
                for key, run in (("dcd", lambda: col.dcd(V1)), ("dcd1", lambda: col.dcd(V1, stop_at_first=True)),
                                 ("ccd", lambda: col.ccd(V0, V1)), ("ccd1", lambda: col.ccd(V0, V1, stop_at_first=True))):
                    w = time.perf_counter()
                    res = run()
                    t[key].append((time.perf_counter() - w, res))
            d, d1, c, c1 = (t[k][0][1] for k in ("dcd", "dcd1", "ccd", "ccd1"))
            full_pairs = {tuple(p) for p in d.pairs.tolist()}
            full_hits = {("vf", tuple(p)) for p in c.vf.tolist()} | {("ee", tuple(p)) for p in c.ee.tolist()}
            for r in range(repeats):  # every run: the full answers as the first run's, each first hit among them
                if not _same_answer(t["dcd"][r][1], d):
                    raise _disagree("first-hit", f"{method}'s full DCD query (run {r + 1})", "run 1", f"on {name}")
                if not _same_answer(t["ccd"][r][1], c):
                    raise _disagree("first-hit", f"{method}'s full CCD query (run {r + 1})", "run 1", f"on {name}")
                p1 = t["dcd1"][r][1].pairs
                if not ((len(p1) == 1 and tuple(p1[0]) in full_pairs) or (len(p1) == 0 == len(full_pairs))):
                    raise _disagree("first-hit", f"{method}'s dcd(stop_at_first) (run {r + 1})", "the full DCD query",
                                    f"on {name}")
                h1 = t["ccd1"][r][1]
                hits = [("vf", tuple(p)) for p in h1.vf.tolist()] + [("ee", tuple(p)) for p in h1.ee.tolist()]
                if not ((len(hits) == 1 and hits[0] in full_hits) or (not hits and not full_hits)):
                    raise _disagree("first-hit", f"{method}'s ccd(stop_at_first) (run {r + 1})", "the full CCD query",
                                    f"on {name}")
            ms = {k: 1e3 * statistics.median(w for w, _ in v) for k, v in t.items()}
            pairs = lambda s: s["vf_candidates"] + s["ee_candidates"]  # noqa: E731
            tests = lambda s: s["vf_tests"] + s["ee_tests"]  # noqa: E731
            row = {"step": name, "triangles": len(F), "method": method, "dcd_ms": ms["dcd"], "dcd_first_hit_ms": ms["dcd1"],
                   "dcd_tests": d.stats["elementary_tests"], "dcd_first_hit_tests": d1.stats["elementary_tests"],
                   "ccd_ms": ms["ccd"], "ccd_first_hit_ms": ms["ccd1"], "ccd_pairs": pairs(c.stats),
                   "ccd_first_hit_pairs": pairs(c1.stats), "ccd_tests": tests(c.stats),
                   "ccd_first_hit_tests": tests(c1.stats), "dcd_colliding": len(full_pairs) > 0,
                   "ccd_colliding": len(full_hits) > 0}
            rows.append(row)
            yes = {(True, True): "both", (True, False): "pose", (False, True): "step", (False, False): "neither"}
            print(f"| {name} | {len(F)} | {method} | {ms['dcd']:.1f} | {ms['dcd1']:.1f} | {row['dcd_tests']} / "
                  f"{row['dcd_first_hit_tests']} | {ms['ccd']:.1f} | {ms['ccd1']:.1f} | {row['ccd_pairs']} / "
                  f"{row['ccd_first_hit_pairs']} | {row['ccd_tests']} / {row['ccd_first_hit_tests']} | "
                  f"{yes[row['dcd_colliding'], row['ccd_colliding']]} |", flush=True)
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, "first_hit.json")
    with open(path, "w") as fh:
        json.dump({"repeats": repeats, "threads": threads, "rows": rows}, fh, indent=1)
    print()
    print(f"(colliding: whether the end pose (DCD) and the step (CCD) have any collision; JSON: {path})")
    return 0
