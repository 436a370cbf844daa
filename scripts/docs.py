#!/usr/bin/env python3
"""The generated parts of the documentation, and the checks that keep the written parts true.

  scripts/docs.py cli-reference CSHAPES OUT.md     the CLI reference, from every command's own --help-all
  scripts/docs.py python-api OUT.md                 the Python API reference, from the module's docstrings
                                                    (import cshapes must work: PYTHONPATH=build/python)
  scripts/docs.py check-commands CSHAPES FILE...    every `cshapes COMMAND --option` the FILEs show exists
  scripts/docs.py run-shell FILE.md WORKDIR CSHAPES run a page's ```sh blocks in WORKDIR, in order
  scripts/docs.py run-python FILE.md WORKDIR        run a page's ```python blocks in WORKDIR, as one program
  scripts/docs.py site CSHAPES [--update-pictures]  the site, in build/site: the tutorials run in build/docs-work,
                                                    the pictures they show checked against docs/images/tutorial-*/
                                                    (--update-pictures: written there) and copied into a copy of
                                                    docs/ (build/docs-src), then mkdocs build --strict

A ```sh or ```python block may be followed by an ```output block showing what it prints, trimmed: run-shell and
run-python fail when a block's output differs (see OUTPUT below for how lines match).

The generated reference pages are committed (docs/reference/); the tests regenerate them and fail, naming the
command that refreshes them, when they differ: the reference cannot drift from the code. The tutorials' pictures
are committed too (so a plain `mkdocs build` works), and the site build draws them again with the tutorials' own
commands and fails, naming the picture and --update-pictures, when one differs. Standard library only, but for
the picture comparison (numpy and matplotlib, as the figures).
"""
import inspect
import os
import re
import shutil
import subprocess
import sys

GLOBAL_OPTIONS_WITH_VALUE = {"--threads"}


def run_help(cshapes, path, flag="--help"):
    """The --help (or --help-all) text of `cshapes PATH...`, with the binary's own path replaced by `cshapes`."""
    out = subprocess.run([cshapes, *path, flag], capture_output=True, text=True, check=True).stdout
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
    """{(path...): help text} for the program and every command and subcommand: a command's --help-all (its
    advanced options too), a group's --help (--help-all would expand every command under it)."""
    tree, todo = {}, [()]
    while todo:
        path = todo.pop(0)
        text = run_help(cshapes, list(path))
        names = subcommands(text)
        tree[path] = text if names else run_help(cshapes, list(path), "--help-all")
        todo += [path + (name,) for name in names]
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
          "Generated from each command's own `--help-all` by `scripts/docs.py cli-reference build/cshapes "
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
          "each function's signature lists every keyword with its default, as `inspect.signature` and "
          "`help()` show it (the type stubs `cshapes/_cshapes.pyi`, which editors read, say the same).", "",
          "```text", inspect.cleandoc(cshapes.__doc__ or ""), "```", ""]
    for name in sorted(n for n in dir(cshapes) if not n.startswith("_")):
        obj = getattr(cshapes, name)
        if inspect.ismodule(obj) or not (callable(obj) or inspect.isclass(obj)):
            continue
        head = [f"{name}{inspect.signature(obj)}", ""] if inspect.isfunction(obj) else []
        md += [f"## {name}", "", "```text", *head, (inspect.getdoc(obj) or "(no docstring)").rstrip(), "```", ""]
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


def fences(markdown):
    """Every fenced block of a page, in order, as (info string, text, line number of its opening fence)."""
    out, info, current, start = [], None, None, 0
    for number, line in enumerate(markdown.splitlines(), 1):
        stripped = line.strip()
        if current is None and stripped.startswith("```"):
            info, current, start = stripped[3:].strip(), [], number
        elif current is not None and stripped == "```":
            out.append((info, "\n".join(current), start))
            current = None
        elif current is not None:
            current.append(line)
    return out


def blocks(markdown, language):
    """The fenced blocks of one language, in order."""
    return [text for info, text, _ in fences(markdown) if info == language]


def steps(markdown, language):
    """The blocks of one language, each with the ```output block that shows what it prints (None if it has none),
    as (code, expected, line number). An output block belongs to the nearest code block above it; prose between
    them is allowed. An output block under a block of another language belongs to that one."""
    out, last = [], None  # last: the language of the nearest code block above (a page may mix sh and python)
    for info, text, line in fences(markdown):
        if info == language:
            out.append([text, None, line])
            last = info
        elif info == OUTPUT:
            if last != language:
                continue  # the output of another language's block
            if not out or out[-1][1] is not None:
                raise ValueError(f"line {line}: an ```{OUTPUT} block with no ```{language} block of its own above it")
            out[-1][1] = text
        else:
            last = info
    return [tuple(step) for step in out]


# Expected output, under a code block:
#   ```output
#   a line the block prints, whitespace-normalised   (blank lines are ignored on both sides)
#   a line with … in it                              (… stands for any text: seconds, paths)
#   ...                                              (a line of its own: any number of lines, none included)
#   ```
# Lines must follow one another as shown, from the output's first line; the output may go on after the last
# expected line only when the block ends with `...`.
OUTPUT = "output"
SKIP_LINES = {"...", "…"}
ANY_TEXT = "…"


def normalise(line):
    return " ".join(line.split())


def line_matches(expected, actual):
    """Whether one normalised actual line is what one expected line shows, `…` standing for any text."""
    pattern = ".*".join(re.escape(part) for part in expected.split(ANY_TEXT))
    return re.fullmatch(pattern, actual) is not None


def segments(expected_text):
    """The expected lines as runs that must follow one another: [(may start later, [lines])], and whether the
    output may go on after the last run."""
    runs, skip = [], False
    for line in filter(None, map(normalise, expected_text.splitlines())):
        if line in SKIP_LINES:
            skip = True
        elif skip or not runs:
            runs.append((skip, [line]))
            skip = False
        else:
            runs[-1][1].append(line)
    return runs, skip


def matching_lines(run, actual, start):
    """How many lines of a run of expected lines match the actual lines from `start` on, one after another."""
    n = 0
    while n < len(run) and start + n < len(actual) and line_matches(run[n], actual[start + n]):
        n += 1
    return n


def output_mismatch(expected_text, actual_text):
    """None when the output is what the expected block shows, else a sentence saying which expected line is not
    where it should be."""
    actual = list(filter(None, map(normalise, actual_text.splitlines())))
    runs, open_end = segments(expected_text)
    if not runs:
        return None if open_end or not actual else f"expected no output, got {len(actual)} line(s)"
    pos = 0
    for k, (may_start_later, run) in enumerate(runs):
        starts = range(pos, len(actual) + 1) if may_start_later else [pos]
        found = [s for s in starts if matching_lines(run, actual, s) == len(run)]
        if k == len(runs) - 1 and not open_end:
            at_end = [s for s in found if s + len(run) == len(actual)]
            if found and not at_end:
                return (f"the output goes on after the expected line {run[-1]!r} (end the expected block with "
                        f"`...` if that is meant)")
            found = at_end
        if not found:
            best = max(starts, key=lambda s: matching_lines(run, actual, s))
            n = matching_lines(run, actual, best)
            if may_start_later and n == 0:
                return f"expected the line {run[0]!r}, not found after the expected lines above it"
            there = repr(actual[best + n]) if best + n < len(actual) else "the end of the output"
            return f"expected the line {run[n]!r}, found {there}"
        pos = found[0] + len(run)
    return None


def check_output(page, k, line, expected, actual):
    """0 when block k's output (opened on `line` of the page) is what its ```output block shows, else 1, with
    the difference and the whole output on stderr."""
    if expected is None:
        return 0
    problem = output_mismatch(expected, actual)
    if problem is None:
        return 0
    print(f"{page}:{line}: block {k}'s output is not what the page shows under it: {problem}\n"
          f"--- the block printed:\n{actual.rstrip()}\n---", file=sys.stderr)
    return 1


def run_shell(page, workdir, cshapes):
    """Run a page's ```sh blocks in WORKDIR, in order, with `cshapes` on the PATH, each in `bash -euo pipefail`;
    each block's output (stdout and stderr together, as a terminal shows them) must be what the ```output block
    under it shows."""
    with open(page) as f:
        code = steps(f.read(), "sh")
    os.makedirs(workdir, exist_ok=True)
    env = dict(os.environ)
    bindir = os.path.join(workdir, "bin")
    os.makedirs(bindir, exist_ok=True)
    link = os.path.join(bindir, "cshapes")
    if os.path.lexists(link):
        os.remove(link)
    os.symlink(os.path.abspath(cshapes), link)
    env["PATH"] = bindir + os.pathsep + env["PATH"]
    failed = 0
    for k, (block, expected, line) in enumerate(code, 1):
        print(f"== {page}: block {k} of {len(code)}", file=sys.stderr)
        r = subprocess.run(["bash", "-euo", "pipefail", "-c", block], cwd=workdir, env=env,
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        print(r.stdout, end="", flush=True)
        if r.returncode != 0:
            print(f"{page}:{line}: block {k} failed (exit {r.returncode}):\n{block}", file=sys.stderr)
            return 1
        failed += check_output(page, k, line, expected, r.stdout)
    return 1 if failed or not code else 0


BLOCK_MARK = "\x1e== docs.py: the next block's output ==\x1e"

# Runs the blocks in one namespace, as one program, with a line on stdout where each block's output begins.
PYTHON_DRIVER = """
namespace = {"__name__": "__main__"}
for name, code in BLOCKS:
    print(MARK, flush=True)
    exec(compile(code, name, "exec"), namespace)
"""


def run_python(page, workdir):
    """Run a page's ```python blocks in WORKDIR as one program; each block's output (stdout and stderr together)
    must be what the ```output block under it shows."""
    with open(page) as f:
        code = steps(f.read(), "python")
    os.makedirs(workdir, exist_ok=True)
    env = dict(os.environ)  # PYTHONPATH absolute, so the module is found from WORKDIR too
    env["PYTHONPATH"] = os.pathsep.join(os.path.abspath(p) for p in env.get("PYTHONPATH", "").split(os.pathsep) if p)
    named = [(f"{page}, block {k} (line {line})", block) for k, (block, _, line) in enumerate(code, 1)]
    program = f"BLOCKS = {named!r}\nMARK = {BLOCK_MARK!r}\n{PYTHON_DRIVER}"
    r = subprocess.run([sys.executable, "-u", "-c", program], cwd=workdir, env=env,
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    before, *outputs = r.stdout.split(BLOCK_MARK + "\n")
    print(before, end="")
    for k, out in enumerate(outputs, 1):
        print(f"== {page}: block {k} of {len(code)}\n{out}", end="", flush=True)
    if r.returncode != 0:
        print(f"{page}: its Python blocks failed (exit {r.returncode})", file=sys.stderr)
        return r.returncode
    failed = sum(check_output(page, k, line, expected, out)
                 for (_, expected, line), k, out in zip(code, range(1, len(code) + 1), outputs))
    return 1 if failed or not code else 0


# The tutorials, each with the language of the blocks it runs. A tutorial's pictures are made by its own
# commands: the page shows images/<page>/PATH, PATH being where its commands wrote the picture in their work folder.
TUTORIALS = {"tutorial-cli.md": "sh", "tutorial-python.md": "python"}


def pictures(markdown, page):
    """The pictures a tutorial page shows from its own commands: its images/<page name>/... references."""
    folder = "images/" + os.path.splitext(page)[0] + "/"
    return [ref for ref in re.findall(r"!\[[^\]]*\]\(([^)\s]+)\)", markdown) if ref.startswith(folder)]


def site_config(root, docs_dir, site_dir):
    """mkdocs.yml with docs_dir and site_dir replaced, as text (mkdocs.yml sets both, each on a line of its own)."""
    with open(os.path.join(root, "mkdocs.yml")) as f:
        text = f.read()
    for key, value in (("docs_dir", docs_dir), ("site_dir", site_dir)):
        text, n = re.subn(rf"^{key}:.*$", f"{key}: {value}", text, flags=re.MULTILINE)
        if n != 1:
            raise ValueError(f"mkdocs.yml: expected one {key}: line")
    return text


def same_picture(a, b, tolerance=0.01):
    """Whether two PNGs show the same picture: the same size and a mean pixel difference below the tolerance (of
    the 0-1 range), so a renderer's last-bit changes pass and a changed figure does not."""
    import numpy as np
    from matplotlib import image
    x, y = image.imread(a), image.imread(b)
    return x.shape == y.shape and float(np.abs(x.astype(float) - y.astype(float)).mean()) <= tolerance


def site(cshapes, update_pictures=False):
    """The documentation site: docs/ copied to build/docs-src, each tutorial run in build/docs-work/<page>/ (its
    expected outputs checked), the pictures it shows drawn there, compared with the committed ones in docs/ (or
    written there with update_pictures) and copied into the copy, then `mkdocs build --strict` from the copy into
    build/site. A committed picture that its tutorial no longer draws fails the build: it cannot drift."""
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    build = os.path.join(root, "build")
    staging, work = os.path.join(build, "docs-src"), os.path.join(build, "docs-work")
    for folder in (staging, work):
        shutil.rmtree(folder, ignore_errors=True)
    shutil.copytree(os.path.join(root, "docs"), staging)
    for page, language in TUTORIALS.items():
        path, workdir = os.path.join(root, "docs", page), os.path.join(work, os.path.splitext(page)[0])
        status = run_shell(path, workdir, cshapes) if language == "sh" else run_python(path, workdir)
        if status != 0:
            print(f"site: docs/{page} did not run as written", file=sys.stderr)
            return 1
        with open(path) as f:
            refs = pictures(f.read(), page)
        for ref in refs:
            made = os.path.join(workdir, ref.split("/", 2)[2])
            if not os.path.isfile(made):
                print(f"site: docs/{page} shows {ref}, but its commands did not write {os.path.relpath(made, root)}",
                      file=sys.stderr)
                return 1
            committed = os.path.join(root, "docs", ref)
            if update_pictures:
                os.makedirs(os.path.dirname(committed), exist_ok=True)
                shutil.copyfile(made, committed)
            elif not os.path.isfile(committed) or not same_picture(made, committed):
                print(f"site: docs/{page} draws {ref} differently from docs/{ref} (or it is missing): look at "
                      f"{os.path.relpath(made, root)}, then run scripts/docs.py site CSHAPES --update-pictures",
                      file=sys.stderr)
                return 1
            os.makedirs(os.path.dirname(os.path.join(staging, ref)), exist_ok=True)
            shutil.copyfile(made, os.path.join(staging, ref))
        print(f"site: docs/{page} ran; {len(refs)} picture(s) from {os.path.relpath(workdir, root)}", file=sys.stderr)
    config = os.path.join(build, "mkdocs-site.yml")
    write_atomically(config, site_config(root, staging, os.path.join(build, "site")))
    return subprocess.run(["mkdocs", "build", "--strict", "-q", "-f", config]).returncode


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
    if what == "site" and len(args) in (1, 2) and args[1:] in ([], ["--update-pictures"]):
        return site(args[0], update_pictures=len(args) == 2)
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
