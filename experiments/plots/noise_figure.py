#!/usr/bin/env python3
"""Draw noise.png of `cshapes experiment noise` from the noise.json it wrote into OUT.

  scripts/python.sh experiments/plots/noise_figure.py OUT [--format png|pdf|svg]

Three panels against the number of glues per shape: mAP of noisy queries among clean shapes under the
paper's Hausdorff distance; the same under Chamfer (dashed) and RMSE (dotted); and the median (solid) and mean
(dashed) RMS distance between each glued pose's canonical form and its clean pose's form (% of the bbox
diagonal). One colour and marker per method, the methods drawn side by side around each level; the levels
are equally spaced, and a level that not every pose could reach says how many it has; one that fewer than
half of the poses reached is drawn as lone hollow markers. The paper's claim predicts flat Coulomb curves and falling mAP /
growing distance for MDS.
"""
import argparse
import json
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

from figure_style import (PAGE_WIDTH, add_format_argument, method_style, method_styles, save,  # noqa: E402
                          use_paper_style, wrapped)

METHOD_MARKER = {"coulomb": "o", "cmds": "s", "smacof": "^", "lbo": "D", "diffusion": "v", "spectral-mds": "P"}
DISTANCE_STYLE = {"hausdorff": ("Hausdorff", "-"), "chamfer": ("Chamfer", "--"), "rmse": ("RMSE", ":")}


def series(rows, method, distance, key, few=False):
    """Levels and values of one curve; levels where nothing was measured (null: no pose glued that often)
    are left out. The curve holds the levels that at least half of the poses reached (FEW_POSES); few=True
    gives the others, drawn as lone hollow markers (a level of one or two poses shows no trend)."""
    sel = sorted((r for r in rows if r["method"] == method and r["distance"] == distance
                  and r.get(key) is not None and FEW_POSES(r) == few), key=lambda r: r["level"])
    return [r["level"] for r in sel], [r[key] for r in sel], [r["queries"] for r in sel]


FEW_POSES = None  # set in main: row -> True when fewer than half of the poses were measured at its level


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("out")
    add_format_argument(p)
    args = p.parse_args()
    with open(os.path.join(args.out, "noise.json")) as f:
        data = json.load(f)
    rows = data["rows"]
    levels = data["levels"]
    methods = data["methods"]
    n_poses = len(data.get("poses", []))
    global FEW_POSES
    FEW_POSES = lambda r: 2 * r["form_poses"] < n_poses  # noqa: E731

    use_paper_style()
    fig, axes = plt.subplots(1, 3, figsize=(PAGE_WIDTH, 2.7))
    ax_h, ax_other, ax_form = axes
    # The levels equally spaced (0, 1, 2, 4, 8 read as steps), the methods side by side around each one (equal
    # values would hide each other's curves).
    position = {L: i for i, L in enumerate(levels)}
    styles = method_styles(args.out)
    for k, m in enumerate(methods):
        label, color = method_style(styles, m)
        marker = METHOD_MARKER.get(m, "o")
        shift = (k - (len(methods) - 1) / 2) * 0.06

        def xs(x):
            return [position[v] + shift for v in x]

        x, y, q = series(rows, m, "hausdorff", "map")
        ax_h.plot(xs(x), y, "-", marker=marker, ms=4, color=color, label=label)
        for d in ("chamfer", "rmse"):
            x, y, _ = series(rows, m, d, "map")
            ax_other.plot(xs(x), y, DISTANCE_STYLE[d][1], marker=marker, ms=3, color=color)
        x, med, _ = series(rows, m, "hausdorff", "form_rms_median")
        _, mean, _ = series(rows, m, "hausdorff", "form_rms_mean")
        ax_form.plot(xs(x), [100 * v for v in med], "-", marker=marker, ms=4, color=color)
        ax_form.plot(xs(x), [100 * v for v in mean], "--", marker=marker, ms=3, mfc="none", color=color, lw=1)
        # Levels fewer than half of the poses reached: lone hollow markers, not joined to the curves.
        x, y, _ = series(rows, m, "hausdorff", "map", few=True)
        ax_h.plot(xs(x), y, ls="none", marker=marker, ms=4, mfc="none", color=color)
        for d in ("chamfer", "rmse"):
            x, y, _ = series(rows, m, d, "map", few=True)
            ax_other.plot(xs(x), y, ls="none", marker=marker, ms=3, mfc="none", color=color)
        x, med, _ = series(rows, m, "hausdorff", "form_rms_median", few=True)
        ax_form.plot(xs(x), [100 * v for v in med], ls="none", marker=marker, ms=4, mfc="none", color=color)
    queries = sorted({r["queries"] for r in rows if r["queries"] > 0}) or [0]
    for ax in (ax_h, ax_other):
        ax.set_ylim(0, 1.02)
    ax_h.set_ylabel("mAP of the noisy queries")
    ax_h.set_title("retrieval, Hausdorff (the paper's)")
    ax_other.set_title("retrieval, Chamfer and RMSE")
    ax_form.set_title("glued vs clean form")
    ax_form.set_ylabel("RMS after rigid fit, % of diag.")
    ax_form.set_ylim(bottom=0)
    # Under each level: how many poses could be glued that often (a level with fewer is another set).
    measured = {r["level"]: r["form_poses"] for r in rows if r["method"] == methods[0]
                and r["distance"] == "hausdorff"}
    labels = [f"{L}" if measured.get(L, 0) == n_poses else f"{L}\n{measured.get(L, 0)}/{n_poses}"
              for L in levels]
    for ax in axes:
        ax.set_xlabel("glues per shape")
        ax.set_xticks(range(len(levels)))
        ax.set_xlim(-0.4, len(levels) - 0.6)
        ax.set_xticklabels(labels)
        ax.grid(alpha=0.3)
    # Line styles in black, one small key per panel that uses them; the methods' colours in one key below all
    # three panels (a legend per panel of 12 entries covered the curves and read at 7 pt).
    for ax, keys in ((ax_other, [("Chamfer", "--"), ("RMSE", ":")]), (ax_form, [("median", "-"), ("mean", "--")])):
        ax.legend(handles=[Line2D([], [], color="black", ls=ls, label=text) for text, ls in keys],
                  handlelength=2.5, loc="best")
    handles = [Line2D([], [], color=method_style(styles, m)[1], marker=METHOD_MARKER.get(m, "o"), ms=4,
                      label=method_style(styles, m)[0]) for m in methods]
    fig.legend(handles=handles, loc="lower center", ncol=min(len(methods), 6), frameon=False,
               bbox_to_anchor=(0.5, -0.01))
    q_text = f"{queries[0]}" if len(queries) == 1 else f"{queries[0]}–{queries[-1]}"
    few = any(FEW_POSES(r) and r["form_poses"] > 0 for r in rows)
    name = os.path.basename(os.path.normpath(data["data"])) + ", " if data.get("data") else ""
    fig.suptitle(wrapped(f"Topological noise: {name}{n_poses} poses, {q_text} queries per level, seed "
                         f"{data.get('seed')}; under a level: the poses glued so often"
                         + ("; hollow markers: levels fewer than half of the poses reached" if few else ""),
                         PAGE_WIDTH))
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    save(fig, args.out, "noise", args.format)


if __name__ == "__main__":
    main()
