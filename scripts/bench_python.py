#!/usr/bin/env python3
"""Benchmark: `cshapes.coulomb` from Python against the CLI's `cshapes canon` on the same mesh and options,
interleaved in one run, as JSON on stdout.

Each repeat times, in turn: the CLI (`cshapes canon MESH -o OUT.ply --method coulomb`, the process's wall
time: start, read, canonize, write) and the module (`read_mesh`, `coulomb`, `write_mesh` in this process, the
interpreter already running). The ratio of the medians is what the module costs beyond the library: the
issue's goal is <= 1.05. Usage:

    PYTHONPATH=build/python /usr/bin/python3 scripts/bench_python.py [MESH] [--repeats 7] [--cli build/cshapes]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import cshapes

root = Path(__file__).resolve().parents[1]
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("mesh", nargs="?", default=str(root.parent / "shared/data/tosca5k/cat0.off"))
parser.add_argument("--repeats", type=int, default=7)
parser.add_argument("--cli", default=str(root / "build/cshapes"))
args = parser.parse_args()

with tempfile.TemporaryDirectory() as tmp:
    out_cli, out_py = Path(tmp) / "cli.ply", Path(tmp) / "py.ply"
    cli_times, py_times, cli_solve, py_solve = [], [], [], []
    for repeat in range(args.repeats + 1):  # the first round warms the caches and is not counted
        start = time.perf_counter()
        result = subprocess.run([args.cli, "--quiet", "canon", args.mesh, "-o", str(out_cli), "--method",
                                 "coulomb", "--json"], capture_output=True, text=True, check=True)
        cli_seconds = time.perf_counter() - start
        start = time.perf_counter()
        V, F = cshapes.read_mesh(args.mesh)
        form = cshapes.coulomb(V, F)
        cshapes.write_mesh(out_py, form.X, F, torn=form.torn)
        py_seconds = time.perf_counter() - start
        if repeat == 0:
            same = out_cli.read_bytes() == out_py.read_bytes()
            continue
        cli_times.append(cli_seconds)
        py_times.append(py_seconds)
        cli_solve.append(json.loads(result.stdout)["seconds"])
        py_solve.append(form.summary["seconds"])

report = {
    "benchmark": "python module vs CLI: coulomb canonical form",
    "mesh": args.mesh,
    "vertices": int(len(V)),
    "repeats": args.repeats,
    "threads": cshapes.get_num_threads(),
    "identical_output_files": same,
    "cli_wall_seconds_median": statistics.median(cli_times),
    "python_wall_seconds_median": statistics.median(py_times),
    "ratio_python_to_cli": statistics.median(py_times) / statistics.median(cli_times),
    "cli_coulomb_seconds_median": statistics.median(cli_solve),
    "python_coulomb_seconds_median": statistics.median(py_solve),
    "cli_wall_seconds": cli_times,
    "python_wall_seconds": py_times,
    "load_average": os.getloadavg(),
}
json.dump(report, sys.stdout, indent=2)
print()
