"""The five-minute tour of cshapes from Python: two poses of a shape and a pose with topological noise,
their Coulomb canonical forms, aligned by ICP and plotted.

    PYTHONPATH=build/python /usr/bin/python3 examples/tour.py [-o tour.png]

(after `cmake --install build`, plain `/usr/bin/python3 examples/tour.py`). Runs in about ten seconds.
"""
import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import cshapes  # noqa: E402

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("-o", "--output", default="tour.png", help="the picture (PNG, PDF or SVG)")
args = parser.parse_args()

# Two poses of a synthetic hand (same vertex order), and the second with fingers glued at two places.
(V0, F0), (V1, F1) = cshapes.generate("articulated", class_="hand", poses=2, vertices=3000, seed=7)
V2, F2, glue = cshapes.add_topological_noise(V1, F1, glue=2, seed=1, return_info=True)
shapes = [(V0, F0, "pose A"), (V1, F1, "pose B"), (V2, F2, "pose B, glued twice")]

# Coulomb canonical forms (the paper's §2), each aligned onto the first by ICP.
forms = [cshapes.coulomb(V, F) for V, F, _ in shapes]
alignments = [cshapes.icp(f.X, forms[0].X) for f in forms[1:]]
aligned = [forms[0].X] + [a.aligned for a in alignments]
# canonical forms are defined up to a reflection too: a mirrored form's triangles turn inside out
flipped = [False] + [a.reflection for a in alignments]
# distances in % of the bounding-box diagonal of A's form: comparable across shapes of any size
diagonal = np.linalg.norm(np.ptp(forms[0].X, axis=0))
for (_, _, name), form in zip(shapes, forms):
    d = cshapes.shape_distance(form.X, forms[0].X)
    print(f"{name:22s} {form.iterations:4d} iterations, {form.seconds:5.2f} s, "
          f"distance to A's form {d:.4f} ({100 * d / diagonal:.2f}% of its bounding-box diagonal)")

fig = plt.figure(figsize=(12, 7))
glued = np.unique(np.array(glue["pairs"]).ravel())
for column, ((V, F, name), X, flip) in enumerate(zip(shapes, aligned, flipped)):
    for row, (P, T, title) in enumerate([(V, F, name), (X, F[:, ::-1] if flip else F, "its Coulomb form")]):
        ax = fig.add_subplot(2, 3, 1 + column + 3 * row, projection="3d")
        ax.computed_zorder = False  # the glued spots are drawn over the surface
        ax.plot_trisurf(P[:, 0], P[:, 1], P[:, 2], triangles=T, color="#9bb7d4", edgecolor="none",
                        linewidth=0, shade=True)
        if column == 2:
            ax.scatter(*P[glued].T, color="#d62728", s=40, depthshade=False, zorder=3)
        ax.set_title(title, fontsize=11)
        ax.set_box_aspect(np.ptp(P, axis=0), zoom=1.3)
        ax.set_axis_off()
        ax.view_init(elev=55, azim=-75)
fig.suptitle("Poses and topological noise (red: glued spots) and their aligned Coulomb canonical forms")
fig.subplots_adjust(left=0, right=1, bottom=0, top=0.92, wspace=0, hspace=0.05)
fig.savefig(args.output, dpi=100)
print("wrote", args.output)
