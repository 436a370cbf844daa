"""What the figure scripts share: each method's name and colour, and an atomic save."""
import json
import os
import sys

import matplotlib.pyplot as plt

# Colours of the methods, fixed so a method looks the same in every figure; a method without one here (added
# later) takes the next of EXTRA_COLOURS in registration order.
COLOURS = {"inputs": "0.45", "coulomb": "tab:red", "cmds": "tab:blue", "smacof": "tab:green",
           "lbo": "tab:purple", "diffusion": "tab:orange", "spectral-mds": "tab:brown"}
EXTRA_COLOURS = ["tab:pink", "tab:olive", "tab:cyan", "black", "tab:gray"]
# Titles when OUT has no methods.json (a folder written before it existed); the library's titles otherwise.
DEFAULT_TITLES = {"inputs": "inputs (no canonical form)", "coulomb": "Coulomb", "cmds": "classical MDS",
                  "smacof": "SMACOF", "lbo": "LBO eigenmap", "diffusion": "diffusion map",
                  "spectral-mds": "spectral MDS"}


def count_text(count):
    """A whole count as such; a share (a query's tied nearest neighbours count 1/n each) with two decimals."""
    return f"{count:.0f}" if count == int(count) else f"{count:.2f}"


def method_styles(out):
    """{method: (title, colour)} for every method named in OUT/methods.json (written by the C++ driver from the
    method registry: the one name of each method in tables and figures), plus the defaults above."""
    titles = dict(DEFAULT_TITLES)
    path = os.path.join(out, "methods.json")
    if os.path.exists(path):
        with open(path) as f:
            titles.update(json.load(f))
    styles, extra = {}, iter(EXTRA_COLOURS)
    for m, title in titles.items():
        styles[m] = (title, COLOURS.get(m) or next(extra, None))
    return styles


def method_style(styles, m):
    """(title, colour) of method m; (m, None) for a name no one registered."""
    return styles.get(m, (m, None))


def save_to(fig, path, **savefig_options):
    """Writes the figure to PATH (its format by extension) through a temporary file beside it, so a killed run
    leaves no partial picture."""
    tmp = path + ".tmp" + os.path.splitext(path)[1]
    fig.savefig(tmp, dpi=150, **savefig_options)
    os.replace(tmp, path)


def save(fig, out, name, pdf):
    """Writes OUT/NAME.png (and .pdf) through a temporary file, so a killed run leaves no partial figure."""
    for ext in ["png"] + (["pdf"] if pdf else []):
        save_to(fig, os.path.join(out, f"{name}.{ext}"), bbox_inches="tight")
    plt.close(fig)
    print(f"wrote {name}.png", file=sys.stderr)
