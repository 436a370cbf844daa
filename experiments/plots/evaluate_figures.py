#!/usr/bin/env python3
"""Draw the figures of `cshapes evaluate` from the files it wrote into OUT.

  scripts/python.sh experiments/plots/evaluate_figures.py OUT [--format png|pdf|svg]

Reads OUT/pr.csv (recall, precision), OUT/metrics.json (the measures, for the legend; "title", what the matrix
is: method, distance, data; "class_blocks", the classes' rows of matrix.csv), OUT/confusion.csv (rows: the
query's class; columns: the class of its nearest neighbour; cells: how many queries) and OUT/matrix.csv (the
distance matrix grouped by class). Writes OUT/pr.FORMAT, OUT/confusion.FORMAT and OUT/matrix.FORMAT, each
through a temporary file, drawn at the width of a column of a two-column paper (3.5 in; wider only when the
classes or shapes need it), no text smaller than 7 pt, each titled with what it shows.
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
from figure_style import (COLUMN_WIDTH, PAGE_WIDTH, SMALLEST_TEXT, add_format_argument, count_text,  # noqa: E402
                          save, use_paper_style, wrapped)

# The height of a line of tick labels at the smallest text size, in inches (7 pt and a little space): rows or
# columns narrower than this cannot each have a readable label.
LABEL_PITCH = SMALLEST_TEXT * 1.3 / 72


def read_rows(path):
    with open(path) as f:
        return [r for r in csv.reader(f) if r]


def read_metrics(out):
    path = os.path.join(out, "metrics.json")
    if not os.path.exists(path):
        return {}
    with open(path) as f:
        return json.load(f)


def subject(metrics):
    """What the matrix is, as `cshapes evaluate` wrote it into metrics.json ("Coulomb, Hausdorff distance,
    tosca5k: 24 shapes, 8 classes"); a folder written before that field says it does not know."""
    title = metrics.get("title", "")
    if title:
        return title
    shapes, classes = metrics.get("shapes"), len(metrics.get("classes", {}))
    counts = f": {shapes} shapes, {classes} classes" if shapes else ""
    return "unknown method and distance" + counts


def titled(fig, kind, metrics, width):
    """The figure's title: what it draws, then what the matrix is, broken to fit the figure's width."""
    fig.suptitle(wrapped(f"{kind}\n{subject(metrics)}", width))


def fig_pr(out, fmt, metrics):
    rows = read_rows(os.path.join(out, "pr.csv"))[1:]
    recall = [float(r[0]) for r in rows]
    precision = [float(r[1]) for r in rows]
    label = "PR curve"
    if "map" in metrics:
        label = f"mAP {metrics['map']:.3f}, NN {metrics['nn']:.3f}, FT {metrics['ft']:.3f}, ST {metrics['st']:.3f}"
    fig, ax = plt.subplots(figsize=(COLUMN_WIDTH, 2.9), layout="constrained")
    ax.plot(recall, precision, marker="o", ms=2.5, color="tab:red", label=label)
    ax.set_xlabel("recall")
    ax.set_ylabel("precision (interpolated)")
    ax.set_xlim(0, 1.02)
    ax.set_ylim(0, 1.02)
    ax.grid(alpha=0.3, linewidth=0.5)
    ax.legend(loc="lower left")
    titled(fig, "Precision-recall, averaged over the queries", metrics, COLUMN_WIDTH)
    save(fig, out, "pr", fmt)


def grid_size(count, margin):
    """(figure width, cell size) in inches for `count` columns and `margin` inches beside them: a column of the
    paper, or its page when a column leaves a column of cells less room than a label needs."""
    count = max(count, 1)
    cell = min(0.3, (COLUMN_WIDTH - margin) / count)
    if cell < LABEL_PITCH:
        cell = min(0.3, (PAGE_WIDTH - margin) / count)
    return min(PAGE_WIDTH, max(COLUMN_WIDTH, margin + cell * count)), cell


def fig_confusion(out, fmt, metrics):
    rows = read_rows(os.path.join(out, "confusion.csv"))
    classes = rows[0][1:]  # every class: a nearest neighbour may be of any
    query_classes = [r[0] for r in rows[1:]]  # the classes with queries (at least min_class_size shapes)
    C = np.array([[float(x) for x in r[1:]] for r in rows[1:]]).reshape(len(query_classes), len(classes))
    longest = max((len(c) for c in classes), default=1)
    label_room = 0.35 + longest * SMALLEST_TEXT * 0.6 / 72  # axis label and the longest class name
    width, cell = grid_size(len(classes), label_room + 0.7)  # and the colour bar
    height = 0.75 + label_room + cell * max(len(query_classes), 1)
    fig, ax = plt.subplots(figsize=(width, height), layout="constrained")
    image = ax.imshow(C, cmap="Blues", vmin=0, aspect="equal")
    labelled = cell >= LABEL_PITCH
    if labelled:
        ax.set_xticks(range(len(classes)))
        ax.set_yticks(range(len(query_classes)))
        ax.set_xticklabels(classes, rotation=90)
        ax.set_yticklabels(query_classes)
    else:  # too many classes for a label each at a readable size: confusion.csv names them
        ax.set_xticks([])
        ax.set_yticks([])
    ax.tick_params(length=0)
    ax.set_xlabel("class of the nearest neighbour")
    ax.set_ylabel("class of the query")
    # Every cell says its count, 0 included, while it fits at the smallest readable size.
    widest = max((len(count_text(c)) for c in C.flat), default=1)
    if cell >= max(LABEL_PITCH, widest * SMALLEST_TEXT * 0.62 / 72):
        top = C.max() if C.size else 0
        for i in range(len(query_classes)):
            for j in range(len(classes)):
                value = C[i, j]
                colour = "white" if value > 0.6 * top else ("0.55" if value == 0 else "black")
                ax.text(j, i, count_text(value), ha="center", va="center", fontsize=SMALLEST_TEXT, color=colour)
    bar = fig.colorbar(image, ax=ax, shrink=0.9, aspect=25)
    bar.set_label("queries")
    if top_is_whole(C):
        bar.ax.yaxis.get_major_locator().set_params(integer=True)
    titled(fig, "Nearest-neighbour confusion", metrics, width)
    save(fig, out, "confusion", fmt)


def top_is_whole(C):
    return bool(C.size) and np.all(C == np.round(C))


def class_blocks(metrics, names):
    """[(class, first row, rows)] of matrix.csv: metrics.json's "class_blocks", else runs of equal class by the
    names' rule (cat0 -> cat) in a folder written before that field."""
    blocks = metrics.get("class_blocks")
    if blocks:
        return [(b["class"], b["first"], b["count"]) for b in blocks]
    result = []
    for k, name in enumerate(names):
        c = os.path.splitext(os.path.basename(name))[0].rstrip("0123456789").rstrip("_-") or name
        if result and result[-1][0] == c:
            result[-1] = (c, result[-1][1], result[-1][2] + 1)
        else:
            result.append((c, k, 1))
    return result


def fig_matrix(out, fmt, metrics):
    rows = read_rows(os.path.join(out, "matrix.csv"))
    names = rows[0]
    D = np.array([[float(x) for x in r] for r in rows[1:]])
    blocks = class_blocks(metrics, names)
    n = len(names)
    longest = max((len(s) for s in names), default=1)
    # A label per shape when each row has room for one in a column's width (about 18 shapes), else a label per
    # class at the middle of its block, on a page's width when a column's is not enough for them.
    per_shape = n * LABEL_PITCH <= COLUMN_WIDTH - 1.4
    labels = [(k, s) for k, s in enumerate(names)] if per_shape else [(f + (c - 1) / 2, cls) for cls, f, c in blocks]
    longest = max((len(text) for _, text in labels), default=1)
    label_room = 0.1 + longest * SMALLEST_TEXT * 0.6 / 72
    width = COLUMN_WIDTH
    if len(labels) * LABEL_PITCH > width - label_room - 0.9:
        width = PAGE_WIDTH
    side = min(width - label_room - 0.9, 5.0)
    fig, ax = plt.subplots(figsize=(width, side + label_room + 0.75), layout="constrained")
    image = ax.imshow(D, cmap="viridis_r", interpolation="nearest")
    if len(labels) * LABEL_PITCH <= side:
        positions, texts = zip(*labels) if labels else ([], [])
        ax.set_xticks(positions)
        ax.set_yticks(positions)
        ax.set_xticklabels(texts, rotation=90)
        ax.set_yticklabels(texts)
    else:
        ax.set_xticks([])
        ax.set_yticks([])
    ax.tick_params(length=0 if not per_shape else 2)
    # The class blocks, outlined: the retrieval is good where the blocks on the diagonal are light.
    for _, first, count in blocks[1:]:
        for line in (ax.axhline, ax.axvline):
            line(first - 0.5, color="white", linewidth=0.6)
    bar = fig.colorbar(image, ax=ax, shrink=0.9, aspect=25)
    bar.set_label("distance / largest distance")
    titled(fig, "Distance matrix, shapes grouped by class", metrics, width)
    save(fig, out, "matrix", fmt)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("out")
    add_format_argument(p)
    args = p.parse_args()
    use_paper_style()
    metrics = read_metrics(args.out)
    fig_confusion(args.out, args.format, metrics)
    fig_matrix(args.out, args.format, metrics)
    fig_pr(args.out, args.format, metrics)  # last: its file is the one the driver waits for


if __name__ == "__main__":
    main()
