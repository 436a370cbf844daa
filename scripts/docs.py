#!/usr/bin/env python3
"""The generated parts of the documentation, and the checks that keep the written parts true.

  scripts/docs.py cli-reference CSHAPES OUT.md     the CLI reference, from every command's own --help
  scripts/docs.py python-api OUT.md                 the Python API reference, from the module's docstrings
                                                    (import cshapes must work: PYTHONPATH=build/python)
  scripts/docs.py check-commands CSHAPES FILE...    every `cshapes COMMAND --option` the FILEs show exists
  scripts/docs.py run-shell FILE.md WORKDIR CSHAPES run a page's ```sh blocks in WORKDIR, in order
  scripts/docs.py run-python FILE.md WORKDIR        run a page's ```python blocks in WORKDIR, as one program

The generated pages are committed (docs/reference/), so the site builds without a build of cshapes; the tests
regenerate them and fail, naming the command that refreshes them, when they differ: the reference cannot
drift from the code. Standard library only.
"""
import inspect
import os
import re
import subprocess
import sys

GLOBAL_OPTIONS_WITH_VALUE = {"--threads"}


def run_help(cshapes, path):
    """The --help text of `cshapes PATH...`, with the binary's own path replaced by `cshapes`."""
    out = subprocess.run([cshapes, *path, "--help"], capture_output=True, text=True, check=True).stdout
    return out.replace(cshapes, "cshapes")


def subcommands(help_text):
    """The subcommand names a --help text lists under "Subcommands:"."""
    names, inside = [], False
    for line in help_text.splitlines():
        if line.startswith("Subcommands:"):
            inside = True
        elif inside and re.match(r"^  [a-z][\w-]*\s", line + " "):
            names.append(line.split()[0])
        elif inside and line and not line.startswith(" "):
            inside = False
    return names


def options(help_text):
    """Every option name (--x and -x) a --help text lists, option groups included."""
    names = set()
    for line in help_text.splitlines():
        m = re.match(r"^\s+((?:-[\w?],)?--[\w-]+(?:,--?[\w-]+)*)", line)
        if m:
            names.update(n for n in m.group(1).split(","))
    return names


def command_tree(cshapes):
    """{(path...): help text} for the program and every command and subcommand."""
    tree, todo = {}, [()]
    while todo:
        path = todo.pop(0)
        text = run_help(cshapes, list(path))
        tree[path] = text
        todo += [path + (name,) for name in subcommands(text)]
    return tree


def write_atomically(path, text):
    tmp = path + ".tmp"
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def wrap_help(text, width=100):
    """Long help lines wrapped at `width`, each continuation under its description's first column, so the page
    reads without scrolling sideways."""
    import textwrap  # noqa: PLC0415

    out = []
    for line in text.splitlines():
        if len(line) <= width:
            out.append(line)
            continue
        m = re.match(r"^(\s*\S.*?\s{2,})(\S.*)$", line)
        indent = " " * (len(m.group(1)) if m and len(m.group(1)) < width // 2 else len(line) - len(line.lstrip()))
        out += textwrap.wrap(line, width=width, subsequent_indent=indent, break_on_hyphens=False)
    return "\n".join(out)


def cli_reference(cshapes, out):
    tree = command_tree(cshapes)
    md = ["# Command-line reference", "",
          "Generated from each command's own `--help` by `scripts/docs.py cli-reference build/cshapes "
          "docs/reference/cli.md`; a test fails when this page and the program differ. For what the commands "
          "are for and how they fit together, see [the command line](../cli.md).", ""]
    for path in sorted(tree):
        title = " ".join(("cshapes",) + path)
        md += [f"## {title}", "", "```text", wrap_help(tree[path].rstrip()), "```", ""]
    write_atomically(out, "\n".join(md))


def python_api(out):
    import cshapes  # noqa: PLC0415 (the module is found through PYTHONPATH)

    md = ["# Python API reference", "",
          "Generated from the module's own docstrings by `scripts/docs.py python-api docs/reference/python.md` "
          "(with `PYTHONPATH=build/python`); a test fails when this page and the module differ. For a "
          "walk-through, see [the Python module](../python.md) and [the Python tutorial](../tutorial-python.md); "
          "the signatures with every keyword and its default are also in the module's type stubs "
          "(`cshapes/_cshapes.pyi`), which editors read.", "",
          "```text", inspect.cleandoc(cshapes.__doc__ or ""), "```", ""]
    for name in sorted(n for n in dir(cshapes) if not n.startswith("_")):
        obj = getattr(cshapes, name)
        if inspect.ismodule(obj) or not (callable(obj) or inspect.isclass(obj)):
            continue
        md += [f"## {name}", "", "```text", (inspect.getdoc(obj) or "(no docstring)").rstrip(), "```", ""]
        if inspect.isclass(obj):
            for member in sorted(m for m in dir(obj) if not m.startswith("_")):
                doc = inspect.getdoc(getattr(obj, member))
                if doc:
                    md += [f"### {name}.{member}", "", "```text", doc.rstrip(), "```", ""]
    write_atomically(out, "\n".join(md))


# `cshapes ...` as a page shows it: in a code span or block, after `cshapes`, `build/cshapes` or `"$cshapes"`.
INVOCATION = re.compile(r"""(?:^|[\s`(|;&'"/$])(?:build/|\$\{?)?cshapes\}?"?((?:[ \t]+[^\s`|;&)]+)*)""")


def code_text(markdown):
    """The code of a page: fenced blocks and inline code spans, one piece per line."""
    pieces, fenced = [], False
    for line in markdown.splitlines():
        if line.strip().startswith("```"):
            fenced = not fenced
            continue
        if fenced:
            pieces.append(line)
        else:
            pieces += re.findall(r"`([^`]+)`", line)
    return pieces


def check_commands(cshapes, files):
    tree = command_tree(cshapes)
    problems = []
    for file in files:
        with open(file) as f:
            pieces = code_text(f.read())
        for piece in pieces:
            for m in INVOCATION.finditer(piece):
                words = m.group(1).split()
                k = 0
                while k < len(words) and words[k].startswith("-"):  # the program's own options
                    k += 2 if words[k] in GLOBAL_OPTIONS_WITH_VALUE else 1
                path = ()
                while k < len(words) and path + (words[k],) in tree:
                    path += (words[k],)
                    k += 1
                if not path:
                    if k < len(words) and re.fullmatch(r"[a-z][a-z0-9-]*", words[k]):
                        problems.append(f"{file}: `cshapes {' '.join(words[:k + 1])}`: no such command")
                    continue
                if subcommands(tree[path]):  # a group: its options are its subcommands'
                    if k < len(words) and re.fullmatch(r"[a-z][a-z0-9-]*", words[k]):
                        problems.append(f"{file}: `cshapes {' '.join(path)} {words[k]}`: no such command")
                    continue
                known = options(tree[path]) | options(tree[()])
                for w in words[k:]:
                    name = w.split("=")[0].rstrip(",.:")
                    if re.fullmatch(r"--?[a-zA-Z][\w-]*", name) and name not in known:
                        problems.append(f"{file}: `cshapes {' '.join(path)} ... {name}`: no such option")
    for p in problems:
        print(p, file=sys.stderr)
    if problems:
        print(f"{len(problems)} documented command(s) or option(s) do not exist", file=sys.stderr)
        return 1
    return 0


def blocks(markdown, language):
    """The fenced blocks of one language, in order."""
    out, current = [], None
    for line in markdown.splitlines():
        stripped = line.strip()
        if current is None and stripped.startswith("```") and stripped[3:].strip() == language:
            current = []
        elif current is not None and stripped.startswith("```"):
            out.append("\n".join(current))
            current = None
        elif current is not None:
            current.append(line)
    return out


def run_shell(page, workdir, cshapes):
    with open(page) as f:
        code = blocks(f.read(), "sh")
    os.makedirs(workdir, exist_ok=True)
    env = dict(os.environ)
    bindir = os.path.join(workdir, "bin")
    os.makedirs(bindir, exist_ok=True)
    link = os.path.join(bindir, "cshapes")
    if os.path.lexists(link):
        os.remove(link)
    os.symlink(os.path.abspath(cshapes), link)
    env["PATH"] = bindir + os.pathsep + env["PATH"]
    for k, block in enumerate(code, 1):
        print(f"== {page}: block {k} of {len(code)}", file=sys.stderr)
        r = subprocess.run(["bash", "-euo", "pipefail", "-c", block], cwd=workdir, env=env)
        if r.returncode != 0:
            print(f"{page}: block {k} failed (exit {r.returncode}):\n{block}", file=sys.stderr)
            return 1
    return 0 if code else 1


def run_python(page, workdir):
    with open(page) as f:
        code = blocks(f.read(), "python")
    os.makedirs(workdir, exist_ok=True)
    program = "\n\n".join(code)
    r = subprocess.run([sys.executable, "-c", program], cwd=workdir)
    if r.returncode != 0:
        print(f"{page}: its Python blocks failed (exit {r.returncode})", file=sys.stderr)
    return r.returncode if code else 1


def main(argv):
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    what, args = argv[1], argv[2:]
    if what == "cli-reference" and len(args) == 2:
        cli_reference(*args)
        return 0
    if what == "python-api" and len(args) == 1:
        python_api(*args)
        return 0
    if what == "check-commands" and len(args) >= 2:
        return check_commands(args[0], args[1:])
    if what == "run-shell" and len(args) == 3:
        return run_shell(*args)
    if what == "run-python" and len(args) == 2:
        return run_python(*args)
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
