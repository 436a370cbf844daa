#!/usr/bin/env python3
"""A 400-shape retrieval collection (20 classes of 20 shapes) from the shared data and generated classes, at
mixed resolution (700-28,000 vertices), with near-duplicates and glued shapes: what issue 61 profiles
`cshapes experiment retrieval` on (docs/benchmarks.md, "A whole collection").

Classes (each 20 shapes):
  cat, dog, michael, victoria (tosca5k): each of the 6 poses remeshed twice at two sizes, once remeshed and
      glued (`cshapes noise --glue 2`); poses 0 and 1 once more as a near-duplicate (renumbered vertices,
      jitter of 1e-4 of the diagonal).
  cat_long, dog_long, michael_tall, victoria_tall: the same poses stretched by 1.4 along each pose's first
      principal axis (so not isometric to the originals), remeshed; 6 poses x 3 sizes + 2 glued.
  kid: the 16 KIDS poses and the TOPKIDS poses kid07-kid10 (real topological noise), remeshed.
  biped, quadruped, hand, spider (`cshapes generate articulated`, 16 poses) and their _long variants (x1.4
  along the first principal axis) and biped_wide, quadruped_wide, spider_wide (x1.4 along the other two): 16
  poses remeshed, and poses 0-3 glued.

Every size is drawn from a seeded generator, so the same seed gives the same collection (to the remesher's
determinism). Writes OUT/NAME.off, OUT/manifest.csv (file,class), OUT/manifest-100.csv (five shapes of each
class, those numbered 00, 04, 08, 12, 16: a quarter of the collection, a sixteenth of its pairs) and
OUT/sizes.csv. A shape already in OUT is kept (a killed run resumes).

Usage: make_benchmark400.py DATA OUT [--seed S] [--cshapes BINARY] [--per-class N]
  (run with the Python that has the cshapes module: PYTHONPATH=build/python /usr/bin/python3 ...)
"""
import argparse
import os
import random
import subprocess
import sys
import tempfile

import numpy as np

import cshapes

LO, HI = 700, 28000


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)}: exit {r.returncode}: {r.stderr.strip()}")


def stretched(V, factors):
    """V stretched along its own principal axes (first = largest variance) by factors[0..2]."""
    c = V.mean(axis=0)
    X = V - c
    w, U = np.linalg.eigh(X.T @ X)
    U = U[:, ::-1]
    return (X @ U) * np.asarray(factors) @ U.T + c


def near_duplicate(V, F, rng):
    """Renumbered vertices (faces remapped) and a jitter of 1e-4 of the bounding-box diagonal."""
    n = len(V)
    perm = rng.permutation(n)  # new vertex k is old vertex perm[k]
    inv = np.empty(n, dtype=np.int64)
    inv[perm] = np.arange(n)
    diag = np.linalg.norm(V.max(axis=0) - V.min(axis=0))
    W = V[perm] + rng.normal(scale=1e-4 * diag / np.sqrt(3), size=V.shape)
    return W, inv[F]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("data")
    ap.add_argument("out")
    ap.add_argument("--seed", type=int, default=61)
    ap.add_argument("--cshapes", default=os.path.join(os.path.dirname(__file__), "..", "build", "cshapes"))
    args = ap.parse_args()
    exe = args.cshapes
    rnd = random.Random(args.seed)
    rng = np.random.default_rng(args.seed)
    os.makedirs(args.out, exist_ok=True)
    tmp = tempfile.mkdtemp(prefix="bench400-")
    rows = []  # (file, class, vertices asked, how)

    def size():
        return rnd.randint(LO, HI)

    def remesh(src, name, cls, how, glue=0):
        n = size()
        out = os.path.join(args.out, name + ".off")
        if not os.path.exists(out):
            mid = os.path.join(tmp, name + ".off")
            run([exe, "--quiet", "remesh", src, "-o", mid, "--vertices", str(n)])
            if glue:
                run([exe, "--quiet", "noise", mid, "-o", out, "--glue", str(glue), "--seed", str(rnd.randint(0, 10**6)),
                     "--relax", "5"])
            else:
                os.replace(mid, out)
        else:
            if glue:
                rnd.randint(0, 10**6)  # keep the draws in step with a fresh run
        rows.append((name + ".off", cls, n, how))
        print(f"{name}: {n} vertices ({how})", flush=True)

    def transformed(src, name, factors):
        path = os.path.join(tmp, name + "-src.off")
        V, F = cshapes.read_mesh(src)
        cshapes.write_mesh(path, stretched(V, factors), F)
        return path

    tosca = os.path.join(args.data, "tosca5k")
    classes = {"cat": ["cat0", "cat1", "cat2", "cat3", "cat4", "cat5"],
               "dog": ["dog0", "dog1", "dog2", "dog3", "dog5", "dog6"],
               "michael": [f"michael{i}" for i in range(6)],
               "victoria": ["victoria0", "victoria1", "victoria2", "victoria4", "victoria7", "victoria10"]}
    for cls, poses in classes.items():
        k = 0
        for p in poses:
            src = os.path.join(tosca, p + ".off")
            for how in ("remesh", "remesh"):
                remesh(src, f"{cls}_{k:02d}", cls, how)
                k += 1
            remesh(src, f"{cls}_{k:02d}", cls, "glued", glue=2)
            k += 1
        for p in poses[:2]:
            name = f"{cls}_{k:02d}"
            out = os.path.join(args.out, name + ".off")
            V, F = cshapes.read_mesh(os.path.join(args.out, f"{cls}_{poses.index(p) * 3:02d}.off"))
            W, G = near_duplicate(V, F, rng)
            if not os.path.exists(out):
                cshapes.write_mesh(out, W, G)
            rows.append((name + ".off", cls, len(W), "near-duplicate"))
            print(f"{name}: near-duplicate", flush=True)
            k += 1
    for cls, suffix in (("cat", "long"), ("dog", "long"), ("michael", "tall"), ("victoria", "tall")):
        name_cls = f"{cls}_{suffix}"
        k = 0
        for p in classes[cls]:
            src = transformed(os.path.join(tosca, p + ".off"), f"{name_cls}-{p}", (1.4, 1, 1))
            for how in ("remesh", "remesh", "remesh"):
                remesh(src, f"{name_cls}_{k:02d}", name_cls, "stretched, " + how)
                k += 1
        for p in classes[cls][:2]:
            src = transformed(os.path.join(tosca, p + ".off"), f"{name_cls}-{p}", (1.4, 1, 1))
            remesh(src, f"{name_cls}_{k:02d}", name_cls, "stretched, glued", glue=2)
            k += 1
    k = 0
    for i in range(16):
        remesh(os.path.join(args.data, "kids", f"kid{i}.off"), f"kid_{k:02d}", "kid", "remesh")
        k += 1
    for i in range(7, 11):
        remesh(os.path.join(args.data, "topkids", f"kid{i:02d}.off"), f"kid_{k:02d}", "kid", "topkids, remesh")
        k += 1
    variants = [("", (1, 1, 1)), ("_long", (1.4, 1, 1)), ("_wide", (1, 1.4, 1.4))]
    for base in ("biped", "quadruped", "hand", "spider"):
        gen = os.path.join(tmp, base)
        run([exe, "--quiet", "generate", "articulated", "--class", base, "--poses", "16", "--seed",
             str(args.seed), "--vertices", "5000", "--out", gen])
        # The 16 poses (the generator also writes the rest pose, which is left out).
        posed = sorted(f for f in os.listdir(gen) if f.endswith(".off") and "rest" not in f)
        for suffix, factors in variants:
            if base == "hand" and suffix == "_wide":
                continue  # 20 classes in all
            cls = base + suffix
            k = 0
            for f in posed:
                src = transformed(os.path.join(gen, f), f"{cls}-{f[:-4]}", factors)
                remesh(src, f"{cls}_{k:02d}", cls, "generated, remesh")
                k += 1
            for f in posed[:4]:
                src = transformed(os.path.join(gen, f), f"{cls}-{f[:-4]}", factors)
                remesh(src, f"{cls}_{k:02d}", cls, "generated, glued", glue=2)
                k += 1
    with open(os.path.join(args.out, "manifest.csv.tmp"), "w") as m:
        m.write("file,class\n")
        for f, c, _, _ in rows:
            m.write(f"{f},{c}\n")
    os.replace(os.path.join(args.out, "manifest.csv.tmp"), os.path.join(args.out, "manifest.csv"))
    with open(os.path.join(args.out, "manifest-100.csv.tmp"), "w") as m:
        m.write("file,class\n")
        for f, c, _, _ in rows:
            if int(f[:-4].rsplit("_", 1)[1]) % 4 == 0:
                m.write(f"{f},{c}\n")
    os.replace(os.path.join(args.out, "manifest-100.csv.tmp"), os.path.join(args.out, "manifest-100.csv"))
    with open(os.path.join(args.out, "sizes.csv"), "w") as s:
        s.write("file,class,vertices,how\n")
        for f, c, n, how in rows:
            s.write(f"{f},{c},{n},{how}\n")
    counts = {}
    for _, c, _, _ in rows:
        counts[c] = counts.get(c, 0) + 1
    print(f"{len(rows)} shapes, {len(counts)} classes: " + ", ".join(f"{c} {n}" for c, n in counts.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
