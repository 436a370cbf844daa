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
panel; larger values, most of the input's, in the top colour). Writes OUT/pose_residuals.png
(.pdf, .svg by --format), through a temporary file renamed at the end.
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
from figure_style import add_format_argument, save  # noqa: E402
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

    cols = min(len(forms), 4)
    rows = int(math.ceil(len(forms) / cols))
    span = np.ptp(S[:, :2], axis=0)
    aspect = span[1] / span[0] if span[0] > 0 else 1.0
    width = 3.2
    fig, axes = plt.subplots(rows, cols, figsize=(width * cols + 0.8, max(2.5, width * aspect) * rows + 0.9),
                             squeeze=False)
    size = max(1.0, min(12.0, 6000.0 / len(P)))
    image = None
    for k, form in enumerate(forms):
        ax = axes[k // cols][k % cols]
        shown = order[np.isfinite(R[order, k])]  # a sample the form dropped has no residual
        if len(shown):
            image = ax.scatter(S[shown, 0], S[shown, 1], c=R[shown, k], cmap="viridis", vmin=0, vmax=top, s=size,
                               linewidths=0)
        else:
            ax.text(0.5, 0.5, "no residual", ha="center", va="center", transform=ax.transAxes)
        rms = meta.get("rms", {}).get(form)
        title = titles.get(form, form)
        ax.set_title(title + (f"\npose RMS {100 * rms:.2f}%" if rms is not None else ""), fontsize=9)
        ax.set_aspect("equal")
        ax.axis("off")
    for k in range(len(forms), rows * cols):
        axes[k // cols][k % cols].axis("off")
    if image is not None:
        bar = fig.colorbar(image, ax=axes.ravel().tolist(), shrink=0.8, extend="max")
        bar.set_label("residual, % of the diagonal")
    fig.suptitle(f"{meta['a']} against {meta['b']} (class {meta['class']}): {meta['chosen_by']}\n"
                 f"samples of {meta['b']} coloured by their residual", fontsize=10)
    save(fig, args.out, "pose_residuals", args.format)


if __name__ == "__main__":
    main()
