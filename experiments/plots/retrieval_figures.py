#!/usr/bin/env python3
"""Draw the figures of `cshapes experiment retrieval` from the retrieval.json it wrote into OUT.

  scripts/python.sh experiments/plots/retrieval_figures.py OUT [--format png|pdf|svg]

OUT/figures/pr.png: the averaged, interpolated precision-recall curves, one panel per distance (Hausdorff,
Chamfer, RMSE), one curve per method. OUT/figures/per_class.png: mAP of each class's queries under the
Hausdorff distance, the methods side by side per class. OUT/figures/confusion.png: the nearest-neighbour
confusion matrix of each method under the Hausdorff distance (rows: the query's class, as fractions of its
queries).
"""
import argparse
import json
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from figure_style import (PAGE_WIDTH, add_format_argument, count_text, method_style, method_styles,  # noqa: E402
                          save, use_paper_style, wrapped)

DISTANCE_TITLE = {"hausdorff": "Hausdorff (the paper's)", "chamfer": "Chamfer", "rmse": "RMSE"}


STYLES = {}  # set in main: figure_style's {method: (title, colour)} from the methods.json the driver wrote


def style(m, k):
    """A method's title and colour (figure_style's: one look per method in every figure); a method it does not
    know gets its retrieval.json title and the k-th colour of matplotlib's cycle."""
    title, colour = method_style(STYLES, m["method"])
    return (m.get("title", title), colour) if colour else (m.get("title", m["method"]), f"C{k % 10}")


def pr_figure(data, out, fmt):
    distances = data["distances"]
    # A page wide, text at 7-8 pt once printed.
    fig, axes = plt.subplots(1, len(distances), figsize=(PAGE_WIDTH, 2.8), squeeze=False)
    for ax, kind in zip(axes[0], distances):
        for k, m in enumerate(data["methods"]):
            d = m["distances"].get(kind)
            if not d:
                continue
            label, colour = style(m, k)
            ax.plot(d["pr"]["recall"], d["pr"]["precision"], "-o", ms=3, color=colour,
                    label=f"{label} (mAP {d['map']:.3f})")
        ax.set_title(DISTANCE_TITLE.get(kind, kind))
        ax.set_xlabel("recall")
        ax.set_xlim(0, 1)
        ax.set_ylim(0, 1.02)
        ax.grid(alpha=0.3)
        ax.legend(loc="lower left")
    axes[0][0].set_ylabel("precision (interpolated)")
    fig.suptitle(wrapped(f"Leave-one-out retrieval, {data['shapes']} shapes in {len(data['classes'])} classes",
                         PAGE_WIDTH))
    fig.tight_layout()
    save(fig, out, "pr", fmt)


def per_class_figure(data, out, fmt):
    classes = data["classes"]
    methods = data["methods"]
    width = 0.8 / max(1, len(methods))
    fig, ax = plt.subplots(figsize=(PAGE_WIDTH, 2.6))
    x = np.arange(len(classes))
    for k, m in enumerate(methods):
        d = m["distances"].get("hausdorff")
        if not d:
            continue
        per = d["classes"]
        values = [per.get(c, {}).get("map", np.nan) for c in classes]
        label, colour = style(m, k)
        ax.bar(x + (k - (len(methods) - 1) / 2) * width, values, width, color=colour, label=label)
    ax.set_xticks(x)
    ax.set_xticklabels(classes, rotation=45 if len(classes) > 8 else 0, ha="right" if len(classes) > 8 else "center")
    ax.set_ylabel("mAP of the class's queries")
    ax.set_ylim(0, 1.05)
    ax.set_title("Per-class mean average precision (Hausdorff distance)")
    ax.grid(axis="y", alpha=0.3)
    # Below the axes: no bar hidden.
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.25 if len(classes) > 8 else -0.12),
              ncol=min(len(methods), 6), frameon=False)
    save(fig, out, "per_class", fmt)


def confusion_figure(data, out, fmt):
    methods = [m for m in data["methods"] if "hausdorff" in m["distances"]]
    if not methods:
        return
    n = len(methods)
    classes = max(len(m["distances"]["hausdorff"]["class_names"]) for m in methods)
    # A page wide: three panels a row, two when there are many classes.
    cols = min(n, 3 if classes <= 12 else 2)
    rows = (n + cols - 1) // cols
    panel = min(2.9, (PAGE_WIDTH - 0.6) / cols)  # one method: a column's width, not a page's
    fig, axes = plt.subplots(rows, cols, figsize=(panel * cols + 0.6, panel * rows + 0.6), squeeze=False)
    for ax in axes.flat[n:]:
        ax.axis("off")
    cell = panel * 72 / max(1, classes)  # points per row
    for ax, m in zip(axes.flat, methods):
        d = m["distances"]["hausdorff"]
        names = d["class_names"]
        counts = np.array(d["confusion"], dtype=float)
        rows = counts.sum(axis=1, keepdims=True)
        share = np.divide(counts, rows, out=np.zeros_like(counts), where=rows > 0)
        ax.imshow(share, vmin=0, vmax=1, cmap="Blues")
        for a in range(len(names)):
            for b in range(len(names)):
                if counts[a, b] and cell >= 12:  # a count where it fits at 7 pt
                    ax.text(b, a, count_text(counts[a, b]), ha="center", va="center", fontsize=7,
                            color="white" if share[a, b] > 0.5 else "black")
        ax.set_xticks(range(len(names)))
        ax.set_yticks(range(len(names)))
        # The classes' names while they fit at 7 pt, none otherwise (the colours still show the diagonal).
        ax.set_xticklabels(names if cell >= 8 else [], rotation=90)
        ax.set_yticklabels(names if cell >= 8 else [])
        ax.set_xlabel("class of the nearest neighbour")
        ax.set_title(f"{style(m, 0)[0]}: NN {d['nn']:.3f}")
    for row in axes:
        row[0].set_ylabel("class of the query")
    save(fig, out, "confusion", fmt)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("out")
    add_format_argument(p)
    args = p.parse_args()
    use_paper_style()
    with open(os.path.join(args.out, "retrieval.json")) as f:
        data = json.load(f)
    figures = os.path.join(args.out, "figures")
    os.makedirs(figures, exist_ok=True)
    STYLES.update(method_styles(figures))
    per_class_figure(data, figures, args.format)
    confusion_figure(data, figures, args.format)
    pr_figure(data, figures, args.format)  # last: its file is the one the driver waits for


if __name__ == "__main__":
    main()
