#!/usr/bin/env python3
"""Render meshes as shaded surfaces (PNG, or PDF by extension), side by side, flagged vertices in red.

  scripts/python.sh experiments/plots/render_mesh.py a.off b.ply -o out.png \
      [--titles "clean,noisy"] [--red-property torn] [--red-json 1=pairs.json] [--view pca|x|y|z]

--red-property NAME  faces touching a vertex whose PLY property NAME is > 0.5 are red (e.g. `torn`); red faces
                     stretched beyond 4x the median edge (opened by a tear) are not drawn.
--red-json K=FILE    red vertices of mesh K (0-based) from a JSON file: every integer found in it is a
                     vertex index (e.g. the glued pairs written by `cshapes noise`).
--view               pca (default): look along the direction of least spread, the longest extent horizontal;
                     x|y|z: look along that axis (for shapes with a meaningful original orientation).
Also importable: draw_mesh(ax, V, F, red=None, title=None, view="pca", vertex_colors=None).
"""
import argparse
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from figure_style import save_to  # noqa: E402
from meshio import read_mesh  # noqa: E402


def view_frame(V, view="pca"):
    """Rotation whose rows are screen-right, screen-up and towards-viewer directions."""
    C = V - V.mean(axis=0)
    if view == "pca":
        _, _, vt = np.linalg.svd(C, full_matrices=False)
        R = vt.copy()
        # Fix each axis' sign by the third moment so that similar shapes get similar views; on the vertical
        # axis thin parts (legs, the long tail of the distribution) point down.
        for k in range(3):
            if (np.mean((C @ R[k]) ** 3) < 0) != (k == 1):
                R[k] = -R[k]
        if np.linalg.det(R) < 0:
            R[2] = -R[2]
    else:
        axis = "xyz".index(view)
        others = [k for k in range(3) if k != axis]
        R = np.eye(3)[[others[0], others[1], axis]]
    # A slight oblique tilt shows depth.
    a, b = np.radians(25), np.radians(20)
    tilt_y = np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])
    tilt_x = np.array([[1, 0, 0], [0, np.cos(b), -np.sin(b)], [0, np.sin(b), np.cos(b)]])
    return tilt_x @ tilt_y @ R


def draw_mesh(ax, V, F, red=None, title=None, view="pca", base_color=(0.62, 0.72, 0.86), vertex_colors=None):
    """vertex_colors: n x 3 RGB in [0, 1], one per vertex (a face takes its vertices' mean) instead of
    base_color."""
    V = np.asarray(V, dtype=float)
    if vertex_colors is not None:
        vertex_colors = np.asarray(vertex_colors, dtype=float).reshape(len(V), 3)
    P = (V - V.mean(axis=0)) @ view_frame(V, view).T
    ax.set_aspect("equal")
    ax.axis("off")
    if title:
        ax.set_title(title, fontsize=10)
    if len(F) == 0:  # point cloud
        order = np.argsort(P[:, 2])
        colors = np.tile(base_color, (len(P), 1)) if vertex_colors is None else vertex_colors.copy()
        if red is not None:
            colors[np.asarray(red, bool)] = (0.85, 0.1, 0.1)
        ax.scatter(P[order, 0], P[order, 1], s=2, c=colors[order], linewidths=0, rasterized=True)
        return
    F = np.asarray(F)
    if red is not None:
        # A torn edge no longer holds its face together: the face stretches with the tear and would render as a
        # long sliver across the picture. Red faces with an edge over 4x the median edge are not drawn.
        red = np.asarray(red, bool)
        E = V[F]
        longest = np.max(np.linalg.norm(E - np.roll(E, 1, axis=1), axis=2), axis=1)
        F = F[~(red[F].any(axis=1) & (longest > 4 * np.median(longest)))]
    tri = P[F]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True) + 1e-300
    light = np.array([0.3, 0.5, 1.0])
    light /= np.linalg.norm(light)
    # Two-sided Lambert shading: canonical forms may be reflected, so the orientation of faces is not trusted.
    shade = 0.25 + 0.75 * np.abs(normals @ light)
    if vertex_colors is None:
        color = np.tile(np.array(base_color), (len(F), 1))
    else:
        color = vertex_colors[F].mean(axis=1)
    if red is not None:
        color[red[F].any(axis=1)] = (0.9, 0.1, 0.1)
    color = np.clip(color * shade[:, None], 0, 1)
    order = np.argsort(tri[:, :, 2].mean(axis=1))  # painter's algorithm: far to near
    # Rasterized in a PDF or SVG (at savefig.dpi): tens of thousands of faces as vector paths make files of
    # megabytes that viewers draw slowly; titles and labels stay text.
    ax.add_collection(PolyCollection(tri[order, :, :2], facecolors=color[order], edgecolors="none",
                                     antialiaseds=False, rasterized=True))
    if red is not None and 0 < red.sum() <= 64:  # a few marked vertices: make them visible as dots
        ax.scatter(P[red, 0], P[red, 1], s=18, c="red", edgecolors="white", linewidths=0.5, zorder=3)
    lo, hi = P[:, :2].min(axis=0), P[:, :2].max(axis=0)
    pad = 0.03 * (hi - lo).max()
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)


def integers_in(obj):
    if isinstance(obj, bool):
        return []
    if isinstance(obj, int):
        return [obj]
    if isinstance(obj, dict):
        return [i for v in obj.values() for i in integers_in(v)]
    if isinstance(obj, list):
        return [i for v in obj for i in integers_in(v)]
    return []


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("meshes", nargs="+")
    p.add_argument("-o", "--output", required=True)
    p.add_argument("--titles", default=None, help="comma-separated panel titles")
    p.add_argument("--red-property", default=None)
    p.add_argument("--red-json", action="append", default=[], metavar="K=FILE")
    p.add_argument("--view", default="pca", choices=["pca", "x", "y", "z"])
    p.add_argument("--columns", type=int, default=0, help="panels per row (default: all in one row)")
    p.add_argument("--panel-size", type=float, default=3.2, help="inches per panel")
    args = p.parse_args()

    titles = args.titles.split(",") if args.titles else [os.path.basename(m) for m in args.meshes]
    red_json = {}
    for spec in args.red_json:
        k, _, path = spec.partition("=")
        with open(path) as f:
            red_json[int(k)] = integers_in(json.load(f))
    n = len(args.meshes)
    cols = args.columns or n
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(args.panel_size * cols, args.panel_size * rows), squeeze=False)
    for k, path in enumerate(args.meshes):
        V, F, props = read_mesh(path)
        red = np.zeros(len(V), bool)
        if args.red_property and args.red_property in props:
            red |= props[args.red_property] > 0.5
        for i in red_json.get(k, []):
            if 0 <= i < len(V):
                red[i] = True
        draw_mesh(axes[k // cols][k % cols], V, F, red if red.any() else None,
                  titles[k] if k < len(titles) else None, args.view)
    for k in range(n, rows * cols):
        axes[k // cols][k % cols].axis("off")
    fig.tight_layout()
    save_to(fig, args.output)


if __name__ == "__main__":
    main()
