#!/usr/bin/env python3
"""Checks that keep the results pages current and consistent with the README.

  scripts/check_pages.py history [--max PERCENT] PAGE...
      The share of a page set's words that sit in dated or history text: a paragraph, list item or table row
      that names a date, a commit, or what was measured before ("previous defaults", "re-measured", "until",
      ...). History belongs in docs/changelog.md; a results page holds the current results. Prints each
      page's share and the flagged blocks, and fails when the pages together exceed --max (default 5).
  scripts/check_pages.py results PAGE...
      The same check on the pages of mkdocs.yml's "Results" section when no PAGE is given.
  scripts/check_pages.py readme-table README.md RESULTS.md
      The README's "Results at a glance" table must appear in RESULTS.md row for row (same header, same
      cells), so the two pages cannot give two numbers for one fact.

Standard library only.
"""
import os
import re
import sys

# What marks a block as history: a date, a commit hash, or words that compare with an earlier state.
HISTORY = [
    r"\b20\d\d-\d\d-\d\d\b",
    r"`[0-9a-f]{7,40}`",
    r"\bcommit [0-9a-f]{7,40}\b",
    r"\bprevious(ly)? (defaults?|runs?|version|code|build|binary)\b",
    r"\bold (defaults?|rule|code|run)\b",
    r"\bre-?measured\b",
    r"\bre-?run (on|after|with)\b",
    r"\bearlier (runs?|pass|version|code)\b",
    r"\buntil (the|it|we|a|this)\b",
    r"\bused to\b(?! (choose|tune|judge|measure|make|compute|pick))",
    r"\bno longer\b",
    r"\b(before|after) the (change|fix)\b",
    r"\bchanged on\b",
    r"\b(issue|issues) \d+\b",
    r"\bthis session\b",
    r"\b(on|measured) a (slower|faster|busier|quieter) day\b",
    r"\bwas (fixed|changed|replaced|removed)\b",
]
HISTORY_RE = re.compile("|".join(HISTORY), re.IGNORECASE)


def blocks(markdown):
    """Paragraphs, list items and table rows of a page, with their words; fenced code is left out."""
    out, current, fenced = [], [], False

    def flush():
        if current:
            out.append(" ".join(current))
            current.clear()

    for line in markdown.splitlines():
        stripped = line.strip()
        if stripped.startswith("```"):
            flush()
            fenced = not fenced
            continue
        if fenced:
            continue
        if not stripped:
            flush()
        elif stripped.startswith("|"):
            flush()
            if not re.fullmatch(r"\|[\s:|-]+\|", stripped):
                out.append(stripped)
        elif re.match(r"([-*]|\d+\.)\s", stripped) or stripped.startswith("#"):
            flush()
            current.append(stripped)
        else:
            current.append(stripped)
    flush()
    return out


def words(text):
    return len(re.findall(r"\w+", text))


def history_share(pages, limit, quiet=False):
    total = flagged = 0
    for page in pages:
        with open(page) as f:
            page_blocks = blocks(f.read())
        page_total = sum(words(b) for b in page_blocks)
        hits = [b for b in page_blocks if HISTORY_RE.search(b)]
        page_flagged = sum(words(b) for b in hits)
        total += page_total
        flagged += page_flagged
        share = 100.0 * page_flagged / max(page_total, 1)
        print(f"{page}: {page_flagged} of {page_total} words in dated or history text ({share:.1f}%)")
        if not quiet:
            for b in hits:
                print(f"    [{HISTORY_RE.search(b).group(0)}] {b[:160]}")
    share = 100.0 * flagged / max(total, 1)
    print(f"together: {flagged} of {total} words ({share:.1f}%); the limit is {limit:g}%")
    if share >= limit:
        print("history belongs in docs/changelog.md; the results pages hold the current results", file=sys.stderr)
        return 1
    return 0


def results_pages(mkdocs_yml):
    """The pages listed under the nav's "Results" section of mkdocs.yml."""
    pages, inside, indent = [], False, None
    docs_dir = os.path.join(os.path.dirname(mkdocs_yml), "docs")
    with open(mkdocs_yml) as f:
        for line in f:
            if re.match(r"\s*-\s*Results:\s*$", line):
                inside, indent = True, len(line) - len(line.lstrip())
                continue
            if inside:
                depth = len(line) - len(line.lstrip())
                if line.strip() and depth <= indent:
                    break
                m = re.match(r"\s*-\s*[^:]+:\s*(\S+\.md)\s*$", line)
                if m:
                    pages.append(os.path.join(docs_dir, m.group(1)))
    return pages


def tables(markdown):
    """Every table of a page as a list of rows, each a list of stripped cells (the separator row left out)."""
    out, current = [], []
    for line in markdown.splitlines() + [""]:
        stripped = line.strip()
        if stripped.startswith("|"):
            if not re.fullmatch(r"\|[\s:|-]+\|", stripped):
                current.append([c.strip() for c in stripped.strip("|").split("|")])
        elif current:
            out.append(current)
            current = []
    return out


def readme_table(readme, results):
    with open(readme) as f:
        text = f.read()
    at = text.find("## Results at a glance")
    if at < 0:
        print(f"{readme}: no section '## Results at a glance'", file=sys.stderr)
        return 1
    glance = tables(text[at:])
    if not glance:
        print(f"{readme}: the section 'Results at a glance' has no table", file=sys.stderr)
        return 1
    wanted = glance[0]
    with open(results) as f:
        candidates = [t for t in tables(f.read()) if t and t[0] == wanted[0]]
    if not candidates:
        print(f"{results}: no table with the README's header {wanted[0]}", file=sys.stderr)
        return 1
    have = candidates[0]
    problems = []
    rows = {r[0]: r for r in have[1:]}
    for row in wanted[1:]:
        other = rows.get(row[0])
        if other is None:
            problems.append(f"row '{row[0]}' is in {readme} but not in {results}")
        elif other != row:
            diff = [f"{h}: README {a!r}, results {b!r}" for h, a, b in zip(wanted[0], row, other) if a != b]
            problems.append(f"row '{row[0]}' differs: " + "; ".join(diff))
    for name in rows:
        if name not in {r[0] for r in wanted[1:]}:
            problems.append(f"row '{name}' is in {results} but not in {readme}")
    for p in problems:
        print(p, file=sys.stderr)
    if problems:
        return 1
    print(f"{readme}'s results table is {results}'s, row for row ({len(wanted) - 1} rows)")
    return 0


def main(argv):
    if len(argv) >= 2 and argv[1] in ("history", "results"):
        args = argv[2:]
        limit = 5.0
        if len(args) >= 2 and args[0] == "--max":
            limit, args = float(args[1]), args[2:]
        if argv[1] == "results" and not args:
            root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
            args = results_pages(os.path.join(root, "mkdocs.yml"))
        if not args:
            print(__doc__, file=sys.stderr)
            return 2
        return history_share(args, limit)
    if len(argv) == 4 and argv[1] == "readme-table":
        return readme_table(argv[2], argv[3])
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
