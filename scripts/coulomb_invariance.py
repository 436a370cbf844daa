#!/usr/bin/env python3
"""Is the Coulomb form a function of the shape? (issue 59; docs/coulomb-defaults.md, "A function of the shape")

Remeshes each shape to each size (`cshapes remesh`), makes variants of it — renumbered (vertices permuted by a
seeded permutation, faces remapped and shuffled), scaled by a factor that is not a power of two, jittered by a
fraction of the bbox diagonal — canonizes every one with `cshapes canon --method coulomb --threads 1` (extra
canon options after `--`) and prints, per shape and size, how far each variant's form lies from the form of
the mesh as remeshed: `cshapes align`'s RMSE (ICP, % of the bbox diagonal) / the RMS over corresponding
vertices after the best rigid motion, reflections allowed (% of the bbox diagonal), and the iterations
("nc": not converged).

    /usr/bin/python3 scripts/coulomb_invariance.py --cshapes build/cshapes --data ../shared/data/tosca5k \\
        --work /tmp/inv --shapes dog0,michael0,victoria0,cat0 --sizes 1000,2000,3500 \\
        --variants p1,p2,p3,s10,s1e-3,j1e-12 [-- --move-limit 0]

Variants: pSEED renumbered with SEED, sFACTOR scaled, jAMPLITUDE jittered (uniform, × the diagonal). Every
output is kept in --work: a rerun reuses the forms it finds there (a new --tag for other canon options).
Needs numpy.
"""
import argparse
import json
import os
import subprocess
import sys

import numpy as np


def read_off(path):
    tokens = open(path).read().split()
    nv, nf = int(tokens[1]), int(tokens[2])
    V = np.array(tokens[4:4 + 3 * nv], dtype=float).reshape(nv, 3)
    F = np.array(tokens[4 + 3 * nv:4 + 3 * nv + 4 * nf], dtype=int).reshape(nf, 4)[:, 1:]
    return V, F


def write_off(path, V, F):
    with open(path, "w") as f:
        f.write("OFF\n%d %d 0\n" % (len(V), len(F)))
        for v in V:
            f.write("%.17g %.17g %.17g\n" % tuple(v))
        for t in F:
            f.write("3 %d %d %d\n" % tuple(t))


def make_variant(base, variant, path):
    """Writes the variant of mesh `base` to `path`; returns (order, scale): form row k is base vertex order[k]."""
    V, F = read_off(base)
    order, scale = np.arange(len(V)), 1.0
    kind, value = variant[0], variant[1:]
    if kind == "p":
        random = np.random.default_rng(int(value))
        order = random.permutation(len(V))
        new_index = np.empty_like(order)
        new_index[order] = np.arange(len(V))
        V, F = V[order], new_index[F][random.permutation(len(F))]
    elif kind == "s":
        scale = float(value)
        V = V * scale
    elif kind == "j":
        diagonal = np.linalg.norm(V.max(0) - V.min(0))
        V = V + np.random.default_rng(12345).uniform(-1, 1, V.shape) * float(value) * diagonal
    else:
        sys.exit("unknown variant " + variant)
    if not os.path.exists(path):
        write_off(path, V, F)
    return order, scale


def rms_percent(X, B):
    A, C = X - X.mean(0), B - B.mean(0)
    U, _, Vt = np.linalg.svd(A.T @ C)
    return 100 * np.sqrt(((A @ (U @ Vt) - C) ** 2).sum(1).mean()) / np.linalg.norm(C.max(0) - C.min(0))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cshapes", default="build/cshapes")
    parser.add_argument("--data", required=True, help="folder of NAME.off")
    parser.add_argument("--work", required=True, help="folder for the meshes, variants and forms")
    parser.add_argument("--shapes", required=True, help="comma-separated names")
    parser.add_argument("--sizes", default="1000,2000,3500", help="vertex counts; 0: the mesh as it is")
    parser.add_argument("--variants", default="p1,p2,p3,s10,s1e-3,j1e-12")
    parser.add_argument("--tag", default="default", help="names the forms' folder (one per set of canon options)")
    parser.add_argument("canon_options", nargs="*", help="after --: extra options of cshapes canon")
    a = parser.parse_args()
    meshes, forms = os.path.join(a.work, "meshes"), os.path.join(a.work, "forms", a.tag)
    os.makedirs(meshes, exist_ok=True)
    os.makedirs(forms, exist_ok=True)

    def run(arguments):
        r = subprocess.run([a.cshapes, "--threads", "1", "-q"] + arguments, capture_output=True, text=True)
        if r.returncode:
            sys.exit(" ".join(arguments) + ":\n" + r.stderr)
        return r.stdout

    def canon(mesh, form):
        if not os.path.exists(form + ".json"):
            out = run(["canon", mesh, "-o", form, "--method", "coulomb", "--json"] + a.canon_options)
            open(form + ".json", "w").write(out)
        return json.load(open(form + ".json"))

    variants = a.variants.split(",")
    print("| shape | vertices | iterations | " + " | ".join(variants) + " |")
    print("| --- | --- | --- |" + " --- |" * len(variants))
    for shape in a.shapes.split(","):
        for size in a.sizes.split(","):
            base = os.path.join(meshes, f"{shape}_{size}.off")
            if not os.path.exists(base):
                source = os.path.join(a.data, shape + ".off")
                if int(size):
                    run(["remesh", source, "-o", base, "--vertices", size])
                else:
                    V, F = read_off(source)
                    write_off(base, V, F)
            base_form = os.path.join(forms, f"{shape}_{size}.off")
            summary = canon(base, base_form)
            B, F = read_off(base_form)
            cells = []
            for variant in variants:
                mesh = os.path.join(meshes, f"{shape}_{size}_{variant}.off")
                order, scale = make_variant(base, variant, mesh)
                form = os.path.join(forms, f"{shape}_{size}_{variant}.off")
                s = canon(mesh, form)
                X = np.empty_like(B)
                X[order] = read_off(form)[0] / scale
                back = form + ".in_base_order.off"
                write_off(back, X, F)
                icp = json.loads(run(["align", back, base_form, "--json"]))["rmse_percent"]
                cells.append(f"{icp:.2f} / {rms_percent(X, B):.3f}" + ("" if s["converged"] else " nc") +
                             f" ({s['iterations']})")
            done = f"{summary['iterations']}" + ("" if summary["converged"] else " nc")
            print(f"| {shape} | {size} | {done} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
