#!/usr/bin/env python3
"""Draw the TOPKIDS cumulative error curves of `cshapes experiment topkids` from the files it wrote into OUT.

  scripts/python.sh experiments/plots/topkids_figure.py OUT [--format png|pdf|svg]

Reads OUT/curves.csv (method,forgiven,error,fraction: the fraction of ground-truth vertices mapped within each
geodesic error, in units of sqrt(area) of the reference, pooled over the poses; forgiven = vertex or map, how a
left-right flip is forgiven: one panel each) and OUT/topkids.json: the medians and mirrored counts, and its rows
for the last panel, a strip per method of each pose's mean error (mean_error, flip forgiven per vertex), a dot
per pose, so that poses whose alignment failed show as their own cluster; where the map is mirrored (the row's
"mirrored": clearly nearer the mirrored truth, experiments/topkids_experiment.h) a cross at its mean error
against the truth alone (direct_mean_error), which is what the flip costs when it is not forgiven. A page wide
at a two-column paper's text sizes, one key of the methods above the panels (the means and shares are in the
report's table). Writes OUT/topkids.png (.pdf, .svg by --format), through a temporary file renamed at the end.
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
from figure_style import (PAGE_WIDTH, add_format_argument, method_style, method_styles, save,  # noqa: E402
                          use_paper_style, wrapped)


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
            ax.plot(x + dx, r["mean_error"], "o", color=colour, ms=3, alpha=0.85)
            if r.get("mirrored") and r.get("direct_mean_error") is not None:
                ax.plot([x + dx, x + dx], [r["mean_error"], r["direct_mean_error"]], "-", color=colour, lw=0.8,
                        alpha=0.6)
                ax.plot(x + dx, r["direct_mean_error"], "x", color=colour, ms=4, mew=1.2)
        s = summary.get(method, {})
        if s.get("median_pose_mean_error") is not None:
            ax.hlines(s["median_pose_mean_error"], x - 0.4, x + 0.4, color=colour, lw=1.5)
    # Under each column its method and how many of its poses were mirrored ("2/9 m."), at 7 pt.
    labels = []
    for m in methods:
        label = method_style(styles, m)[0].replace(" (no canonical form)", "")
        s = summary.get(m, {})
        if s.get("poses"):
            label += f" ({s.get('mirrored_poses', 0)}/{s['poses']} \u00d7)"
        labels.append(label)
    ax.set_xticks(range(len(methods)))
    ax.set_xticklabels(labels, rotation=40, ha="right")
    ax.set_xlim(-0.6, len(methods) - 0.4)
    ax.set_ylim(bottom=0)
    ax.set_ylabel("a pose's mean error / \u221aarea")
    ax.set_title("per pose (\u25cf), median (bar);\n\u00d7: mirrored, against the truth alone")
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

    panels = [(k, t) for k, t in (("vertex", "flip forgiven per vertex\n(SHREC'16's reading)"),
                                  ("map", "flip forgiven per whole map\n(stricter)")) if k in curves]
    styles = method_styles(args.out)
    strip = any(r.get("direct_mean_error") is not None for r in rows)
    count = len(panels) + (1 if strip else 0)
    # A page wide (a column for one panel), text at 7-8 pt once printed; one key of the methods above the
    # panels (the means and shares are the report's table, not the legend's).
    use_paper_style()
    width = PAGE_WIDTH if count > 1 else PAGE_WIDTH / 2
    fig, axes = plt.subplots(1, count, figsize=(width, 2.5), squeeze=False)
    if strip:
        draw_pose_strip(axes[0][-1], rows, summary, styles)
    handles, labels = [], []
    for panel, (ax, (kind, panel_title)) in enumerate(zip(axes[0], panels)):
        for method, (x, y) in curves[kind].items():
            name, colour = method_style(styles, method)
            line, = ax.plot(x, y, "--" if method == "inputs" else "-", color=colour)
            if panel == 0:
                handles.append(line)
                labels.append(name)
        for t in (0.1, 0.25):
            ax.axvline(t, color="0.75", lw=0.6, zorder=0)
        ax.set_xlim(0, max(max(x) for x, _ in curves[kind].values()))
        ax.set_ylim(0, 1)
        ax.set_xlabel("geodesic error / \u221aarea")
        if panel == 0:
            ax.set_ylabel("share of ground-truth vertices")
        ax.set_title(panel_title)
        ax.grid(alpha=0.3)
    title = "TOPKIDS (SHREC'16, real topological noise): point maps from ICP of canonical forms"
    if poses:
        title += f", {len(poses)} poses onto kid00"
        if samples:
            title += f", {samples} ground-truth vertices each"
    fig.tight_layout(w_pad=1.0)
    key = fig.legend(handles, labels, loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=min(4, len(labels)),
                     frameon=False, title=wrapped(title, width), title_fontsize=8)
    key.get_title().set_multialignment("center")
    save(fig, args.out, "topkids", args.format)


if __name__ == "__main__":
    main()
