#!/usr/bin/env python3
"""Draw the TOPKIDS cumulative error curves of `cshapes experiment topkids` from the files it wrote into OUT.

  scripts/python.sh experiments/plots/topkids_figure.py OUT [--format png|pdf|svg]

Reads OUT/curves.csv (method,forgiven,error,fraction: the fraction of ground-truth vertices mapped within each
geodesic error, in units of sqrt(area) of the reference, pooled over the poses; forgiven = vertex or map, how a
left-right flip is forgiven: one panel each) and OUT/topkids.json: the legend's means and medians, and its rows
for the last panel, a strip per method of each pose's mean error (mean_error, flip forgiven per vertex), a dot
per pose, so that poses whose alignment failed show as their own cluster; where the map is mirrored (the row's
"mirrored": clearly nearer the mirrored truth, experiments/topkids_experiment.h) a cross at its mean error
against the truth alone (direct_mean_error), which is what the flip costs when it is not forgiven. Writes
OUT/topkids.png (.pdf, .svg by --format), through a temporary file renamed at the end.
"""
import argparse
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from figure_style import add_format_argument, method_style, method_styles, save  # noqa: E402


def draw_pose_strip(ax, rows, summary, styles):
    """One column per method: each pose's mean error (flip forgiven per vertex, the benchmark's reading), a dot
    per pose (spread sideways so equal values stay visible); where the map is mirrored, a cross at the same
    map's mean error against the truth alone, joined to its dot; a bar at the median over poses."""
    methods = []
    for r in rows:
        if r["method"] not in methods:
            methods.append(r["method"])
    for x, method in enumerate(methods):
        _, colour = method_style(styles, method)
        mine = [r for r in rows if r["method"] == method and r.get("mean_error") is not None]
        for k, r in enumerate(mine):
            dx = 0.3 * ((k % 7) - 3) / 3
            ax.plot(x + dx, r["mean_error"], "o", color=colour, ms=6, alpha=0.85)
            if r.get("mirrored") and r.get("direct_mean_error") is not None:
                ax.plot([x + dx, x + dx], [r["mean_error"], r["direct_mean_error"]], "-", color=colour, lw=0.8,
                        alpha=0.6)
                ax.plot(x + dx, r["direct_mean_error"], "x", color=colour, ms=7, mew=2)
        s = summary.get(method, {})
        if s.get("median_pose_mean_error") is not None:
            ax.hlines(s["median_pose_mean_error"], x - 0.4, x + 0.4, color=colour, lw=2)
    labels = []
    for m in methods:
        label = method_style(styles, m)[0].replace(" (no canonical form)", "")
        s = summary.get(m, {})
        if s.get("poses"):
            label += f"\n{s.get('mirrored_poses', 0)} of {s['poses']} mirrored"
        labels.append(label)
    ax.set_xticks(range(len(methods)))
    ax.set_xticklabels(labels, rotation=30, ha="right", fontsize=8)
    ax.set_xlim(-0.6, len(methods) - 0.4)
    ax.set_ylim(bottom=0)
    ax.set_ylabel("pose's mean error / \u221aarea")
    ax.set_title("per pose: \u25cf flip forgiven per vertex, bar: median;\n"
                 "\u00d7 a mirrored map against the truth alone", fontsize=9)
    ax.grid(alpha=0.3, axis="y")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out")
    add_format_argument(parser)
    args = parser.parse_args()

    # curves[forgiven][method] = (errors, fractions); files without the column are per-vertex curves.
    curves = {}
    with open(os.path.join(args.out, "curves.csv")) as f:
        for row in csv.DictReader(f):
            panel = curves.setdefault(row.get("forgiven", "vertex"), {})
            x, y = panel.setdefault(row["method"], ([], []))
            x.append(float(row["error"]))
            y.append(float(row["fraction"]))
    summary, poses, samples, rows = {}, [], None, []
    path = os.path.join(args.out, "topkids.json")
    if os.path.exists(path):
        with open(path) as f:
            j = json.load(f)
        summary = {s["method"]: s for s in j.get("summary", [])}
        poses = j.get("poses", [])
        samples = j.get("samples_per_pose")
        rows = j.get("rows", [])

    panels = [(k, t) for k, t in (("vertex", "flip forgiven per vertex (SHREC'16)"),
                                  ("map", "flip forgiven per whole map (stricter)")) if k in curves]
    styles = method_styles(args.out)
    strip = any(r.get("direct_mean_error") is not None for r in rows)
    count = len(panels) + (1 if strip else 0)
    fig, axes = plt.subplots(1, count, figsize=(6.0 * count, 4.8), squeeze=False)
    if strip:
        draw_pose_strip(axes[0][-1], rows, summary, styles)
    for ax, (kind, panel_title) in zip(axes[0], panels):
        prefix = "" if kind == "vertex" else "whole_map_"
        for method, (x, y) in curves[kind].items():
            name, colour = method_style(styles, method)
            dash = "--" if method == "inputs" else "-"
            s = summary.get(method)
            if s and s.get(prefix + "mean_error") is not None:
                name += f"  (mean {s[prefix + 'mean_error']:.3f}"
                if kind == "vertex" and s.get("median_error") is not None:
                    name += f", median {s['median_error']:.3f}"
                name += f", \u2264 0.25: {100 * s[prefix + 'under_0.25']:.0f}%)"
            ax.plot(x, y, dash, color=colour, lw=2, label=name)
        for t in (0.1, 0.25):
            ax.axvline(t, color="0.75", lw=0.8, zorder=0)
        ax.set_xlim(0, max(max(x) for x, _ in curves[kind].values()))
        ax.set_ylim(0, 1)
        ax.set_xlabel("geodesic error on the reference / \u221aarea")
        ax.set_ylabel("fraction of ground-truth vertices")
        ax.set_title(panel_title, fontsize=10)
        ax.grid(alpha=0.3)
        ax.legend(loc="upper left", fontsize=8)
    title = "TOPKIDS (SHREC'16, real topological noise): point maps from ICP of canonical forms"
    if poses:
        title += f"\n{len(poses)} poses onto kid00"
        if samples:
            title += f", {samples} ground-truth vertices each"
    fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    save(fig, args.out, "topkids", args.format)


if __name__ == "__main__":
    main()
