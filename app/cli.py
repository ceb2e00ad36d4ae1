"""The `conecull` command line: demo, bench."""

from __future__ import annotations

import argparse
import sys


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="conecull", description="Reliable self-collision culling with unprojected normal cones")
    sub = parser.add_subparsers(dest="command", required=True)

    p = sub.add_parser("demo", help="run DCD on a generated scene (a sheet folding onto itself) and print per-frame stats")
    p.add_argument("--triangles", type=int, default=8000, help="approximate triangle count (default 8000)")
    p.add_argument("--frames", type=int, default=24, help="number of frames (default 24)")
    p.add_argument("--method", choices=["aabb", "nc"], default="nc")

    p = sub.add_parser("bench", help="benchmarks (tables on stdout, JSON in bench-results/)")
    p.add_argument("suite", choices=["dcd"], help="which benchmark")
    p.add_argument("--triangles", type=int, default=64000)
    p.add_argument("--frames", type=int, default=8)
    p.add_argument("--repeats", type=int, default=5, help="timed runs per frame; medians are reported")
    p.add_argument("--out", default="bench-results", help="folder for the JSON output")

    args = parser.parse_args(argv)
    if args.command == "demo":
        from conecull.app.demo import run_demo

        return run_demo(args.triangles, args.frames, args.method)
    if args.command == "bench":
        from conecull.app.bench import run_dcd_bench

        return run_dcd_bench(args.triangles, args.frames, args.repeats, args.out)
    return 2


if __name__ == "__main__":
    sys.exit(main())
