"""What the figure scripts share: each method's name and colour, the formats a figure is written in, the sizes
of a two-column paper, and an atomic save."""
import json
import math
import os
import sys
import textwrap

import matplotlib
import matplotlib.pyplot as plt

# The formats every figure can be written in (`--figure-format`, experiments/figures.h), by extension.
FIGURE_FORMATS = ("png", "pdf", "svg")
# Text stays text: SVG keeps <text> elements (editable, searchable) instead of glyph outlines, and PDF embeds
# TrueType (Type 42) fonts, since journals' PDF checkers (IEEE PDF eXpress) refuse matplotlib's default Type 3.
# The ids and dates that would change at every save are fixed, so the same data gives the same file.
matplotlib.rcParams.update({"svg.fonttype": "none", "pdf.fonttype": 42, "ps.fonttype": 42,
                            "svg.hashsalt": "cshapes", "savefig.dpi": 150})

# A two-column paper (IEEE, ACM, Elsevier): a column is about 3.5 in wide, the page 7.16 in. A figure drawn at
# that width prints at its own size, so its text is as large as set here: 8 pt, 7 pt the smallest, as journals
# ask (at least 6-7 pt after scaling).
COLUMN_WIDTH = 3.5
PAGE_WIDTH = 7.16
SMALLEST_TEXT = 7
PAPER_STYLE = {"font.size": 8, "axes.titlesize": 8, "axes.labelsize": 8, "xtick.labelsize": SMALLEST_TEXT,
               "ytick.labelsize": SMALLEST_TEXT, "legend.fontsize": SMALLEST_TEXT, "figure.titlesize": 8,
               "axes.linewidth": 0.6, "xtick.major.width": 0.6, "ytick.major.width": 0.6,
               "lines.linewidth": 1.2, "savefig.pad_inches": 0.02, "savefig.dpi": 300}


def use_paper_style():
    """Sets the text and line sizes above (and PNG at 300 dpi, what journals ask of a raster figure) for the
    figures drawn afterwards in this process."""
    matplotlib.rcParams.update(PAPER_STYLE)


_SUPERSCRIPTS = str.maketrans("-0123456789", "\u207b\u2070\u00b9\u00b2\u00b3\u2074\u2075\u2076\u2077\u2078\u2079")


def powers_of_ten(value, _position=None):
    """A log axis's tick as 10 with its exponent in Unicode superscripts (10\u207b\u00b9\u00b3): one text at the
    tick's size, where matplotlib's mathtext draws the exponent at 70% of it (5 pt on a 7 pt tick)."""
    if value <= 0:
        return ""
    exponent = round(math.log10(value))
    if abs(math.log10(value) - exponent) > 1e-9:
        return ""
    return "1" if exponent == 0 else "10" + str(exponent).translate(_SUPERSCRIPTS)


def add_format_argument(parser):
    """--format png|pdf|svg, the format of every figure a script writes (default png)."""
    parser.add_argument("--format", choices=FIGURE_FORMATS, default="png",
                        help="png (default), pdf or svg: what a LaTeX paper includes (text kept as text)")


def wrapped(text, width_inches, points=8):
    """text broken into lines that fit width_inches at a font of `points` (about half an em a character), so
    that a long title is never cut at the figure's edge: a line too long breaks after its ": " first (what a
    thing is, then its counts), then between words."""
    characters = max(12, int(width_inches * 72 / (0.55 * points)))
    lines = []
    for line in str(text).split("\n"):
        head, colon, tail = line.partition(": ")
        parts = [head + ":", tail] if len(line) > characters and colon and tail else [line]
        lines += [textwrap.fill(part, characters) for part in parts]
    return "\n".join(lines)

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


# The date a PDF or SVG would record: none, so that the same figure gives the same bytes.
_NO_DATE = {".pdf": {"CreationDate": None}, ".svg": {"Date": None}}


def save_to(fig, path, **savefig_options):
    """Writes the figure to PATH (its format by extension: .png at savefig.dpi, .pdf or .svg as text and lines)
    through a temporary file beside it, so a killed run leaves no partial picture."""
    extension = os.path.splitext(path)[1].lower()
    tmp = path + ".tmp" + extension
    fig.savefig(tmp, metadata=_NO_DATE.get(extension), **savefig_options)
    os.replace(tmp, path)


def save(fig, out, name, fmt="png"):
    """Writes OUT/NAME.FMT (png, pdf or svg) through a temporary file, so a killed run leaves no partial
    figure."""
    if fmt not in FIGURE_FORMATS:
        raise ValueError(f"{name}: unknown figure format {fmt!r} (expected one of {', '.join(FIGURE_FORMATS)})")
    save_to(fig, os.path.join(out, f"{name}.{fmt}"), bbox_inches="tight")
    plt.close(fig)
    print(f"wrote {name}.{fmt}", file=sys.stderr)
