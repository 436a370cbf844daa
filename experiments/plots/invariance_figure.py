#!/usr/bin/env python3
"""Draw invariance.png of `cshapes experiment invariance` from the files it wrote into OUT.

  scripts/python.sh experiments/plots/invariance_figure.py OUT [--format png|pdf|svg]

Reads OUT/invariance.csv (a row per resolution, shape, method, transformation and seed: rmse_percent, the RMSE
after alignment in % of the reference form's diagonal) and OUT/invariance.json (resolutions, methods,
transformations in order, and per method and resolution its verdict, tolerance_percent and pose_rmse_percent).
One panel per resolution (two a row), sharing a logarithmic y axis of RMSE %: per transformation, each method's rows as
small dots and its largest as a large one, side by side; the remeshes (reported apart) after a vertical rule;
last, "pose variation", the method's median pose RMSE as a star (the signal the noise is held against). The
tolerance floor is a grey dashed line over the exact transformations, and a method whose tolerance is above it
(1% of a large pose variation) has its own dashed line in its colour. An exact zero (a method that does not
move at all) is drawn at the bottom of the axis, on a grey band. A page wide (a column for one resolution) at a
two-column paper's text sizes. Writes OUT/invariance.png (.pdf, .svg by
--format) through a temporary file renamed at the end.
"""
import argparse
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from figure_style import (COLUMN_WIDTH, PAGE_WIDTH, add_format_argument, method_style, method_styles,  # noqa: E402
                          powers_of_ten, save, use_paper_style)


def read_rows(out):
    with open(os.path.join(out, "invariance.csv")) as f:
        return [r for r in csv.DictReader(f) if r["rmse_percent"] != ""]


def resolution_title(n):
    return "shapes as given" if n == 0 else f"{n:,} vertices"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out")
    add_format_argument(parser)
    args = parser.parse_args()
    with open(os.path.join(args.out, "invariance.json")) as f:
        meta = json.load(f)
    rows = read_rows(args.out)
    if not rows:
        sys.exit("invariance_figure.py: invariance.csv has no measured row")
    resolutions, methods = meta["resolutions"], meta["methods"]
    transformations = meta["transformations"]
    exact = [t for t in transformations if not t.startswith("remesh-")]
    columns = transformations + ["pose variation"]
    styles = method_styles(args.out)
    verdicts = {(v["resolution"], v["method"]): v for v in meta["verdicts"]}

    values = [float(r["rmse_percent"]) for r in rows]
    values += [v["pose_rmse_percent"] for v in meta["verdicts"] if v.get("pose_rmse_percent")]
    values += [v["tolerance_percent"] for v in meta["verdicts"] if v.get("tolerance_percent")]
    positive = [v for v in values if v > 0]
    # Exact zeros are drawn at `zero`, on a grey band below every measured value.
    zero = 10 ** math.floor(math.log10(min(positive))) / 10 if positive else 1e-12
    top = 10 ** math.ceil(math.log10(max(positive))) * 3 if positive else 1.0
    floor = meta["tolerance"]["floor_percent"]

    width = 0.8 / max(1, len(methods))
    # Two panels a row at most, a page wide (a column for one resolution), text at 7-8 pt once printed.
    use_paper_style()
    ncols = min(2, len(resolutions))
    nrows = math.ceil(len(resolutions) / ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(PAGE_WIDTH if ncols > 1 else COLUMN_WIDTH, 2.4 * nrows),
                             sharey=True, squeeze=False)
    for ax in axes.flat[len(resolutions):]:
        ax.set_visible(False)
    for panel, n in enumerate(resolutions):
        ax = axes.flat[panel]
        ax.set_yscale("log")
        ax.yaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(powers_of_ten))
        ax.axhspan(zero / 3, zero * 3, color="0.92", zorder=0)
        ax.hlines(floor, -0.5, len(exact) - 0.5, colors=["0.45"], linestyles="dashed", linewidth=0.8, zorder=1)
        for k, m in enumerate(methods):
            title, colour = method_style(styles, m)
            offset = (k - (len(methods) - 1) / 2) * width
            for x, t in enumerate(transformations):
                ys = [max(float(r["rmse_percent"]), zero) for r in rows
                      if int(r["resolution"]) == n and r["method"] == m and r["transformation"] == t]
                if not ys:
                    continue
                ax.scatter([x + offset] * len(ys), ys, s=2, color=colour, alpha=0.5, linewidths=0, zorder=2)
                ax.scatter([x + offset], [max(ys)], s=9, color=colour, linewidths=0, zorder=3,
                           label=title if (panel == 0 and x == 0) else None)
            v = verdicts.get((n, m), {})
            if v.get("tolerance_percent") and v["tolerance_percent"] > floor * (1 + 1e-9):
                ax.hlines(v["tolerance_percent"], -0.5, len(exact) - 0.5, colors=[colour], linestyles="dashed",
                          linewidth=0.8, zorder=1)
            if v.get("pose_rmse_percent"):
                ax.scatter([len(transformations) + offset], [v["pose_rmse_percent"]], marker="*", s=28,
                           color=colour, linewidths=0, zorder=3)
        for x in (len(exact) - 0.5, len(transformations) - 0.5):
            ax.axvline(x, color="0.6", linewidth=0.6)
        ax.set_xticks(range(len(columns)))
        ax.set_xticklabels(columns, rotation=40, ha="right")
        ax.set_xlim(-0.6, len(columns) - 0.4)
        ax.set_ylim(zero / 3, top)
        ax.set_title(resolution_title(n))
        ax.grid(axis="y", which="major", color="0.9", linewidth=0.6)
    for row in axes:
        row[0].set_ylabel("RMSE after alignment,\n% of the diagonal")
    axes[0][0].text(0.01, 0.01, "exact 0", transform=axes[0][0].transAxes, fontsize=7, color="0.4", va="bottom")
    handles, labels = axes[0][0].get_legend_handles_labels()
    handles.append(plt.Line2D([], [], color="0.45", linestyle="dashed"))
    labels.append(f"tolerance floor ({floor:g}%)")
    handles.append(plt.Line2D([], [], color="0.3", marker="*", linestyle="none", markersize=6))
    labels.append("pose variation (median)")
    fig.tight_layout(h_pad=0.6, w_pad=0.8)
    fig.legend(handles, labels, loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=min(len(labels), 4),
               frameon=False)
    save(fig, args.out, "invariance", args.format)


if __name__ == "__main__":
    main()
