#!/usr/bin/env python3
"""Draw the figures of `cshapes evaluate` from the files it wrote into OUT.

  scripts/python.sh experiments/plots/evaluate_figures.py OUT [--format png|pdf|svg]

Reads OUT/pr.csv (recall, precision), OUT/metrics.json (the measures, for the legend), OUT/confusion.csv
(rows: the query's class; columns: the class of its nearest neighbour; cells: how many queries) and
OUT/matrix.csv (the distance matrix grouped by class). Writes OUT/pr.png, OUT/confusion.png and OUT/matrix.png
(.pdf or .svg by --format), each through a temporary file.
"""
import argparse
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from figure_style import add_format_argument, count_text, save  # noqa: E402


def read_rows(path):
    with open(path) as f:
        return [r for r in csv.reader(f) if r]


def input_name(out):
    """The matrix evaluated (metrics.json "input"), to name in the titles: its file name usually says the method
    and the distance (distmat's output, e.g. coulomb-hausdorff.csv)."""
    path = os.path.join(out, "metrics.json")
    if os.path.exists(path):
        with open(path) as f:
            source = json.load(f).get("input", "")
        if source:
            return os.path.basename(source)
    return ""


def titled(title, out):
    name = input_name(out)
    return f"{title}\n{name}" if name else title


def fig_pr(out, fmt):
    rows = read_rows(os.path.join(out, "pr.csv"))[1:]
    recall = [float(r[0]) for r in rows]
    precision = [float(r[1]) for r in rows]
    label = "PR curve"
    path = os.path.join(out, "metrics.json")
    if os.path.exists(path):
        with open(path) as f:
            m = json.load(f)
        if "map" in m:
            label = f"mAP {m['map']:.3f}, NN {m['nn']:.3f}, FT {m['ft']:.3f}, ST {m['st']:.3f}"
    fig, ax = plt.subplots(figsize=(5, 4.2))
    ax.plot(recall, precision, marker="o", ms=3, color="tab:red", label=label)
    ax.set_xlabel("recall")
    ax.set_ylabel("precision (interpolated)")
    ax.set_xlim(0, 1.02)
    ax.set_ylim(0, 1.02)
    ax.grid(alpha=0.3)
    ax.legend(loc="lower left", fontsize=8)
    ax.set_title(titled("precision-recall, averaged over the queries", out), fontsize=10)
    save(fig, out, "pr", fmt)


def fig_confusion(out, fmt):
    rows = read_rows(os.path.join(out, "confusion.csv"))
    classes = rows[0][1:]  # every class: a nearest neighbour may be of any
    query_classes = [r[0] for r in rows[1:]]  # the classes with queries (at least min_class_size shapes)
    C = np.array([[float(x) for x in r[1:]] for r in rows[1:]]).reshape(len(query_classes), len(classes))
    fig, ax = plt.subplots(figsize=(1.2 + 0.45 * len(classes), 1.0 + 0.45 * max(len(query_classes), 1)))
    ax.imshow(C, cmap="Blues", vmin=0)
    ax.set_xticks(range(len(classes)))
    ax.set_yticks(range(len(query_classes)))
    ax.set_xticklabels(classes, rotation=90, fontsize=8)
    ax.set_yticklabels(query_classes, fontsize=8)
    ax.set_xlabel("class of the nearest neighbour")
    ax.set_ylabel("class of the query")
    if len(classes) <= 30:
        top = C.max() if C.size else 0
        for i in range(len(query_classes)):
            for j in range(len(classes)):
                if C[i, j]:
                    ax.text(j, i, count_text(C[i, j]), ha="center", va="center", fontsize=7,
                            color="white" if C[i, j] > 0.6 * top else "black")
    ax.set_title(titled("nearest-neighbour confusion of the queries", out), fontsize=10)
    save(fig, out, "confusion", fmt)


def fig_matrix(out, fmt):
    rows = read_rows(os.path.join(out, "matrix.csv"))
    names = rows[0]
    D = np.array([[float(x) for x in r] for r in rows[1:]])
    fig, ax = plt.subplots(figsize=(5.2, 4.6))
    im = ax.imshow(D, cmap="viridis_r", interpolation="nearest")
    if len(names) <= 60:
        ax.set_xticks(range(len(names)))
        ax.set_yticks(range(len(names)))
        ax.set_xticklabels(names, rotation=90, fontsize=5)
        ax.set_yticklabels(names, fontsize=5)
    fig.colorbar(im, ax=ax, fraction=0.046, pad=0.04, label="distance (normalised, grouped by class)")
    ax.set_title(titled("distance matrix", out), fontsize=10)
    save(fig, out, "matrix", fmt)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("out")
    add_format_argument(p)
    args = p.parse_args()
    fig_confusion(args.out, args.format)
    fig_matrix(args.out, args.format)
    fig_pr(args.out, args.format)  # last: its file is the one the driver waits for


if __name__ == "__main__":
    main()
