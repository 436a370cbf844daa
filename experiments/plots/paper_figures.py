#!/usr/bin/env python3
"""Draw every figure of `cshapes experiment paper` from the CSV/JSON/mesh files it wrote into OUT.

  scripts/python.sh experiments/plots/paper_figures.py OUT [--format png|pdf|svg]

Reads:
  figures.json                  written by the C++ driver: "draw", the figures of this run (only these are
                                drawn: files of an earlier run into the same folder are not taken for this
                                run's); "methods", the methods of this run; "grids", the meshes of Fig. 2/3/4/6;
                                "data", the data's name for the titles
  convergence.csv               projection_steps,iteration,energy,mean_violation         -> fig5_convergence
  distances/<method>.csv        distance matrix, header "shape,<names...>"                -> fig7_distance_matrices
  labels.csv                    shape,class
  metrics.json                  per method: map, nn, ft, st, e, dcg, pr {recall, precision} -> fig8_pr
  correspondence_error.csv      method,error,fraction                                     -> fig9_correspondence
Writes each figure next to them as PNG, or PDF or SVG with --format.
"""
import argparse
import concurrent.futures
import csv
import json
import multiprocessing
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import FuncFormatter  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from meshio import read_mesh  # noqa: E402
from render_mesh import draw_mesh  # noqa: E402
from figure_style import (COLUMN_WIDTH, PAGE_WIDTH, add_format_argument, method_style, method_styles,  # noqa: E402
                          save, use_paper_style, wrapped)


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def red_mask(V, props, spec, out):
    red = np.zeros(len(V), bool)
    if not spec:
        return None
    prop = spec.get("property")
    if prop and prop in props:
        red |= props[prop] > 0.5
    for i in spec.get("vertices", []):
        if 0 <= i < len(V):
            red[i] = True
    return red if red.any() else None


def mesh_grid(out, name, grid, fmt, panel=2.6):
    """grid: {"rows": [...row titles], "cols": [...col titles], "cells": [[{"mesh", "red"}...]...]}. At most a
    page wide (the panels shrink to fit), its text at the paper style's sizes."""
    rows, cols = len(grid["cells"]), max(len(r) for r in grid["cells"])
    panel = min(panel, (PAGE_WIDTH - 0.3) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(panel * cols + 0.3, panel * rows + 0.3), squeeze=False)
    for r, row in enumerate(grid["cells"]):
        for c in range(cols):
            ax = axes[r][c]
            ax.axis("off")
            if c >= len(row) or not row[c] or not os.path.exists(os.path.join(out, row[c]["mesh"])):
                continue
            V, F, props = read_mesh(os.path.join(out, row[c]["mesh"]))
            title = row[c].get("title")
            draw_mesh(ax, V, F, red_mask(V, props, row[c].get("red"), out), wrapped(title, panel) if title else None)
            ax.title.set_fontsize(8)
        if grid.get("rows"):
            axes[r][0].text(-0.05, 0.5, grid["rows"][r], transform=axes[r][0].transAxes, rotation=90,
                            va="center", ha="right", fontsize=8)
    if grid.get("title"):
        fig.suptitle(wrapped(grid["title"], PAGE_WIDTH), fontsize=8)
    fig.tight_layout()
    save(fig, out, name, fmt)


def fig_convergence(out, fmt):
    path = os.path.join(out, "convergence.csv")
    if not os.path.exists(path):
        return
    rows = read_csv(path)
    fig, ax1 = plt.subplots(figsize=(COLUMN_WIDTH, 2.6))
    ax2 = ax1.twinx()
    styles = ["-", "--", ":", "-."]
    for k_index, k in enumerate(sorted({int(r["projection_steps"]) for r in rows})):
        sel = [r for r in rows if int(r["projection_steps"]) == k]
        it = [int(r["iteration"]) for r in sel]
        ls = styles[k_index % len(styles)]
        steps = f"{k} proj. step" + ("" if k == 1 else "s")
        ax1.plot(it, [float(r["energy"]) for r in sel], "tab:red", ls=ls, label=f"energy, {steps}")
        ax2.plot(it, [float(r["mean_violation"]) for r in sel], "tab:blue", ls=ls, label=f"violation, {steps}")
    ax1.set_xlabel("outer iteration")
    ax1.set_ylabel("Coulomb energy", color="tab:red")
    ax2.set_ylabel("mean relative metric violation", color="tab:blue")
    ax1.set_yscale("log")
    ax2.set_yscale("log")
    # Plain numbers on the log axes ("0.01", "40000"): mathtext's "10^-2" has a superscript under 7 pt. The
    # minor ticks are labelled only on an axis within one decade, as matplotlib's default does.
    for ax in (ax1, ax2):
        ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        ax.yaxis.set_minor_formatter(FuncFormatter(
            lambda v, _, ax=ax: f"{v:g}" if ax.get_ylim()[1] < 10 * ax.get_ylim()[0] else ""))
    h1, l1 = ax1.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    # Below the axes, off the curves (which cross the whole plot).
    ax1.legend(h1 + h2, l1 + l2, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=2, frameon=False)
    ax1.set_title("Fig. 5: convergence for 1, 10 and 100 projection steps")
    save(fig, out, "fig5_convergence", fmt)


def read_matrix(path):
    """A distance CSV as `cshapes distmat`/`experiment paper` write it: a header of shape names, then one row of
    numbers per shape; a leading name column (header "shape" or empty) is accepted too."""
    with open(path) as f:
        rows = [r for r in csv.reader(f) if r]
    header, body = rows[0], rows[1:]
    named = len(body) > 0 and len(body[0]) == len(header) + 1 or header[0] in ("", "shape", "name")
    names = header[1:] if named and len(body[0]) == len(header) else header
    D = np.array([[float(x) for x in (r[1:] if len(r) == len(names) + 1 else r)] for r in body])
    return names, D


def data_suffix(spec):
    """", DATA" for a title when figures.json names the data; "" otherwise (a folder written before it did)."""
    return f", {spec['data']}" if spec.get("data") else ""


def fig_distance_matrices(out, fmt, methods, data=""):
    """Fig. 7: one panel per method of the run, all on one colour scale (the 95th percentile of every method's
    distances between different shapes), so the methods can be compared by eye: a method whose distances are
    smaller across the board looks brighter everywhere, not just rescaled."""
    folder = os.path.join(out, "distances")
    if not methods:
        return
    styles = method_styles(out)
    matrices = {m: read_matrix(os.path.join(folder, m + ".csv")) for m in methods}
    labels_path = os.path.join(out, "labels.csv")
    class_of = {r["shape"]: r["class"] for r in read_csv(labels_path)} if os.path.exists(labels_path) else {}
    off_diagonal = np.concatenate([D[~np.eye(len(D), dtype=bool)] for _, D in matrices.values()])
    vmax = np.percentile(off_diagonal, 95) if off_diagonal.size else 1.0
    # A page wide, at most three panels a row.
    cols = min(3, len(methods))
    rows = (len(methods) + cols - 1) // cols
    panel = (PAGE_WIDTH - 0.9) / cols
    fig, axes = plt.subplots(rows, cols, figsize=(PAGE_WIDTH, panel * rows + 0.5), squeeze=False)
    for ax in axes.flat[len(methods):]:
        ax.axis("off")
    for k, (ax, m) in enumerate(zip(axes.flat, methods)):
        names, D = matrices[m]
        im = ax.imshow(D, cmap="viridis_r", vmin=0, vmax=vmax, interpolation="nearest")
        # Each shape's class from labels.csv ("cat4_noisy" is a cat); from its name where there is none.
        classes = [class_of.get(n) or n.replace("_noisy", "").rstrip("0123456789") for n in names]
        starts = [i for i in range(len(classes)) if i == 0 or classes[i] != classes[i - 1]]
        # Each shape named while the names fit at 7 pt (a row at least 8 pt tall), each class block otherwise.
        if panel * 72 / max(1, len(names)) >= 8:
            ticks, labels = range(len(names)), names
        else:
            ends = starts[1:] + [len(names)]
            ticks, labels = [(a + b - 1) / 2 for a, b in zip(starts, ends)], [classes[a] for a in starts]
        ax.set_xticks(ticks)
        ax.set_yticks(ticks)
        ax.set_xticklabels(labels, rotation=90)
        # The rows' names at the left of each row of panels only (the same order in every panel).
        ax.set_yticklabels(labels if k % cols == 0 else [])
        for i in starts[1:]:  # class boundaries
            ax.axhline(i - 0.5, color="white", lw=1)
            ax.axvline(i - 0.5, color="white", lw=1)
        ax.set_title(method_style(styles, m)[0])
    # The forms' units: each method's form keeps the scale of the input's geodesic or edge lengths.
    fig.colorbar(im, ax=list(axes.flat), fraction=0.025, pad=0.02, label="Hausdorff distance (form units)")
    fig.suptitle(f"Fig. 7: Hausdorff distances between ICP-aligned forms{data} (one scale; yellow = close)")
    save(fig, out, "fig7_distance_matrices", fmt)


def fig_pr(out, fmt, data=""):
    path = os.path.join(out, "metrics.json")
    if not os.path.exists(path):
        return
    with open(path) as f:
        metrics = json.load(f)
    styles = method_styles(out)
    fig, ax = plt.subplots(figsize=(COLUMN_WIDTH, 3.0))
    for m, v in metrics.get("methods", metrics).items():
        if not isinstance(v, dict) or "pr" not in v:
            continue
        label, color = method_style(styles, m)
        ax.plot(v["pr"]["recall"], v["pr"]["precision"], marker="o", ms=3, color=color,
                label=f"{label} (mAP {v['map']:.2f})")
    ax.set_xlabel("recall")
    ax.set_ylabel("precision")
    ax.set_xlim(0, 1.02)
    ax.set_ylim(0, 1.02)
    ax.grid(alpha=0.3)
    ax.legend()
    ax.set_title(wrapped(f"Fig. 8: precision-recall, Hausdorff distance{data}", COLUMN_WIDTH))
    save(fig, out, "fig8_pr", fmt)


def fig_correspondence(out, fmt):
    path = os.path.join(out, "correspondence_error.csv")
    if not os.path.exists(path):
        return
    rows = read_csv(path)
    styles = method_styles(out)
    fig, ax = plt.subplots(figsize=(COLUMN_WIDTH, 2.8))
    for m in dict.fromkeys(r["method"] for r in rows):
        sel = [r for r in rows if r["method"] == m]
        label, color = method_style(styles, m)
        ax.plot([float(r["error"]) for r in sel], [float(r["fraction"]) for r in sel], color=color, label=label)
    ax.set_xlabel("geodesic error on the target pose / √area")  # eval/correspondence_error.h normalises so
    ax.set_ylabel("fraction of correspondences")
    ax.set_ylim(0, 1.02)
    ax.grid(alpha=0.3)
    ax.legend()
    ax.set_title(wrapped("Point maps induced by aligning canonical forms", COLUMN_WIDTH))
    save(fig, out, "fig9_correspondence", fmt)


# The figures other than the mesh grids, by name: each drawn from the run's folder (out, spec, fmt).
FIGURES = {
    "fig5_convergence": lambda out, spec, fmt: fig_convergence(out, fmt),
    "fig7_distance_matrices": lambda out, spec, fmt: fig_distance_matrices(out, fmt, spec.get("methods", []),
                                                                           data_suffix(spec)),
    "fig8_pr": lambda out, spec, fmt: fig_pr(out, fmt, data_suffix(spec)),
    "fig9_correspondence": lambda out, spec, fmt: fig_correspondence(out, fmt),
}


def draw_one(out, spec, name, fmt):
    """Draws figure NAME (a mesh grid or one of FIGURES) of the run in OUT."""
    if name in spec.get("grids", {}):
        mesh_grid(out, name, spec["grids"][name], fmt)
    else:
        FIGURES[name](out, spec, fmt)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("out")
    add_format_argument(p)
    args = p.parse_args()
    use_paper_style()
    spec_path = os.path.join(args.out, "figures.json")
    if not os.path.exists(spec_path):
        sys.exit(f"paper_figures.py: {spec_path} is missing: run `cshapes experiment paper --out {args.out}` first")
    with open(spec_path) as f:
        spec = json.load(f)
    draw = spec.get("draw", [])
    unknown = [n for n in draw if n not in spec.get("grids", {}) and n not in FIGURES]
    if unknown:
        sys.exit(f"paper_figures.py: {spec_path} asks for '{unknown[0]}', which this script does not draw")
    # The figures are independent files: two processes draw them, the largest mesh grids (the slow ones) first,
    # which about halves the wall time on two cores; each picture is drawn as it would be alone.
    grids = spec.get("grids", {})
    order = sorted(draw, key=lambda n: -sum(len(row) for row in grids[n]["cells"]) if n in grids else 0)
    # "progress K N" on stdout as each figure is done, when `cshapes experiment paper` asks for it to report.
    def done(k):
        if os.environ.get("CSHAPES_FIGURE_PROGRESS"):
            print(f"progress {k + 1} {len(order)}", flush=True)

    if min(2, os.cpu_count() or 1, len(draw)) < 2:
        for k, name in enumerate(order):
            draw_one(args.out, spec, name, args.format)
            done(k)
        return
    with concurrent.futures.ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("fork")) as pool:
        jobs = [pool.submit(draw_one, args.out, spec, name, args.format) for name in order]
        for k, job in enumerate(concurrent.futures.as_completed(jobs)):
            job.result()
            done(k)


if __name__ == "__main__":
    main()
