#!/usr/bin/env python3
"""The size of the code, per folder: its largest file and its longest function, and how many exceed the
limits of docs/contributing.md (functions of more than 100 lines, files of more than 600).

    scripts/code_sizes.py [--limits] [FOLDER ...]

Functions are those Universal Ctags (Debian's `universal-ctags`) finds in C++ files (.h, .cpp, .inl),
lambdas excluded (they are counted in the function that holds them), from the line of the name to the
closing brace. Default folders: the library rooms and the two skins. --limits: list every function and file
over the limits, and exit 1 if there is one.
"""
import json
import os
import subprocess
import sys

ROOMS = ["support", "mesh", "operators", "geodesics", "data", "canon", "matching", "eval", "pipeline",
         "experiments", "cli", "python"]
FUNCTION_LIMIT, FILE_LIMIT = 100, 600


def functions(paths):
    try:
        version = subprocess.run(["ctags", "--version"], capture_output=True, text=True).stdout
    except FileNotFoundError:
        version = ""
    if "Universal Ctags" not in version:
        sys.exit("code_sizes.py: needs Universal Ctags as `ctags` (Debian: apt-get install universal-ctags; "
                 "scripts/install-deps.sh installs it)")
    out = subprocess.run(["ctags", "--output-format=json", "--fields=+ne", "--kinds-C++=f", "--languages=C++",
                          "--map-C++=+.inl", "-o", "-"] + paths, capture_output=True, text=True, check=True)
    for line in out.stdout.splitlines():
        tag = json.loads(line)
        if tag.get("_type") != "tag" or "end" not in tag or tag["name"].startswith("__anon"):
            continue
        scope = tag.get("scope", "")
        name = (scope.split("::")[-1] + "::" if tag.get("scopeKind") in ("class", "struct") else "") + tag["name"]
        yield tag["path"], name, tag["line"], tag["end"] - tag["line"] + 1


def main(argv):
    limits = "--limits" in argv
    folders = [a for a in argv if not a.startswith("--")] or ROOMS
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    os.chdir(root)
    over = []
    print("| folder | files | largest file (lines) | longest function (lines) | functions > 100 | files > 600 |")
    print("| --- | --- | --- | --- | --- | --- |")
    for folder in folders:
        paths = sorted(os.path.join(folder, f) for f in os.listdir(folder)
                       if f.endswith((".h", ".cpp", ".inl")))
        if not paths:
            continue
        sizes = {p: sum(1 for _ in open(p, encoding="utf-8")) for p in paths}
        largest = max(paths, key=lambda p: sizes[p])
        funcs = list(functions(paths))
        longest = max(funcs, key=lambda f: f[3]) if funcs else None
        long_funcs = [f for f in funcs if f[3] > FUNCTION_LIMIT]
        big_files = [p for p in paths if sizes[p] > FILE_LIMIT]
        over += [f"function {f[0]}:{f[2]} {f[1]}: {f[3]} lines" for f in long_funcs]
        over += [f"file {p}: {sizes[p]} lines" for p in big_files]
        lf = f"`{longest[1]}` ({longest[0]}:{longest[2]}) {longest[3]}" if longest else "—"
        print(f"| `{folder}/` | {len(paths)} | `{largest}` {sizes[largest]} | {lf} | {len(long_funcs)} | "
              f"{len(big_files)} |")
    if limits:
        print()
        for line in over:
            print(line)
        return 1 if over else 0
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
