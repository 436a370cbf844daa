#!/usr/bin/env python3
"""Draw the figure of `cshapes compare` from the compare.json it wrote into OUT.

  scripts/python.sh experiments/plots/compare_figure.py OUT [--format png|pdf|svg]

OUT/pr.png: the averaged, interpolated precision-recall curves of every method of the compared runs, one panel
per distance: retrieval_figures.py's PR figure, so a merged figure looks as each run's own.
"""
import argparse
import json
import os

import retrieval_figures
from figure_style import add_format_argument, method_styles, use_paper_style


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("out")
    add_format_argument(p)
    args = p.parse_args()
    with open(os.path.join(args.out, "compare.json")) as f:
        data = json.load(f)
    use_paper_style()
    retrieval_figures.STYLES.update(method_styles(args.out))
    retrieval_figures.pr_figure(data, args.out, args.format)


if __name__ == "__main__":
    main()
