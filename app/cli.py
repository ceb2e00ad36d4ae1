"""The `conecull` command line: demo, record, view, explain, check, scenes, bench."""

from __future__ import annotations

import argparse
import os
import sys
import warnings


def main(argv: list[str] | None = None) -> int:
    from conecull._api import DEFAULT_LEAF_SIZE, METHODS  # "sct" is DCD only: `record --ccd --method sct` is refused with a ValueError
    from conecull.datasets.inputs import DEFAULT_SCENE

    parser = argparse.ArgumentParser(prog="conecull", description="Reliable self-collision culling with unprojected normal cones")
    sub = parser.add_subparsers(dest="command", required=True)

    method_help = "culling method (default nc)"
    p = sub.add_parser("demo", help="record the demo scene (a sheet folding onto itself) to an .rrd and print per-frame stats")
    p.add_argument("--out", default="demo.rrd", help="recording to write (default demo.rrd)")
    p.add_argument("--method", choices=list(METHODS), default="nc", help=method_help)

    p = sub.add_parser("record", help="trace a mesh sequence and write a rerun recording (.rrd)")
    p.add_argument("input", nargs="?", default=None, help=INPUT_HELP + f" (default: the scene {DEFAULT_SCENE})")
    p.add_argument("--positions", help="an .npz (or .npy) of positions (T, n, 3) when INPUT is one mesh file")
    p.add_argument("--resolution", type=int, help="a scene's resolution (default: the scene's own; see `conecull scenes`)")
    p.add_argument("--out", default="run.rrd", help="recording to write (default run.rrd)")
    p.add_argument("--method", choices=list(METHODS), default="nc",
                   help="culling method (default nc; --ccd: any but sct)")
    p.add_argument("--frames", help="A:B (B exclusive) or K, frames counted from 0: the frames to record "
                                    "(default all)")
    p.add_argument("--depth", type=int, default=None,
                   help="BVH depth whose boxes are drawn (default 4, or the BVH's deepest if less)")
    p.add_argument("--ccd", action="store_true", help="continuous: frame k shows the step from frame k to k + 1")
    p.add_argument("--arithmetic", choices=["float", "conservative", "exact"], default="exact",
                   help="CCD arithmetic (default exact)")
    p.add_argument("--compare", help="comma-separated methods also run on every frame, untraced, their "
                                     "contour-test time and counters plotted under stats/compare (e.g. nc,sct,cbc)")

    p = sub.add_parser("view", help="the interactive viewer in the browser (viser)")
    p.add_argument("input", nargs="?", default=None, help=INPUT_HELP + f" (default: the scene {DEFAULT_SCENE})")
    p.add_argument("--positions", help="an .npz (or .npy) of positions (T, n, 3) when INPUT is one mesh file")
    p.add_argument("--resolution", type=int, help="a scene's resolution (default: the scene's own; see `conecull scenes`)")
    p.add_argument("--port", type=int, default=8080,
                   help="port in [0, 65535] (default 8080; if taken, viser moves to the next free one; 0: any free "
                        "one; the real one is printed)")
    p.add_argument("--host", default="127.0.0.1", help="address to bind (default 127.0.0.1; 0.0.0.0: all interfaces)")
    p.add_argument("--method", choices=list(METHODS), default="nc", help="culling method shown first; the viewer "
                   "switches between all (default nc)")
    p.add_argument("--ccd", action="store_true", help="start with CCD steps (frame k shows the step from frame k to "
                   "k + 1); the viewer switches between DCD and CCD")

    p = sub.add_parser("explain", help="why a BVH node was culled or not, or why a triangle or a pair of triangles "
                                       "collides or was never tested, at one frame (or, with --ccd, one step)")
    p.add_argument("input", help=INPUT_HELP)
    p.add_argument("--positions", help="an .npz (or .npy) of positions (T, n, 3) when INPUT is one mesh file")
    p.add_argument("--resolution", type=int, help="a scene's resolution (default: the scene's own; see `conecull scenes`)")
    p.add_argument("--frame", type=int, required=True, help="the frame to query, counted from 0 (required; with "
                                                           "--ccd, the step from this frame to the next)")
    what = p.add_mutually_exclusive_group(required=True)
    what.add_argument("--node", type=int, help="a BVH node id, 0 the root (`conecull record` logs node ids)")
    what.add_argument("--face", type=int, help="a triangle id: the collisions it takes part in and why the region "
                                               "holding each was not culled (`check` and `record` print ids)")
    what.add_argument("--cones", action="store_true",
                      help="the nodes whose normal cone failed, each with whether its normals really span a "
                           "hemisphere or only the merged cone bound is too wide (checked exactly)")
    what.add_argument("--pair", type=int, nargs=2, metavar=("I", "J"),
                      help="two triangle ids: do they collide, and the verdict of the smallest node holding both")
    p.add_argument("--method", choices=list(METHODS), default="nc", help=method_help)
    p.add_argument("--ccd", action="store_true", help="explain the CCD step from --frame to the next (default: DCD "
                                                      "at --frame)")
    p.add_argument("--arithmetic", choices=["float", "conservative", "exact"], default="exact",
                   help="CCD arithmetic (default exact)")
    p.add_argument("--since", type=int, default=None,
                   help="front methods: the first frame the recording queried (`record --frames A:`; default 0): "
                        "a front depends on every query before, so the frames (steps) from it to --frame are "
                        "replayed first")

    p = sub.add_parser("check", help="is each frame intersection-free (and, with --ccd, each step collision-free)? "
                                     "Prints the first collision found; exit status 1 if any, 0 if none")
    p.add_argument("input", nargs="?", default=None, help=INPUT_HELP + f" (default: the scene {DEFAULT_SCENE})")
    p.add_argument("--positions", help="an .npz (or .npy) of positions (T, n, 3) when INPUT is one mesh file")
    p.add_argument("--resolution", type=int, help="a scene's resolution (default: the scene's own; see `conecull scenes`)")
    p.add_argument("--frames", help="A:B (B exclusive) or K, frames counted from 0: the frames to check (default all)")
    p.add_argument("--method", choices=list(METHODS), default="nc", help="culling method (default nc; --ccd: any but sct)")
    p.add_argument("--ccd", action="store_true", help="also check each step from frame k to k + 1 within --frames")
    p.add_argument("--arithmetic", choices=["float", "conservative", "exact"], default="exact",
                   help="CCD arithmetic (default exact)")

    p = sub.add_parser("scenes", help="list the built-in scenes (name, triangles, frames, effects, paper benchmark)")
    p.add_argument("--generate", nargs="*", metavar="NAME",
                   help="generate (or read from the cache) these scenes at their defaults, all if none given, "
                        "and print the seconds each took")

    p = sub.add_parser("bench", help="benchmarks (tables on stdout, JSON in bench-results/)")
    p.add_argument("suite", nargs="?", default="all", choices=["all", "dcd", "trace", "ccd", "contour", "threads", "first-hit", "front"],
                   help="all (default): the paper's evaluation on our scenes and the shared steps, with report.md, "
                        "PNG plots and JSON; dcd: methods and leaf sizes; trace: tracing overhead; "
                        "ccd: what accuracy costs in time; contour: contour test time, ours vs the sct and cbc "
                        "baselines (Fig. 9); threads: 1 thread vs --threads; first-hit: stop_at_first against the "
                        "full DCD and CCD queries on the real steps and the generated fold; front: the front "
                        "size table alone (Fig. 11, DCD and CCD, counters only) on --scenes, and on each last frame the front no "
                        "normal-cone test could cull")
    p.add_argument("--scenes", help="all, front: comma-separated scenes (default the paper-sized ones: "
                                    "funnel,twisting,flowing,falling,flamenco,squishy)")
    p.add_argument("--resolution", type=int, help="all, front: the scenes' resolution (default each scene's own)")
    p.add_argument("--leaf-size", type=int, help="front: triangles per BVH leaf, as SelfCollider's leaf_size "
                                                 f"(default {DEFAULT_LEAF_SIZE}, the library's default)")
    p.add_argument("--sizes", help="all: comma-separated triangle counts for the scaling table "
                                   "(default 16000,64000,256000,1000000)")
    p.add_argument("--from-json", metavar="PAPER_JSON",
                   help="all: re-render the scene tables and plots of a finished run (its paper.json) into --out")
    p.add_argument("--ipctk-candidates", type=int, metavar="N",
                   help="all: run ipctk's narrow phase (one Python call per candidate) on at most N candidates "
                        "of a step (default 10000000); above, on a random sample of N, whose time is a lower bound "
                        "(0: not at all). It holds about 0.5 KB per candidate")
    p.add_argument("--skip", help="all: comma-separated sections to leave out: "
                                  "scenes,steps,ipctk,contour,ccd,scaling,threads; first-hit: steps (the shared "
                                  "real steps)")
    # --triangles, --frames and --out default to None here and are filled in by _check_bench_args,
    # which must see what was typed: an option the suite does not use is an error, not ignored.
    p.add_argument("--triangles", type=int,
                   help="triangles of the generated folding sheet the suites query (all: its step in the steps "
                        "table, and the contour, ccd and threads sections) (default 64000)")
    p.add_argument("--frames", type=int, help="frames per query sequence (all: the last N of each scene) (default 8)")
    p.add_argument("--repeats", type=int, help="timed runs per frame; medians are reported (default 5; all: 3)")
    p.add_argument("--out", help="folder for the JSON output (default bench-results)")
    p.add_argument("--threads", type=int, help="threads per query (dcd, ccd, first-hit, all, front: default 1; not "
                                               "for trace and contour, which measure one thread); "
                                               "the threads suite compares 1 thread with this many (default 2)")

    words = _glue_dash_values(list(sys.argv[1:] if argv is None else argv))
    args = parser.parse_args(words)
    args.argv = list(sys.argv[1:] if argv is None else argv)[1:]
    try:
        with warnings.catch_warnings():  # the library's warnings (a mesh file's polygons split) as one line each
            warnings.showwarning = lambda message, *_a, **_k: print(
                f"conecull {args.command}: warning: {_as_option(str(message))}", file=sys.stderr)
            return _run(args)
    except BrokenPipeError:  # the reader of our output left (`| head`): nothing to report
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())  # Python's own flush at exit would fail again
        return 1
    except (ValueError, OSError, MemoryError) as e:  # OSError: a file that cannot be read or written
        why = str(e) or ("out of memory" if isinstance(e, MemoryError) else type(e).__name__)  # a bare MemoryError
        print(f"conecull {args.command}: error: {_as_option(why)}", file=sys.stderr)
        return 2


# Options taking one value that may start with '-' by mistake (a negative count or frame).
VALUE_OPTIONS = {"--frames", "--frame", "--since", "--node", "--face", "--depth", "--resolution", "--sizes",
                 "--threads", "--repeats", "--triangles", "--leaf-size", "--ipctk-candidates", "--port"}


def _glue_dash_values(words: list) -> list:
    """`--frames -3:` as `--frames=-3:`: argparse takes a value starting with '-' for an option and
    says only "expected one argument"; glued, the value reaches our own check, which names what is
    wrong with it (frames are counted from 0, not from the end; --sizes -5,10: each size >= 8)."""
    out = []
    for w in words:
        if out and out[-1] in VALUE_OPTIONS and w.startswith("-") and w[1:2] != "-" and len(w) > 1:
            out[-1] = f"{out[-1]}={w}"
        else:
            out.append(w)
    return out


INPUT_HELP = ("a scene name (see `conecull scenes`), a folder of OBJ/PLY frames with identical faces "
              "(in the order of the numbers in their names), or one mesh file (with --positions)")

# The library names its Python arguments (load_sequence's positions=, record's frame_range=, ...);
# the CLI passes its options' values to them, so it names the option the user typed.
OPTION_OF = {"positions": "--positions", "resolution": "--resolution", "method": "--method",
             "arithmetic": "--arithmetic", "frame_range": "--frames", "bvh_depth": "--depth", "skip": "--skip",
             "threads": "--threads", "ccd": "--ccd"}


def _as_option(message: str) -> str:
    head, sep, rest = message.partition(": ")
    return f"{OPTION_OF[head]}: {rest}" if sep and head in OPTION_OF else message


def _progress(done: int, total: int, unit: str = "frames") -> None:
    width = 30
    fill = width * done // total
    end = "\n" if done == total else ""
    print(f"\r[{'#' * fill}{'.' * (width - fill)}] {done}/{total} {unit}", end=end, file=sys.stderr, flush=True)


def _plural(n: int, word: str) -> str:
    return f"{n} {word}" if n == 1 else f"{n} {word}s"


def _check_out_file(out: str) -> None:
    """A recording is written at the end of a run: refuse a path it cannot be written to up front."""
    from conecull.datasets.checks import writable_file

    writable_file("--out", out)


def _explain_command(args, what: str, since: int = 0) -> str:
    """The `conecull explain` command line for the same input and method as `args`; since: the
    first frame queried after frame 0 (a front method's history: --since)."""
    import shlex

    from conecull.datasets.inputs import DEFAULT_SCENE

    words = ["conecull", "explain", (DEFAULT_SCENE if args.input is None else args.input)]
    if args.positions:
        words += ["--positions", args.positions]
    if args.resolution is not None:
        words += ["--resolution", str(args.resolution)]
    if args.method != "nc":
        words += ["--method", args.method]
    if args.method.endswith("+front") and since > 0:
        words += ["--since", str(since)]
    return " ".join(shlex.quote(w) for w in words) + " " + what


def _source_words(args) -> str:
    """The input as the command line named it, for a recording's /about page."""
    from conecull.datasets.inputs import DEFAULT_SCENE

    words = [f"{DEFAULT_SCENE} (the default scene)" if args.input is None else args.input]
    if args.positions:
        words.append(f"with positions {args.positions}")
    if args.resolution is not None:
        words.append(f"at resolution {args.resolution}")
    return "`" + words[0] + "`" + "".join(" " + w for w in words[1:])


def _front_history(ccd: bool, since: int, k: int) -> str:
    """Where `explain`'s front came from, after replaying `record --frames since:` up to query k."""
    if k > since:
        return (f"its front from replaying the queries of `record --frames {since}:` before this one: frame 0, "
                f"then {'steps' if ccd else 'frames'} {since}..{k - 1}")
    if ccd:
        return f"its front built from the top: no earlier CCD query, as `record --frames {k}: --ccd` has it"
    return f"its front from the query of frame 0, as `record --frames {k}:` has it"


def _check(args) -> int:
    """`conecull check`: the first-hit queries (stop_at_first) per frame and, with --ccd, per step."""
    import conecull
    from conecull.app.demo import contact_face
    from conecull.viz.explain import time_bound
    from conecull.datasets.inputs import DEFAULT_SCENE, load_sequence, parse_frames

    if args.ccd and args.method not in conecull.CCD_METHODS:
        raise ValueError(f"--method: {args.method!r} is a discrete (DCD) method; --ccd needs one of {conecull.CCD_METHODS}")
    if args.arithmetic != "exact" and not args.ccd:
        raise ValueError("--arithmetic: only with --ccd (a DCD query has no arithmetic mode)")
    F, frames = load_sequence((DEFAULT_SCENE if args.input is None else args.input), args.positions, args.resolution)
    if args.ccd and len(frames) < 2:
        raise ValueError("--ccd: the input has one frame, so no step from a frame to the next to check")
    rng = parse_frames(args.frames, len(frames))
    if args.ccd and len(rng) < 2:  # else "no collision in the frames and steps checked", with no step checked
        raise ValueError(f"--ccd: --frames {args.frames} selects one frame, and `check` checks the steps k -> k + 1 "
                         f"with both frames inside --frames (A:B with B >= A + 2; `record --ccd` counts a step from "
                         f"each frame of its range instead)")
    mesh = conecull.Mesh(F, n_vertices=frames.shape[1])
    col = conecull.SelfCollider(mesh, method=args.method)
    if rng[0] != 0:  # the BVH from frame 0, as `record` and `explain` build it: the same first pair found
        col.dcd(frames[0])
    bad = 0
    for k in rng:
        res = col.dcd(frames[k], stop_at_first=True)
        if len(res.pairs):
            bad += 1
            i, j = res.pairs[0]
            print(f"frame {k}: self-intersecting: triangles {i} and {j} intersect; why they were tested: "
                  + _explain_command(args, f"--frame {k} --pair {i} {j}", rng[0]))
        else:
            print(f"frame {k}: intersection-free")
        if args.ccd and k + 1 in rng:
            step = col.ccd(frames[k], frames[k + 1], arithmetic=args.arithmetic, stop_at_first=True, toi=True)
            if len(step.vf):
                v, f = step.vf[0]
                what = f"vertex {v} touches triangle {f}"
            elif len(step.ee):
                a, b = step.ee[0]
                what = f"edges {a} and {b} (ids of Mesh.edges) touch"
            else:
                print(f"step {k} -> {k + 1}: collision-free ({args.arithmetic})")
                continue
            bad += 1
            print(f"step {k} -> {k + 1}: contact ({args.arithmetic}): {what}, {time_bound(step.toi[0], 6)}; "
                  "why: " + _explain_command(args, f"--frame {k} --ccd --face {contact_face(mesh, step)}"
                                             + (f" --arithmetic {args.arithmetic}" if args.arithmetic != "exact" else ""),
                                             rng[0]))
    kinds = "frames and steps" if args.ccd else "frames"
    tris = _plural(len(F), "triangle")
    print(f"{tris}, method {args.method}: {bad} of the {kinds} checked collide{'s' if bad == 1 else ''}" if bad else
          f"{tris}, method {args.method}: no collision in the {kinds} checked")
    return 1 if bad else 0


# The options each bench suite reads (the suite itself aside); any other one typed is an error.
BENCH_OPTIONS = {
    "all": {"scenes", "resolution", "sizes", "from_json", "skip", "triangles", "frames", "repeats", "out", "threads",
            "ipctk_candidates"},
    "front": {"scenes", "resolution", "out", "threads", "leaf_size"},
    "dcd": {"triangles", "frames", "repeats", "out", "threads"},
    "ccd": {"triangles", "repeats", "out", "threads"},  # single steps: no frame count
    "threads": {"triangles", "frames", "repeats", "out", "threads"},
    "first-hit": {"triangles", "repeats", "out", "threads", "skip"},
    "trace": {"triangles", "frames", "repeats", "out"},    # a traced query runs on one thread
    "contour": {"triangles", "frames", "repeats", "out"},  # contour times are one thread's
}
MAX_BENCH_FRAMES = 10_000  # frames per query sequence: beyond this a typo, not a benchmark
MAX_BENCH_REPEATS = 1_000
MAX_IPCTK_CANDIDATES = 10**9  # the narrow phase's memory is checked per step, against its real count


def _check_bench_args(args) -> None:
    """The bench options, checked before minutes of work (each names its option); then the
    defaults of --triangles, --frames and --out."""
    from conecull.datasets.checks import count, fits_in_memory, writable_folder
    from conecull._api import MAX_LEAF_SIZE, MAX_THREADS
    from conecull.app.evaluation import TIMED_FRAMES

    typed = {name for name in ("scenes", "resolution", "sizes", "from_json", "skip", "triangles", "frames", "repeats",
                               "out", "threads", "ipctk_candidates", "leaf_size") if getattr(args, name) is not None}
    if args.suite == "all" and args.from_json is not None:
        allowed = {"from_json", "out"}  # a re-render times nothing
    else:
        allowed = BENCH_OPTIONS[args.suite]
    for name in sorted(typed - allowed):
        option = "--" + name.replace("_", "-")
        why = "only the output folder goes with --from-json" if args.suite == "all" else \
            f"the {args.suite} suite does not use it"
        if args.suite in ("trace", "contour") and name == "threads":
            why = f"the {args.suite} suite always measures one thread"
        raise ValueError(f"{option}: {why} (options of `bench {args.suite}`: "
                         f"{', '.join('--' + o.replace('_', '-') for o in sorted(allowed))})")
    for name, value, low, high in (("--threads", args.threads, 1, MAX_THREADS), ("--repeats", args.repeats, 1, MAX_BENCH_REPEATS),
                                   ("--ipctk-candidates", args.ipctk_candidates, 0, MAX_IPCTK_CANDIDATES),
                                   ("--frames", args.frames, 2, MAX_BENCH_FRAMES), ("--triangles", args.triangles, 8, None),
                                   ("--leaf-size", args.leaf_size, 1, MAX_LEAF_SIZE)):
        if value is not None:
            count(name, value, low, high)
    if args.from_json is not None and not args.from_json:
        raise ValueError("--from-json: expected the path of a paper.json, got ''")
    if args.suite == "all" and args.from_json is None:  # an option only skipped sections read: before --out exists
        from conecull.app.bench import check_skip
        from conecull.app.evaluation import check_sections

        check_sections(args, check_skip("all", args.skip))
    args.triangles = 64000 if args.triangles is None else args.triangles
    args.frames = TIMED_FRAMES if args.frames is None else args.frames
    args.out = "bench-results" if args.out is None else args.out
    # The generated sheet's frames are held at once (positions: 24 bytes per vertex, about half as
    # many vertices as triangles); a size beyond this machine is refused, not swapped through.
    # (`all`'s --frames counts the scenes' last frames; it builds no sheet of that many.)
    fits_in_memory("--triangles", 2 * 24.0 * (args.triangles / 2 + 1), f"a sheet of {args.triangles} triangles")
    if args.suite in ("dcd", "trace", "contour", "threads"):
        fits_in_memory("--frames", args.frames * 24.0 * (args.triangles / 2 + 1),
                       f"{args.frames} frames of a sheet of {args.triangles} triangles")
    if args.sizes is not None:
        from conecull.app.evaluation import parse_sizes

        parse_sizes(args.sizes)
    if args.scenes is not None:
        from conecull.app.evaluation import _scenes_of

        _scenes_of(args)
    if args.skip is not None:
        from conecull.app.bench import check_skip

        check_skip(args.suite, args.skip)
    # Last: a refused option leaves no folder behind. A re-render creates it once its paper.json
    # has been read and checked (render_from_json).
    writable_folder("--out", args.out, create=not args.from_json)


def _run(args) -> int:
    if args.command == "demo":
        from conecull.app.demo import run_demo

        _check_out_file(args.out)
        return run_demo(args.out, args.method)
    if args.command == "scenes":
        from conecull.datasets import describe, load, names

        if args.generate is None:
            print("\n".join(describe()))
            return 0
        import time

        for name in args.generate:  # all of them before generating any (minutes each)
            if name not in names():
                raise ValueError(f"NAME: unknown scene '{name}'; known: {', '.join(names())}")
        for name in args.generate or names():
            t = time.perf_counter()
            F, P = load(name)
            print(f"{name:9s} {len(F):8d} triangles {len(P):4d} frames  {time.perf_counter() - t:8.1f} s", flush=True)
        return 0
    if args.command == "record":
        from conecull.app.demo import rerun_command
        from conecull.datasets.inputs import DEFAULT_SCENE, load_sequence, parse_frames
        from conecull.viz.checks import check_compare, check_depth
        from conecull.viz.rerun_sink import record

        if args.depth is not None:
            check_depth(args.depth, "--depth")
        compare = None
        if args.compare is not None:
            compare = [m.strip() for m in args.compare.split(",")]
            check_compare(compare, args.ccd, "--compare")
        _check_out_file(args.out)
        F, frames = load_sequence((DEFAULT_SCENE if args.input is None else args.input), args.positions, args.resolution)
        rng = parse_frames(args.frames, len(frames))
        stats = record(args.out, F, frames, method=args.method, frame_range=rng, bvh_depth=args.depth,
                       progress=(lambda d, t: _progress(d, t, "steps" if args.ccd else "frames"))
                       if sys.stderr.isatty() or len(rng) > 1 else None, ccd=args.ccd,
                       arithmetic=args.arithmetic, compare=compare, source=_source_words(args))
        kind = f"{_plural(len(stats), 'CCD step')} ({args.arithmetic})" if args.ccd else _plural(len(stats), "frame")
        print(f"wrote {args.out}: {kind}, {_plural(len(F), 'triangle')}, method {args.method}; "
              f"open it with: {rerun_command(args.out)}")
        hit = next((k for k, s in zip(rng, stats) if s["colliding_pairs"]), None)
        if hit is not None:  # the triage question for the first collision recorded
            from conecull.app.demo import first_collision_args

            what = first_collision_args(F, frames, hit, args.method, args.ccd, args.arithmetic)
            print(f"first collision recorded at {'step' if args.ccd else 'frame'} {hit}; why it was not culled "
                  f"away: {_explain_command(args, what, rng[0])}")
        return 0
    if args.command == "view":
        import conecull
        from conecull.datasets.inputs import DEFAULT_SCENE, load_sequence
        from conecull.viz.checks import check_host_port
        from conecull.viz.viser_app import ViewerApp, serve_forever

        check_host_port(args.host, args.port, "--host", "--port")  # before loading: the server would hang on them
        if args.ccd and args.method not in conecull.CCD_METHODS:
            raise ValueError(f"--method: {args.method!r} is a discrete (DCD) method; --ccd needs one of "
                             f"{conecull.CCD_METHODS}")
        F, frames = load_sequence((DEFAULT_SCENE if args.input is None else args.input), args.positions, args.resolution)
        serve_forever(ViewerApp(F, frames, host=args.host, port=args.port, method=args.method, ccd=args.ccd))
        return 0
    if args.command == "explain":
        import conecull
        from conecull.datasets.inputs import load_sequence
        from conecull.viz.checks import check_method
        from conecull.viz.explain import explain_cones, explain_face, explain_node, explain_pair

        check_method(args.method, args.ccd, "--method")
        if args.arithmetic != "exact" and not args.ccd:
            raise ValueError("--arithmetic: only with --ccd (a DCD query has no arithmetic mode)")
        F, frames = load_sequence(args.input, args.positions, args.resolution)
        if args.ccd and len(frames) < 2:
            raise ValueError("--ccd: the input has one frame, so no step from a frame to the next to explain")
        last = len(frames) - 1 - bool(args.ccd)  # a step needs the next frame
        if not 0 <= args.frame <= last:
            raise ValueError(f"--frame: {args.frame} is out of range: the input has frames 0..{len(frames) - 1}"
                             + (f", so steps start at frames 0..{last}" if args.ccd else ""))
        col = conecull.SelfCollider(conecull.Mesh(F, n_vertices=frames.shape[1]), method=args.method)
        col.dcd(frames[0])  # the BVH (and so node ids) come from the first frame, as in `record`
        k = args.frame
        # A front method's front depends on every query before (Alg. 4: a front that churned rests
        # for several queries): replay the queries `record --frames A:` makes before frame k
        # (frame 0 to build the BVH, then A..k-1; CCD: the steps A..k-1), so the story is the
        # recording's.
        front = args.method.endswith("+front")
        since = 0 if args.since is None else args.since
        if args.since is not None and not front:
            raise ValueError(f"--since: only for a front method (aabb+front, nc+front): {args.method!r} keeps no "
                             "front, so no earlier query changes its answer")
        if not 0 <= since <= k:
            raise ValueError(f"--since: {since} is out of range: the recording's first frame, in 0..--frame ({k})")
        if front:
            for j in range(since, k):
                if args.ccd:
                    col.ccd(frames[j], frames[j + 1], arithmetic=args.arithmetic)
                else:
                    col.dcd(frames[j])
        if args.ccd:
            res = col.ccd(frames[k], frames[k + 1], arithmetic=args.arithmetic, trace=True, toi=True)
            head = f"step {k} -> {k + 1} ({args.arithmetic}), method {args.method}"
        else:
            res = col.dcd(frames[k], trace=True)
            head = f"frame {k}, method {args.method}"
        head += (f" ({_front_history(args.ccd, since, k)}):" if front else ":")
        if args.node is not None:
            text = explain_node(col, res, args.node, node_name="--node")
        elif args.face is not None:
            text = explain_face(col, res, args.face, name="--face")
        elif args.cones:
            text = explain_cones(col, res)
        else:
            text = explain_pair(col, res, *args.pair, names=("--pair", "--pair"))
        print(head + "\n" + text)
        return 0
    if args.command == "check":
        return _check(args)
    if args.command == "bench":
        _check_bench_args(args)
    if args.command == "bench" and args.suite == "front":
        from conecull.app.evaluation import run_front

        return run_front(args)
    if args.command == "bench" and args.suite == "all":
        from conecull.app.evaluation import render_from_json, run_all

        if args.from_json:
            return render_from_json(args.from_json, args.out)
        return run_all(args)
    if args.command == "bench":
        from conecull.app.bench import (run_ccd_bench, run_contour_bench, run_dcd_bench, run_first_hit_bench,
                                        run_threads_bench, run_trace_bench)

        run = {"dcd": run_dcd_bench, "trace": run_trace_bench, "ccd": run_ccd_bench, "contour": run_contour_bench,
               "threads": run_threads_bench, "first-hit": run_first_hit_bench}[args.suite]
        # trace and contour always measure one thread (a traced query runs on one)
        extra = {} if args.threads is None or args.suite in ("trace", "contour") else {"threads": args.threads}
        if args.suite == "first-hit" and args.skip:
            extra["skip"] = args.skip
        return run(args.triangles, args.frames, 5 if args.repeats is None else args.repeats, args.out, **extra)
    return 2


if __name__ == "__main__":
    sys.exit(main())
