#!/usr/bin/env python3
"""The paper experiment's retrieval figures under every instruction set this CPU supports, side by side.

  scripts/simd_retrieval.py [--data DIR] [--out OUT] [--methods M,M] [--cshapes PATH]

Runs `cshapes experiment paper --data DIR --out OUT/TARGET --methods M --no-table1 --no-figure-data --no-draw
--correspondence-samples 0` (the retrieval stages only) once per target
(CSHAPES_SIMD=baseline|avx2|avx512, support/simd.h), each from an empty folder (no shared cache), then prints one
row per method and distance with mAP, NN, FT, ST, E and DCG per target, and whether they agree to 3 decimals.
Exits 1 when they do not. Defaults: DIR ../shared/data/tosca5k, OUT results/simd-retrieval, the six methods.
Standard library only.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MEASURES = ("map", "nn", "ft", "st", "e", "dcg")


def supported_targets(cshapes):
    env = dict(os.environ)
    env.pop("CSHAPES_SIMD", None)
    text = subprocess.run([cshapes, "--version"], capture_output=True, text=True, env=env, check=True).stdout
    line = next(l for l in text.splitlines() if l.startswith("kernels: "))
    inside = line[line.index("(") + 1:line.rindex(")")]
    return [t.strip() for t in inside.split(":")[-1].split(",")]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", default=os.path.join(ROOT, "..", "shared", "data", "tosca5k"))
    parser.add_argument("--out", default=os.path.join(ROOT, "results", "simd-retrieval"))
    parser.add_argument("--methods", default="coulomb,cmds,smacof,lbo,diffusion,spectral-mds")
    parser.add_argument("--cshapes", default=os.path.join(ROOT, "build", "cshapes"))
    args = parser.parse_args()
    targets = supported_targets(args.cshapes)
    results = {}
    for target in targets:
        out = os.path.join(args.out, target)
        shutil.rmtree(out, ignore_errors=True)
        env = dict(os.environ, CSHAPES_SIMD=target)
        command = [args.cshapes, "-q", "experiment", "paper", "--data", args.data, "--out", out, "--methods",
                   args.methods, "--no-table1", "--no-figure-data", "--no-draw", "--correspondence-samples", "0"]
        print("==", f"CSHAPES_SIMD={target}", " ".join(command), file=sys.stderr, flush=True)
        status = subprocess.run(command, env=env).returncode
        if status not in (0, 3):
            print(f"simd_retrieval: the run under {target} failed (exit {status})", file=sys.stderr)
            return 1
        with open(os.path.join(out, "metrics.json")) as f:
            results[target] = json.load(f)
    agree = True
    print(f"| method | distance | " + " | ".join(targets) + " | same to 3 decimals |")
    print("| --- | --- | " + " | ".join("---" for _ in targets) + " | --- |")
    for method in args.methods.split(","):
        for distance in ("hausdorff", "chamfer", "rmse"):
            cells, rounded = [], set()
            for target in targets:
                m = results[target]["methods"].get(method, {}).get("by_distance", {}).get(distance)
                if m is None:
                    cells.append("—")
                    rounded.add(None)
                    continue
                values = tuple(round(m[k], 3) for k in MEASURES)
                rounded.add(values)
                cells.append(f"mAP {m['map']:.3f}, NN {m['nn']:.3f}, FT {m['ft']:.3f}")
            same = len(rounded) == 1
            agree &= same
            print(f"| {method} | {distance} | " + " | ".join(cells) + f" | {'yes' if same else '**no**'} |")
    return 0 if agree else 1


if __name__ == "__main__":
    sys.exit(main())
