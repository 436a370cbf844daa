#!/usr/bin/env python3
"""Prints every ratio of docs/benchmarks.md's table from the JSON files scripts/benchmarks.sh wrote into OUT.

  scripts/benchmark_ratios.py OUT

One line per ratio: the row, ours, the reference measured in the same run, and their ratio. Exits 1 when an
anchor that should have run did not (scikit-learn or Open3D missing: scripts/install-deps.sh --with-anchors),
naming the reason the benchmark gave. Standard library only.
"""
import json
import os
import sys


def load(out, name):
    path = os.path.join(out, name + ".json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)


def line(row, ours, reference, ratio, unit="×"):
    print(f"{row:44s} {ours:>26s}   {reference:>34s}   {ratio:8.2f}{unit}")


def main(out):
    missing = []
    print(f"{'row':44s} {'ours':>26s}   {'reference, same run':>34s}   ratio")
    for n in (3505, 22738, 100000):
        j = load(out, f"coulomb-{n}")
        if j:
            line(f"Coulomb gradient, n = {n:,}", f"FMM {j['fast_seconds']:.4g} s", f"direct {j['direct_seconds']:.4g} s"
                 + (" (extrapolated)" if j.get("direct_extrapolated") else ""), j["speedup"])
    for kind in ("surface", "uniform"):
        j = load(out, f"coulomb-1000000-{kind}")
        if j:
            line(f"Coulomb gradient, n = 1,000,000, {kind}", f"FMM {j['fast_seconds']:.3g} s",
                 f"direct {j['direct_seconds']:.4g} s (extrapolated)", j["speedup"])
    for n in (3505, 22738):
        j = load(out, f"coulomb-iteration-{n}")
        if j:
            line(f"Coulomb outer iteration, {n:,} vertices", f"{j['seconds_per_iteration']:.3g} s",
                 f"paper {j['paper_seconds_per_iteration']:.3g} s", j["speedup_vs_paper"])
            line(f"  the same, fast sum at 1e-3", f"{j['seconds_per_iteration_accuracy_1e-3']:.3g} s",
                 f"paper {j['paper_seconds_per_iteration']:.3g} s", j["speedup_vs_paper_accuracy_1e-3"])
    for n in (3505, 22738):
        j = load(out, f"geodesics-{n}")
        if j:
            a = j["anchor"]
            line(f"all-pairs geodesics, {n:,} vertices", f"heat (ours) {j['ours']['seconds']:.3g} s",
                 f"CGAL Heat_method_3 {a['seconds']:.3g} s" + (" (extrap.)" if a.get("extrapolated") else ""),
                 j["speedup_vs_anchor"])
    for n in (3505, 22738):
        j = load(out, f"smacof-{n}")
        if not j:
            continue
        ref = j.get("reference", {})
        if "speedup_vs_reference" in j:
            line(f"SMACOF iteration, n = {n:,}", f"{j['seconds_per_iteration']:.3g} s",
                 f"scikit-learn {ref.get('version', '')} {ref['seconds_per_iteration']:.3g} s",
                 j["speedup_vs_reference"])
            if "single_thread" in j:
                line("  the same, one thread", f"{j['single_thread']['seconds_per_iteration']:.3g} s",
                     f"scikit-learn {ref['seconds_per_iteration']:.3g} s", j["single_thread"]["speedup_vs_reference"])
        else:
            reason = ref.get("skipped", "not measured")
            print(f"{'SMACOF iteration, n = ' + format(n, ','):44s} {j['seconds_per_iteration']:.3g} s; "
                  f"scikit-learn skipped: {reason}")
            if n <= 5000:
                missing.append(f"smacof-{n}: {reason}")
    j = load(out, "smacof-cat0-acceleration")
    if j and "acceleration" in j:
        acc = j["acceleration"]
        plain = acc["none"]["iterations"]
        for method in ("rre", "mpe"):
            if method in acc:
                line(f"SMACOF acceleration ({method}), cat0", f"{acc[method]['iterations']} iterations",
                     f"plain {plain} iterations", plain / max(acc[method]["iterations"], 1))
    j = load(out, "icp")
    if j:
        if "ratio_open3d_over_ours" in j:
            line("ICP iteration, cat0 vs cat1", f"{j['ours_ms_per_iteration']:.3g} ms",
                 f"Open3D {j['open3d_version']} {j['open3d_ms_per_iteration']:.3g} ms", j["ratio_open3d_over_ours"])
        else:
            reason = j.get("open3d_skipped", "not measured")
            print(f"{'ICP iteration, cat0 vs cat1':44s} Open3D skipped: {reason}")
            missing.append(f"icp: {reason}")
    for n in (5000, 22738, 50000):
        for method in ("coulomb", "cmds", "smacof", "lbo", "diffusion", "spectral-mds"):
            j = load(out, f"form-{method}-{n}")
            if not j:
                continue
            ours = f"{j['seconds']:.3g} s, {j['peak_rss_mb']:.0f} MB"
            row = f"{method} form, {j['vertices']:,} vertices"
            if "speedup_vs_reference" in j:
                ref = j["reference"]
                line(row, ours, f"full cMDS {ref['seconds']:.3g} s, {ref['peak_rss_mb']:.0f} MB",
                     j["speedup_vs_reference"])
            else:
                print(f"{row:44s} {ours:>26s}   (reference: {j['reference'].get('skipped', 'not run')})")
    for m in missing:
        print(f"benchmark_ratios: an anchor did not run: {m} (scripts/install-deps.sh --with-anchors)",
              file=sys.stderr)
    return 1 if missing else 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
