#!/usr/bin/env python3
"""Landmark MDS against the full methods on one mesh: for cmds and smacof, `cshapes canon` with --mds-solver full
and landmarks (each --mds-landmarks L), the wall time and peak memory (/usr/bin/time -v), and the landmark form's
distance to the full form (same vertices: RMS after the best rigid motion or reflection, in % of the full
form's bounding-box diagonal), as a Markdown table on stdout. Usage:

    /usr/bin/python3 scripts/landmark_vs_full.py MESH [--mds-landmarks 100,300,1000] [--methods cmds,smacof]
        [--geodesics heat] [--work DIR] [--cli build/cshapes] [--skip-full]

Forms already in --work are reused. --skip-full measures landmarks only (no distance column). Timings on a
shared machine are noisy.
"""
import argparse
import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np

root = Path(__file__).resolve().parents[1]
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("mesh")
parser.add_argument("--mds-landmarks", default="100,300,1000")
parser.add_argument("--methods", default="cmds,smacof")
parser.add_argument("--geodesics", default="heat")
parser.add_argument("--work", default=str(root / "build/landmark_vs_full"))
parser.add_argument("--cli", default=str(root / "build/cshapes"))
parser.add_argument("--skip-full", action="store_true")
args = parser.parse_args()
work = Path(args.work)
work.mkdir(parents=True, exist_ok=True)


def read_off(path):
    tokens = [t for line in open(path) for t in line.split("#")[0].split()]
    n = int(tokens[1])
    return np.array(tokens[4:4 + 3 * n], dtype=float).reshape(n, 3)


def form(method, solver, landmarks):
    stem = work / f"{Path(args.mesh).stem}_{method}_{solver}{landmarks or ''}"
    if not Path(f"{stem}.json").exists():
        command = ["/usr/bin/time", "-v", args.cli, "canon", args.mesh, "-o", f"{stem}.off", "--method", method,
                   "--geodesics", args.geodesics, "--mds-solver", solver, "--json"]
        command += ["--mds-landmarks", str(landmarks)] if landmarks else []
        with open(f"{stem}.time", "w") as err:
            done = subprocess.run(command, stdout=subprocess.PIPE, stderr=err, text=True)
        if done.returncode != 0:
            sys.exit(f"failed: {' '.join(command)}; see {stem}.time")
        text = open(f"{stem}.time").read()
        wall = re.search(r"Elapsed \(wall clock\) time.*: (\S+)", text).group(1)
        s = json.loads(done.stdout)
        s["_seconds"] = sum(float(x) * 60 ** k for k, x in enumerate(reversed(wall.split(":"))))
        s["_cpu"] = sum(float(re.search(rf"{kind} time \(seconds\): (\S+)", text).group(1))
                        for kind in ("User", "System"))
        s["_peak_mb"] = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", text).group(1)) / 1024
        Path(f"{stem}.json").write_text(json.dumps(s))
    return read_off(f"{stem}.off"), json.loads(Path(f"{stem}.json").read_text())


def aligned_rms(A, B):
    a, b = A - A.mean(0), B - B.mean(0)
    U, _, Vt = np.linalg.svd(a.T @ b)
    return np.sqrt(((a @ U @ Vt - b) ** 2).sum(1).mean())


print(f"{Path(args.mesh).name}, geodesics {args.geodesics}\n")
print("| method | solver | wall s | CPU s | peak MB | distance to full | form quality |")
print("| --- | --- | --- | --- | --- | --- | --- |")
for method in args.methods.split(","):
    full = None if args.skip_full else form(method, "full", 0)
    runs = ([("full", 0)] if full else []) + [("landmarks", int(L)) for L in args.mds_landmarks.split(",")]
    for solver, L in runs:
        X, s = form(method, solver, L)
        distance = "—" if full is None else \
            f"{100 * aligned_rms(X, full[0]) / np.linalg.norm(full[0].max(0) - full[0].min(0)):.2f}%"
        q = s.get("form_quality", {})
        print(f"| {method} | {solver}{' L=' + str(L) if L else ''} | {s['_seconds']:.1f} | {s['_cpu']:.1f} | {s['_peak_mb']:.0f} | "
              f"{distance} | {q.get('description', '?')} |")
