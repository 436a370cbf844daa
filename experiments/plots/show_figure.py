#!/usr/bin/env python3
"""A picture of a mesh, or of a mesh and its canonical form side by side with the same colour per vertex
(`cshapes show`, experiments/show_mesh.h, which checks the files and writes the picture atomically).

  scripts/python.sh experiments/plots/show_figure.py MESH [FORM] -o PICTURE.png \
      [--title TEXT] [--view pca|x|y|z] [--label MESH_TITLE [--label FORM_TITLE]]

MESH and FORM are OFF, PLY or XYZ files (meshio.py); `cshapes show` reads every format the library reads and
hands this script binary PLY files.
A vertex is coloured by its place on MESH: its coordinates along MESH's principal axes as red, green and
blue, scaled by the largest extent (a thin axis shifts the colour little), so the same part of the body has
the same colour in the form. Rows with non-finite coordinates or valid = 0 (vertices a canonical form
dropped) are not drawn, nor are the faces that use them. PNG, PDF or SVG by extension. A panel is a column
of a two-column paper wide (3.5 in), its title in 8 pt broken into lines that fit it.
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from meshio import read_mesh  # noqa: E402
from figure_style import COLUMN_WIDTH, save_to, use_paper_style, wrapped  # noqa: E402
from render_mesh import draw_mesh  # noqa: E402


def drawn_vertices(V, props):
    """The rows to draw: finite coordinates, and valid != 0 where the file has that column."""
    keep = np.isfinite(V).all(axis=1)
    if "valid" in props:
        keep &= props["valid"] != 0
    return keep


def position_colors(V, keep):
    """n x 3 RGB in [0, 1]: the kept rows' principal coordinates, centred on grey and scaled by the largest
    extent; dropped rows are grey (never drawn)."""
    colors = np.full((len(V), 3), 0.5)
    P = V[keep] - V[keep].mean(axis=0)
    if len(P) < 2:
        return colors
    _, _, vt = np.linalg.svd(P, full_matrices=False)
    Q = P @ vt.T
    Q -= (Q.max(axis=0) + Q.min(axis=0)) / 2
    extent = max(np.ptp(Q, axis=0).max(), 1e-300)
    colors[keep] = np.clip(0.5 + 0.85 * Q / extent, 0, 1)
    return colors


def compact(V, F, keep, colors):
    """The kept vertices, the faces whose three vertices are kept (renumbered), and their colours."""
    index = np.full(len(V), -1)
    index[keep] = np.arange(keep.sum())
    F = np.asarray(F, dtype=int).reshape(-1, 3)
    F = F[keep[F].all(axis=1)] if len(F) else F
    return V[keep], index[F], colors[keep]


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("mesh")
    p.add_argument("form", nargs="?")
    p.add_argument("-o", "--output", required=True)
    p.add_argument("--title", default=None, help="a line above the picture")
    p.add_argument("--view", default="pca", choices=["pca", "x", "y", "z"])
    p.add_argument("--label", action="append", default=[], help="a panel's title (default: the file name)")
    p.add_argument("--panel-size", type=float, default=COLUMN_WIDTH, help="inches per panel")
    args = p.parse_args()
    use_paper_style()

    paths = [args.mesh] + ([args.form] if args.form else [])
    labels = args.label + [os.path.basename(path) for path in paths[len(args.label):]]
    meshes = [read_mesh(path) for path in paths]
    V, _, props = meshes[0]
    if len(meshes) > 1 and len(meshes[1][0]) != len(V):
        sys.exit(f"{args.form} has {len(meshes[1][0])} vertices but {args.mesh} has {len(V)}")
    colors = position_colors(V, drawn_vertices(V, props))

    fig, axes = plt.subplots(1, len(meshes), figsize=(args.panel_size * len(meshes), args.panel_size),
                             squeeze=False, layout="constrained")
    for ax, (V, F, props), label in zip(axes[0], meshes, labels):
        keep = drawn_vertices(V, props)
        if not keep.any():
            sys.exit(f"{label}: no vertex to draw (every row is NaN or valid = 0)")
        drawn_V, drawn_F, drawn_colors = compact(V, F, keep, colors)
        draw_mesh(ax, drawn_V, drawn_F, view=args.view, vertex_colors=drawn_colors)
        if label:
            ax.set_title(wrapped(label, args.panel_size))
    if args.title:
        fig.suptitle(wrapped(args.title, args.panel_size * len(meshes)))
    save_to(fig, args.output)


if __name__ == "__main__":
    main()
