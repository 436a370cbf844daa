"""What the figure scripts share: each method's name and colour, and an atomic save."""
import os
import sys

import matplotlib.pyplot as plt

METHOD_STYLE = {"coulomb": ("Coulomb", "tab:red"), "cmds": ("classical MDS", "tab:blue"),
                "smacof": ("SMACOF MDS", "tab:green")}


def save(fig, out, name, pdf):
    """Writes OUT/NAME.png (and .pdf) through a temporary file, so a killed run leaves no partial figure."""
    for ext in ["png"] + (["pdf"] if pdf else []):
        path = os.path.join(out, f"{name}.{ext}")
        tmp = path + ".tmp." + ext
        fig.savefig(tmp, dpi=150, bbox_inches="tight")
        os.replace(tmp, path)
    plt.close(fig)
    print(f"wrote {name}.png", file=sys.stderr)
