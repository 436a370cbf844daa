#!/usr/bin/env python3
"""Scans mesh collections the way a new user would: every mesh through `cshapes info --json` (its defects),
all-pairs heat-method geodesics (count of non-finite distances among the vertices kept by the repair) and,
with --canon, `cshapes canon` with each method (exit code, vertices written against the input's).

Usage: scripts/python.sh scripts/scan_data.py [--canon] [--cshapes build/cshapes] [--threads T] FOLDER...
Prints one Markdown table row per mesh and a closing line; exits 1 if any check failed.
"""
import argparse
import json
import os
import pathlib
import re
import subprocess
import sys
import tempfile
import time

import numpy as np


def run(cmd):
    start = time.monotonic()
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    return proc, time.monotonic() - start


def read_distance_matrix(path):
    raw = pathlib.Path(path).read_bytes()
    if raw[:8] != b"CSHDIST1":
        raise ValueError(f"{path}: not a CSHDIST1 file")
    n = int.from_bytes(raw[8:16], "little")
    return np.frombuffer(raw[16:], dtype="<f4").reshape(n, n)


def ply_vertex_count(path):
    with open(path, "rb") as f:
        for line in f:
            if line.startswith(b"element vertex"):
                return int(line.split()[2])
            if line.strip() == b"end_header":
                break
    raise ValueError(f"{path}: no vertex element in the PLY header")


def registered_methods(cshapes):
    """The canonical-form methods the binary registers, from `canon --help` ("--method TEXT:{a, b, c}")."""
    text = subprocess.run([cshapes, "canon", "--help"], capture_output=True, text=True, check=True).stdout
    m = re.search(r"--method TEXT:\{([^}]*)\}", text)
    if not m:
        raise SystemExit(f"scan_data: no method list in `{cshapes} canon --help`")
    return [x.strip() for x in m.group(1).split(",")]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folders", nargs="+")
    parser.add_argument("--cshapes", default="build/cshapes")
    parser.add_argument("--threads", type=int, default=0, help="--threads for cshapes (0: its default)")
    parser.add_argument("--canon", action="store_true", help="also canonize with every registered method")
    args = parser.parse_args()
    base = [args.cshapes, "-q"] + (["--threads", str(args.threads)] if args.threads > 0 else [])
    methods = registered_methods(args.cshapes) if args.canon else []

    header = "| mesh | vertices | defects | heat all-pairs: non-finite / dropped rows | s |"
    header += "".join(f" canon {m}: exit, vertices, s |" for m in methods)
    print(header)
    print("|" + " --- |" * (5 + len(methods)))
    failures = 0
    meshes = 0
    with tempfile.TemporaryDirectory() as tmp:
        for folder in args.folders:
            for path in sorted(pathlib.Path(folder).glob("*.off")) + sorted(pathlib.Path(folder).glob("*.ply")):
                meshes += 1
                name = f"{path.parent.name}/{path.stem}"
                proc, _ = run(base + ["info", str(path), "--json"])
                if proc.returncode != 0:
                    print(f"| {name} | – | info failed: {proc.stderr.strip()} | | |")
                    failures += 1
                    continue
                info = json.loads(proc.stdout)
                n = info["vertices"]
                defects = info["defects"]["summary"]
                dpath = os.path.join(tmp, "d.bin")
                proc, seconds = run(base + ["geodesics", str(path), "--method", "heat", "-o", dpath])
                if proc.returncode != 0:
                    geo = f"exit {proc.returncode}: {proc.stderr.strip().splitlines()[-1]}"
                    failures += 1
                else:
                    D = read_distance_matrix(dpath)
                    dropped = np.isnan(D).all(axis=1)
                    kept = D[~dropped][:, ~dropped]
                    bad = int((~np.isfinite(kept)).sum())
                    failures += bad > 0 or D.shape[0] != n
                    geo = f"{bad} / {int(dropped.sum())}" + ("" if D.shape[0] == n else f" ({D.shape[0]} rows!)")
                row = f"| {name} | {n} | {defects} | {geo} | {seconds:.1f} |"
                for method in methods:
                    out = os.path.join(tmp, f"{method}.ply")
                    proc, seconds = run(base + ["canon", str(path), "--method", method, "-o", out])
                    written = ply_vertex_count(out) if proc.returncode == 0 else 0
                    failures += proc.returncode != 0 or written != n
                    row += f" {proc.returncode}, {written}, {seconds:.1f} |"
                    if os.path.exists(out):
                        os.remove(out)
                print(row, flush=True)
    print(f"\n{meshes} meshes, {failures} failed checks")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
