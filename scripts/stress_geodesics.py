#!/usr/bin/env python3
"""Stress run of every geodesic method, canonical form and ICP on generated failure-prone meshes.

    scripts/stress_geodesics.py --count 1000 --seed 1 [--tosca ../shared/data/tosca5k] [--out DIR]

Runs `cshapes stress` (data/stress_corpus.h, experiments/geodesic_stress.h): case i of seed s is always the same
mesh, so any failure can be rebuilt from the two numbers. Prints, as markdown, the meshes per kind, per method
the failures and the error against the reference (exact geodesics up to --exact-max vertices, fast marching
above: median and worst of the per-mesh mean relative error, and how many meshes are beyond 50%: heat-direct,
which has no tolerance, is judged on finiteness only), the canonical forms' and ICP's failures, and the
run time; then the file of every failing mesh (saved under OUT/failures, ready to become a regression test).
Exits 1 when any mesh failed. Standard library only: runs with any python3.
"""
import argparse
import collections
import json
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def median(values):
    values = sorted(values)
    return values[len(values) // 2] if values else float("nan")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--count", type=int, default=100, help="meshes (default 100)")
    parser.add_argument("--seed", type=int, default=1, help="corpus seed (default 1)")
    parser.add_argument("--first", type=int, default=0, help="first case index (default 0)")
    parser.add_argument("--tosca", default="", help="folder of TOSCA .off shapes to use as bases too")
    parser.add_argument("--max-vertices", type=int, default=30000, help="largest base size (default 30000)")
    parser.add_argument("--min-vertices", type=int, default=200, help="smallest base size (default 200)")
    parser.add_argument("--out", default="stress-out", help="folder for results.jsonl and failures/")
    parser.add_argument("--binary", default=os.path.join(ROOT, "build", "cshapes"), help="the cshapes CLI")
    parser.add_argument("--extra", default="", help="more `cshapes stress` options, one string")
    parser.add_argument("--table-only", metavar="RESULTS", default="",
                        help="print the table of an earlier (or stopped) run's results.jsonl; run nothing")
    args = parser.parse_args()
    if args.table_only:
        with open(args.table_only) as f:
            rows = [json.loads(line) for line in f if line.strip()]
        return report(rows, args, float("nan"))
    if args.count < 1:
        parser.error("--count must be at least 1")
    if not os.access(args.binary, os.X_OK):
        sys.exit(f"stress_geodesics.py: {args.binary} not found; build first (scripts/build.sh)")
    os.makedirs(args.out, exist_ok=True)
    results_file = os.path.join(args.out, "results.jsonl")
    command = [args.binary, "stress", "--count", str(args.count), "--seed", str(args.seed), "--first",
               str(args.first), "--min-vertices", str(args.min_vertices), "--max-vertices",
               str(args.max_vertices), "--save-failures", os.path.join(args.out, "failures")]
    if args.tosca:
        command += ["--tosca", args.tosca]
    command += args.extra.split()
    start = time.time()
    # One JSON line per mesh as it finishes (kept when the run is stopped part-way).
    with open(results_file, "w") as results:
        status = subprocess.call(command, stdout=results)
    elapsed = time.time() - start
    if status != 0:
        sys.exit(f"stress_geodesics.py: `{' '.join(command)}` exited with {status}")
    with open(results_file) as f:
        rows = [json.loads(line) for line in f if line.strip()]
    return report(rows, args, elapsed)


def report(rows, args, elapsed):
    kinds = collections.Counter(r.get("kind", "?") for r in rows)
    indices = [r["index"] for r in rows if "index" in r]
    seconds = sum(r.get("seconds", 0) for r in rows)
    print(f"## Stress run: {len(rows)} meshes, cases {min(indices, default=0)}..{max(indices, default=0)}, "
          f"wall {elapsed:.0f} s, checks {seconds:.0f} s (one thread, mesh making not included)\n")
    print("| kind | meshes | vertices (min-max) |\n| --- | --- | --- |")
    for kind in sorted(kinds):
        sizes = [r["vertices"] for r in rows if r.get("kind") == kind and "vertices" in r]
        print(f"| {kind} | {kinds[kind]} | {min(sizes) if sizes else '-'}-{max(sizes) if sizes else '-'} |")

    print("\n| method | meshes | failures | refused | median error | worst error | error > 50% | worst max error "
          "| coarse (exempt) |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    methods = []
    for r in rows:
        for m in r.get("geodesics", {}):
            if m not in methods:
                methods.append(m)
    for m in methods:
        outcomes = [r["geodesics"][m] for r in rows if m in r.get("geodesics", {}) and r["geodesics"][m]["ran"]]
        errors = [o["mean_error"] for o in outcomes if "mean_error" in o]
        maxima = [o["max_error"] for o in outcomes if "max_error" in o]
        failures = sum(o["failed"] for o in outcomes)
        exempt = sum(o.get("exempt", False) for o in outcomes)
        refused = sum("refused" in o for o in outcomes)
        print(f"| {m} | {len(outcomes)} | {failures} | {refused} | {100 * median(errors):.2f}% | "
              f"{100 * max(errors, default=float('nan')):.2f}% | {sum(e > 0.5 for e in errors)} | "
              f"{100 * max(maxima, default=float('nan')):.1f}% | "
              f"{exempt} |")
    print("\n| canonical form / ICP | meshes run | failures | poor form quality |\n| --- | --- | --- | --- |")
    canon_methods = list(dict.fromkeys(m for r in rows for m in r.get("canon", {})))  # as the run names them
    for m in canon_methods:
        outcomes = [r["canon"][m] for r in rows if m in r.get("canon", {}) and r["canon"][m]["ran"]]
        print(f"| {m} | {len(outcomes)} | {sum(o['failed'] for o in outcomes)} | "
              f"{sum(o.get('verdict') == 'poor' for o in outcomes)} |")
    icp = [r["icp"] for r in rows if "icp" in r]
    print(f"| icp | {len(icp)} | {sum(o['failed'] for o in icp)} | - |")

    failing = [r for r in rows if r.get("failed")]
    print(f"\n{len(failing)} failing meshes")
    for r in failing:
        what = [f"{g}:{m}: {o.get('error', '')[:160]}" for g in ("geodesics", "canon")
                for m, o in r.get(g, {}).items() if o.get("failed")]
        if r.get("icp", {}).get("failed"):
            what.append("icp: " + r["icp"].get("error", ""))
        if "error" in r:
            what.append(r["error"])
        print(f"- {r.get('case')} ({r.get('vertices', '?')} vertices) {r.get('mesh_file', '')}")
        for w in what:
            print(f"    {w}")
    return 1 if failing else 0


if __name__ == "__main__":
    sys.exit(main())
