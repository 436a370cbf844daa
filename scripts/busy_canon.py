#!/usr/bin/env python3
"""Two threads against one on a machine with a core kept busy: `cshapes canon MESH --method coulomb` timed with
--threads 1 and --threads 2, interleaved (A, B, A, B, ...) while a busy loop (`yes > /dev/null`) runs beside
them, so that any other load on the machine weighs on both alike. Prints JSON: median seconds of each, the
median of the per-pair ratios threads2 / threads1 (the figure to judge: docs/benchmarks.md asks for <= 1.3), and the load
average before the run.

  scripts/busy_canon.py [--mesh M] [--repeats N] [--idle] [--env NAME=VALUE ...] [--cshapes build/cshapes]

--idle: no busy loop (the same comparison on whatever the machine is doing). --env: extra environment for the
timed runs, e.g. OMP_WAIT_POLICY=active (libgomp's long spin, as before), OMP_WAIT_POLICY=passive (sleep at
once), GOMP_SPINCOUNT=N, or CSHAPES_EXACT_THREADS=1 (keep 2 threads even when a core is busy).
"""
import argparse
import json
import os
import statistics
import subprocess
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--mesh", default=os.path.join(ROOT, "..", "shared", "data", "tosca5k", "cat0.off"))
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--idle", action="store_true", help="no busy loop")
    parser.add_argument("--env", action="append", default=[], help="NAME=VALUE for the timed runs")
    parser.add_argument("--cshapes", default=os.path.join(ROOT, "build", "cshapes"))
    args = parser.parse_args()
    if args.repeats < 1:
        parser.error("--repeats must be at least 1")
    env = dict(os.environ)
    for item in args.env:
        name, _, value = item.partition("=")
        env[name] = value

    load_before = os.getloadavg()[0]
    busy = None if args.idle else subprocess.Popen(["yes"], stdout=subprocess.DEVNULL)
    seconds = {1: [], 2: []}
    ratios = []
    try:
        with tempfile.TemporaryDirectory() as out:
            for _ in range(args.repeats):
                pair = {}
                for threads in (1, 2):
                    start = time.perf_counter()
                    subprocess.run([args.cshapes, "-q", "--threads", str(threads), "canon", args.mesh, "-o",
                                    os.path.join(out, "form.ply"), "--method", "coulomb"], env=env, check=True)
                    pair[threads] = time.perf_counter() - start
                    seconds[threads].append(pair[threads])
                ratios.append(pair[2] / pair[1])
    finally:
        if busy:
            busy.kill()
            busy.wait()
    print(json.dumps({
        "mesh": args.mesh,
        "busy_core": busy is not None,
        "env": args.env,
        "repeats": args.repeats,
        "load_average_before": load_before,
        "seconds_threads1": statistics.median(seconds[1]),
        "seconds_threads2": statistics.median(seconds[2]),
        "ratio_threads2_over_threads1": statistics.median(ratios),
        "ratios": ratios,
    }, indent=2))


if __name__ == "__main__":
    main()
