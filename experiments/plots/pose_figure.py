#!/usr/bin/env python3
"""Draw where the pose stays for one pair of `cshapes experiment pose`, from the files it wrote into OUT.

  scripts/python.sh experiments/plots/pose_figure.py OUT [--format png|pdf|svg]

Reads OUT/pose_residuals.json (a, b, class, chosen_by, forms, titles, rms: the pair, why it was chosen, the
forms in run order and each one's pose RMS, a fraction of the mean diagonal) and OUT/pose_residuals.csv
(sample,vertex,x,y,z,part,<one column per form>: each sample of pose b at its input position and its residual
after the pair's whole-shape rigid fit, a fraction of the mean diagonal, empty where the form has none).
Draws one panel per form, the samples seen along the direction of least spread of pose b (render_mesh's pca
view), nearest on top, coloured by residual in % of the diagonal on one colour scale for every panel (up to
the 98th percentile over the methods' panels, the input left out: its residuals would darken every other
panel; larger values, most of the input's, in the top colour). A column wide for up to two forms, else a page
wide with four panels a row, at a two-column paper's text sizes; the points are rasterized in a PDF or SVG.
Writes OUT/pose_residuals.png (.pdf, .svg by --format), through a temporary file renamed at the end.
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
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from figure_style import (COLUMN_WIDTH, PAGE_WIDTH, add_format_argument, save, use_paper_style,  # noqa: E402
                          wrapped)
from render_mesh import view_frame  # noqa: E402


def read_residuals(out, forms):
    """(positions n×3, residuals n×len(forms) in %, NaN where empty)."""
    positions, residuals = [], []
    with open(os.path.join(out, "pose_residuals.csv")) as f:
        for row in csv.DictReader(f):
            positions.append([float(row[c]) for c in ("x", "y", "z")])
            residuals.append([100 * float(row[m]) if row[m] != "" else math.nan for m in forms])
    return np.array(positions, dtype=float).reshape(-1, 3), np.array(residuals, dtype=float).reshape(-1, len(forms))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out")
    add_format_argument(parser)
    args = parser.parse_args()

    with open(os.path.join(args.out, "pose_residuals.json")) as f:
        meta = json.load(f)
    forms = meta["forms"]
    titles = meta.get("titles", {})
    P, R = read_residuals(args.out, forms)
    if len(P) == 0:
        sys.exit("pose_figure.py: pose_residuals.csv has no sample")

    frame = view_frame(P, "pca")
    S = (P - P.mean(axis=0)) @ frame.T  # screen x, screen y, towards the viewer
    order = np.argsort(S[:, 2])         # far first, so the near samples are drawn on top
    # The scale is the methods' (the input's residuals are 5-10x larger and would leave every method's panel
    # in the darkest colour); the input panel saturates in the top colour.
    methods = [k for k, form in enumerate(forms) if form != "input"]
    scaled = R[:, methods] if methods else R
    finite = scaled[np.isfinite(scaled)]
    top = float(np.percentile(finite, 98)) if finite.size else 1.0
    top = top if top > 0 else 1.0

    # A column for up to two forms, else the page with up to four panels a row; text at 7-8 pt once printed.
    use_paper_style()
    cols = min(len(forms), 4)
    rows = int(math.ceil(len(forms) / cols))
    width = COLUMN_WIDTH if cols <= 2 else PAGE_WIDTH
    panel = width / cols
    span = np.ptp(S[:, :2], axis=0)
    aspect = span[1] / span[0] if span[0] > 0 else 1.0
    height = min(max(1.2, panel * aspect), 2.2 * panel) + 0.35  # the panel's title above it
    fig, axes = plt.subplots(rows, cols, figsize=(width, height * rows + 0.9), squeeze=False, layout="constrained")
    size = max(0.3, min(6.0, 2000.0 / len(P)))
    image = None
    for k, form in enumerate(forms):
        ax = axes[k // cols][k % cols]
        shown = order[np.isfinite(R[order, k])]  # a sample the form dropped has no residual
        if len(shown):
            image = ax.scatter(S[shown, 0], S[shown, 1], c=R[shown, k], cmap="viridis", vmin=0, vmax=top, s=size,
                               linewidths=0, rasterized=True)
        else:
            ax.text(0.5, 0.5, "no residual", ha="center", va="center", transform=ax.transAxes)
        rms = meta.get("rms", {}).get(form)
        title = titles.get(form, form)
        ax.set_title(wrapped(title, panel) + (f"\npose RMS {100 * rms:.2f}%" if rms is not None else ""))
        ax.set_aspect("equal")
        ax.axis("off")
    for k in range(len(forms), rows * cols):
        axes[k // cols][k % cols].axis("off")
    if image is not None:
        # Below the panels, where its label fits whatever the panels' height.
        bar = fig.colorbar(image, ax=axes.ravel().tolist(), location="bottom", shrink=0.5, aspect=40, extend="max",
                           pad=0.02)
        bar.set_label("residual, % of the diagonal")
    fig.suptitle(wrapped(f"{meta['a']} against {meta['b']} (class {meta['class']}): {meta['chosen_by']}\n"
                         f"samples of {meta['b']} coloured by their residual", width))
    save(fig, args.out, "pose_residuals", args.format)


if __name__ == "__main__":
    main()
