#!/usr/bin/env python3
"""The resolution table of issue 24: one surface remeshed to several vertex counts, canonized by each method;
per form the time and peak memory of `cshapes canon` (/usr/bin/time -v), its form quality, and its distance to
the form of the smallest mesh at corresponding points, as a Markdown table on stdout.

Correspondence: every vertex of the smallest remesh is paired with the nearest vertex of the other remesh (all
remeshes lie on the same input surface, so the pair is within about half an edge); the distance is the RMS over
the pairs after the best rigid motion or reflection (Kabsch), in % of the smallest form's bounding-box
diagonal. --seed draws the subset of --pairs vertices used (all when --pairs is 0). Usage:

    /usr/bin/python3 scripts/resolution_table.py [--shape ../shared/data/tosca5k/michael0.off]
        [--sizes 3500,10000,25000,50000] [--methods coulomb,cmds:landmarks] [--work DIR] [--cli build/cshapes]
        [--extra "--coulomb-... args"] [--seed 1]

A method is NAME or NAME:SOLVER (cmds:landmarks runs `--method cmds --mds-solver landmarks`). Remeshes and
forms already in --work are reused (delete the folder to measure again). Timings on a shared machine are noisy.
"""
import argparse
import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

root = Path(__file__).resolve().parents[1]
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--shape", default=str(root.parent / "shared/data/tosca5k/michael0.off"))
parser.add_argument("--sizes", default="3500,10000,25000,50000")
parser.add_argument("--methods", default="coulomb,cmds:landmarks")
parser.add_argument("--work", default=str(root / "build/resolution_table"))
parser.add_argument("--cli", default=str(root / "build/cshapes"))
parser.add_argument("--extra", default="", help="more `cshapes canon` options for every run")
parser.add_argument("--tag", default="", help="name suffix of the forms (e.g. 'before'), so runs coexist")
parser.add_argument("--pairs", type=int, default=0)
parser.add_argument("--seed", type=int, default=1)
args = parser.parse_args()
work = Path(args.work)
work.mkdir(parents=True, exist_ok=True)
sizes = [int(s) for s in args.sizes.split(",")]


def read_off(path):
    tokens = [t for line in open(path) for t in line.split("#")[0].split()]
    assert tokens[0] == "OFF", path
    n, m = int(tokens[1]), int(tokens[2])
    V = np.array(tokens[4:4 + 3 * n], dtype=float).reshape(n, 3)
    return V


def run(command, log):
    with open(log, "w") as out:
        done = subprocess.run(["/usr/bin/time", "-v"] + command, stdout=subprocess.PIPE, stderr=out, text=True)
    if done.returncode != 0:
        sys.exit(f"failed ({done.returncode}): {' '.join(command)}; see {log}")
    text = open(log).read()
    wall = re.search(r"Elapsed \(wall clock\) time.*: (\S+)", text).group(1)
    seconds = sum(float(x) * 60 ** k for k, x in enumerate(reversed(wall.split(":"))))
    peak = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", text).group(1)) / 1024
    return done.stdout, seconds, peak, cpu_seconds(text)


def cpu_seconds(text):
    """User + system CPU seconds of a /usr/bin/time -v log: less sensitive to other processes than wall time."""
    return sum(float(re.search(rf"{kind} time \(seconds\): (\S+)", text).group(1)) for kind in ("User", "System"))


def remeshed(n):
    path = work / f"surface_{n}.off"
    if not path.exists():
        run([args.cli, "remesh", args.shape, "-o", str(path), "--vertices", str(n)], work / f"remesh_{n}.log")
    return path


def canonized(n, method):
    name, _, solver = method.partition(":")
    stem = work / f"form_{name}{'_' + solver if solver else ''}{'_' + args.tag if args.tag else ''}_{n}"
    if not Path(f"{stem}.json").exists():
        command = [args.cli, "canon", str(remeshed(n)), "-o", f"{stem}.off", "--method", name, "--json"]
        command += ["--mds-solver", solver] if solver else []
        command += args.extra.split()
        out, seconds, peak, cpu = run(command, f"{stem}.time")
        summary = json.loads(out)
        summary["_seconds"], summary["_peak_mb"], summary["_cpu"] = seconds, peak, cpu
        Path(f"{stem}.json").write_text(json.dumps(summary))
    summary = json.loads(Path(f"{stem}.json").read_text())
    summary.setdefault("_cpu", cpu_seconds(Path(f"{stem}.time").read_text()) if Path(f"{stem}.time").exists()
                       else float("nan"))
    return read_off(f"{stem}.off"), summary


def aligned_rms(A, B):
    """RMS of A moved onto B by the best rotation or reflection and translation."""
    a, b = A - A.mean(0), B - B.mean(0)
    U, _, Vt = np.linalg.svd(a.T @ b)
    return np.sqrt(((a @ U @ Vt - b) ** 2).sum(1).mean())


rng = np.random.default_rng(args.seed)
base_V = read_off(remeshed(sizes[0]))
subset = np.arange(len(base_V)) if args.pairs <= 0 else rng.choice(len(base_V), args.pairs, replace=False)
print(f"Shape {Path(args.shape).name} remeshed to {', '.join(map(str, sizes))} vertices; distance to the "
      f"{sizes[0]:,}-vertex form in % of its bounding-box diagonal ({len(subset):,} vertex pairs, seed {args.seed}).\n")
print("| method | vertices | wall s | CPU s | peak MB | form quality | mean stretch | distance to the "
      f"{sizes[0]:,} form |")
print("| --- | --- | --- | --- | --- | --- | --- | --- |")
for method in args.methods.split(","):
    base_X, _ = canonized(sizes[0], method)
    diagonal = np.linalg.norm(base_X.max(0) - base_X.min(0))
    for n in sizes:
        X, s = canonized(n, method)
        pairs = cKDTree(read_off(remeshed(n))).query(base_V[subset])[1]
        distance = 100 * aligned_rms(X[pairs], base_X[subset]) / diagonal
        q = s.get("form_quality", {})
        print(f"| {method} | {n:,} | {s['_seconds']:.1f} | {s['_cpu']:.1f} | {s['_peak_mb']:.0f} | "
              f"{'ok' if q.get('ok') else 'FAILS'} ({q.get('runaway_vertices', '?')} runaway, max stretch "
              f"{q.get('max_stretch', float('nan')):.2f}) | {q.get('mean_stretch', float('nan')):.2f} | "
              f"{distance:.2f}% |")
