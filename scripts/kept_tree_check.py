#!/usr/bin/env python3
"""Coulomb forms with the fast sum's tree kept for K iterations against a tree built at every iteration, on
generated meshes (JSON lines on stdout, a summary on stderr; exit 1 when a case fails). Usage:

    PYTHONPATH=build/python /usr/bin/python3 scripts/kept_tree_check.py [--seed 1] [--count 12] [--keep 10]
        [--min-vertices 3000] [--max-vertices 12000] [--cli build/cshapes]

Case i is stress case i of --seed (`cshapes stress --mesh-out`, sizes log-uniform in [min, max]; the fast sum
runs from 3,000 vertices) under variant i mod 4: as made, scaled by 1e12, scaled by 1e-12, or beside a
translated copy of itself (two components; Coulomb canonizes the largest). Each case is canonized three
times: K = 1 at the iterations' default accuracy (1e-2), K = --keep at 1e-2, and K = 1 at 3e-3. The
reference for the kept tree's effect is the accuracy's: `kept` is the RMS vertex distance between the K and
the K = 1 forms, `accuracy` the one between the 1e-2 and 3e-3 forms (both in % of the K = 1 form's
bounding-box diagonal; the three runs start from the same form). A case fails when a run throws or returns a
non-finite vertex. The summary gives medians and maxima of both distances, of their ratio, and of the
seconds ratio K / 1.
"""
import argparse
import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

import cshapes

root = Path(__file__).resolve().parents[1]
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--seed", type=int, default=1)
parser.add_argument("--count", type=int, default=12)
parser.add_argument("--keep", type=int, default=10)
parser.add_argument("--min-vertices", type=int, default=3000)
parser.add_argument("--max-vertices", type=int, default=12000)
parser.add_argument("--cli", default=str(root / "build/cshapes"))
args = parser.parse_args()

VARIANTS = ["as-made", "scaled-1e12", "scaled-1e-12", "two-components"]


def stress_mesh(index, folder):
    path = Path(folder) / f"case{index}.off"
    subprocess.run([args.cli, "-q", "stress", "--seed", str(args.seed), "--first", str(index), "--mesh-out",
                    str(path), "--min-vertices", str(args.min_vertices), "--max-vertices",
                    str(args.max_vertices)], check=True)
    return cshapes.read_mesh(str(path))


def variant(V, F, name):
    if name == "scaled-1e12":
        return V * 1e12, F
    if name == "scaled-1e-12":
        return V * 1e-12, F
    if name == "two-components":
        shift = 2 * (V.max(axis=0) - V.min(axis=0))[0]
        return np.vstack([V, V + [shift, 0, 0]]), np.vstack([F, F + len(V)])
    return V, F


def rms_percent(A, B, diagonal):
    return float(100 * np.sqrt(np.mean(np.sum((A - B) ** 2, axis=1))) / diagonal)


rows, failures = [], 0
with tempfile.TemporaryDirectory() as folder:
    for i in range(args.count):
        name = VARIANTS[i % len(VARIANTS)]
        row = {"case": i, "seed": args.seed, "variant": name}
        try:
            V, F = variant(*stress_mesh(i, folder), name)
            row["vertices"] = int(len(V))
            runs = {}
            for label, keep, accuracy in [("K1", 1, 1e-2), ("K", args.keep, 1e-2), ("acc", 1, 3e-3)]:
                form = cshapes.coulomb(V, F, coulomb_fmm_rebuild_every=keep, coulomb_accuracy=accuracy)
                X = form.X[np.asarray(form.valid, dtype=bool)]
                if not np.isfinite(X).all():
                    raise RuntimeError(f"{label}: a non-finite vertex")
                runs[label] = (X, form.seconds)
            X1 = runs["K1"][0]
            diagonal = float(np.linalg.norm(X1.max(axis=0) - X1.min(axis=0)))
            row["kept_percent"] = rms_percent(runs["K"][0], X1, diagonal)
            row["accuracy_percent"] = rms_percent(runs["acc"][0], X1, diagonal)
            row["seconds_K1"] = runs["K1"][1]
            row["seconds_K"] = runs["K"][1]
        except Exception as error:  # one bad case is reported, the run goes on
            row["error"] = str(error)
            failures += 1
        rows.append(row)
        print(json.dumps(row), flush=True)

done = [r for r in rows if "error" not in r]
if done:
    def line(label, values):
        return f"{label}: median {statistics.median(values):.4g}, max {max(values):.4g}"
    print(f"{len(done)} cases, {failures} failed (K = {args.keep}, seed {args.seed})", file=sys.stderr)
    print(line("kept tree vs K=1, % of diagonal", [r["kept_percent"] for r in done]), file=sys.stderr)
    print(line("accuracy 3e-3 vs 1e-2, % of diagonal", [r["accuracy_percent"] for r in done]), file=sys.stderr)
    print(line("ratio kept / accuracy", [r["kept_percent"] / max(r["accuracy_percent"], 1e-12) for r in done]),
          file=sys.stderr)
    wider = [r["case"] for r in done if r["kept_percent"] > r["accuracy_percent"]]
    print(f"cases where the kept tree moved the form more than the accuracy: {len(wider)} {wider}",
          file=sys.stderr)
    print(line("seconds K / K=1", [r["seconds_K"] / r["seconds_K1"] for r in done]), file=sys.stderr)
sys.exit(1 if failures else 0)
