"""A keyword that a Python function shares with a CLI option is declared once, in the library
(support/option_declaration.h): the CLI's help for the flag and the Python docstring's description come from
that one declaration (cshapes.option_declarations()), never from a second text in cshapes/_docs.py.

Which keywords have a CLI counterpart is read from the CLI itself: a keyword whose flag (``--`` + its
kebab-case, or ``--no-`` + it: draw=True and ``--no-draw``) the function's command lists in its --help-all. Each must be declared (or be a canonical-form
method's option, declared as a MethodOption), unless it is listed below with the reason it is not yet.
"""
import inspect
import re

import pytest

import cshapes
from cshapes import _api, _docs

# The command each function stands for (its CLI counterpart).
COMMANDS = {
    "icp": ["align"],
    "shape_distance": ["align"],
    "geodesics": ["geodesics"],
    "add_topological_noise": ["noise"],
    "experiment_paper": ["experiment", "paper"],
    "experiment_retrieval": ["experiment", "retrieval"],
    "experiment_noise": ["experiment", "noise"],
    "experiment_pose": ["experiment", "pose"],
    "experiment_topkids": ["experiment", "topkids"],
    "experiment_invariance": ["experiment", "invariance"],
    "compare_runs": ["compare"],
    "show": ["show"],
    "distance_matrix": ["distmat"],
    "retrieval_measures": ["evaluate"],
    "canonical_form": ["canon"],
    "coulomb": ["canon"],
}

# Keywords with a flag of the same name on their command that are not declared yet, each with its reason.
# The list may only shrink: a keyword listed here that is declared fails the test.
NOT_YET_DECLARED = {
    # The skins take different values: the CLI 'all' (a word), Python 0 or -1 (an int).
    ("experiment_paper", "poses_per_class"): "CLI 'all', Python 0",
    ("experiment_paper", "noisy_per_class"): "CLI 'all', Python -1",
    ("experiment_noise", "poses_per_class"): "CLI 'all', Python 0",
    # Python takes more forms than the CLI's comma-separated names: lists, (NAME, fn) pairs with a function.
    **{(f, "methods"): "Python's own forms" for f in COMMANDS if f.startswith("experiment_")},
    ("canonical_form", "method"): "Python also takes a function or a (NAME, fn) pair",
    ("retrieval_measures", "labels"): "Python a list of labels, the CLI a file",
    ("distance_matrix", "cache"): "Python None: no cache; distmat's default: a folder beside the output",
    # Not declared yet: each the same option on both skins, still described twice.
    ("canonical_form", "knn"): "to declare: the point-cloud option of every method (cli/method_options.cpp)",
    ("coulomb", "knn"): "to declare: the point-cloud option of every method (cli/method_options.cpp)",
}


@pytest.fixture(scope="module")
def declared():
    """{function: {keyword: declaration}}; a module without declarations has none (every keyword undeclared)."""
    return _api.declared_options() if hasattr(_api, "declared_options") else {}


def flags_and_help(cli, command):
    """{flag: what --help-all lists after it (its type, default and help text, continuation lines joined)} of
    `cshapes COMMAND`."""
    text = cli(*command, "--help-all").stdout
    out, last = {}, None
    for line in text.splitlines():
        m = re.match(r"^\s{2,6}(?:-[a-zA-Z],)?(--[a-z0-9-]+)(.*)$", line)
        if m:
            last = m.group(1)
            out[last] = " ".join(m.group(2).split())
        elif last and re.match(r"^\s{20,}\S", line):
            out[last] = (out[last] + " " + " ".join(line.split())).strip()
        else:
            last = None
    return out


def shows_help(entry, help_text):
    """Whether a --help entry (type, default, text) gives exactly this text after the type and default
    ("FLOAT:in [0, 0.9]=0", "TEXT:{png, pdf, svg}=png", "TEXT REQUIRED", or nothing for a flag)."""
    help_text = " ".join(help_text.split())
    if not entry.endswith(help_text):
        return False
    prefix = entry[:len(entry) - len(help_text)].strip()
    return prefix == "" or re.fullmatch(r"[A-Z]+(:.*)?(=\S*)?( REQUIRED)?", prefix) is not None


def test_declarations_name_keywords_the_functions_take(declared):
    signatures = {n: inspect.signature(getattr(cshapes, n)) for n in declared}
    for function, options in declared.items():
        for keyword, o in options.items():
            assert keyword in signatures[function].parameters, f"{function}() takes no keyword {keyword}"
            assert o["flag"].startswith("--"), o


def test_declared_keywords_are_not_described_in_docs(declared):
    """_docs.py holds only the text of parameters without a CLI counterpart."""
    for function, options in declared.items():
        params = _docs.DOCS.get(function, {}).get("params", {})
        for keyword in options:
            assert keyword not in params, (
                f"_docs.py describes {function}()'s {keyword}, which its declaration ({options[keyword]['flag']}) "
                "describes: remove it from _docs.py")
    # A shared description (COMMON) must still be used by some function that has no declaration for it.
    functions = [n for n in cshapes.__all__ if hasattr(getattr(cshapes, n), "__signature__")]
    undeclared_users = {p for name in functions for p in inspect.signature(getattr(cshapes, name)).parameters
                        if p not in declared.get(name, {})}
    for keyword in _docs.COMMON:
        assert keyword in undeclared_users, (
            f"_docs.COMMON describes {keyword}, which every function taking it has a declaration for")


def test_docstrings_give_the_declaration_and_its_limit(declared):
    for function, options in declared.items():
        doc = " ".join(getattr(cshapes, function).__doc__.split())
        for keyword, o in options.items():
            assert " ".join(o["text"].split()) in doc, f"{function}(): {keyword} is not described by its declaration"
            if o["limit"]:
                assert f"Limit: {o['limit']}." in o["text"]
    # The limits are the library's: icp_limits::kTolerance, noise_limits::kRelax.
    assert declared["icp"]["icp_tolerance"]["limit"] == "a number >= 0"
    assert declared["add_topological_noise"]["relax"]["limit"] == "an integer 0..100"
    # Another option named in a text is spelt per skin.
    gap = declared["add_topological_noise"]["max_gap"]
    assert "gap_edges" in gap["help"] and "--gap-edges" in gap["cli_help"]


def test_every_keyword_with_a_cli_counterpart_is_declared_and_the_cli_shows_its_text(cli, declared):
    method_options = {o["name"] for o in cshapes.method_options()}
    for function, command in COMMANDS.items():
        cli_help = flags_and_help(cli, command)
        for keyword in inspect.signature(getattr(cshapes, function)).parameters:
            flag = "--" + keyword.replace("_", "-")
            if flag not in cli_help and "--no-" + flag[2:] in cli_help:
                flag = "--no-" + flag[2:]  # draw=True is --no-draw's opposite
            if flag not in cli_help or keyword in method_options and (
                    function in ("canonical_form", "coulomb") or flag == "--geodesics"):
                continue  # no counterpart, or a canonical-form method's option (a MethodOption)
            o = declared.get(function, {}).get(keyword)
            if (function, keyword) in NOT_YET_DECLARED:
                assert o is None, f"{function}(): {keyword} is declared now: remove it from NOT_YET_DECLARED"
                continue
            assert o is not None, (f"{function}(): {keyword} has a CLI counterpart ({' '.join(command)} {flag}) "
                                   "but no declaration: declare it in the library (support/option_declaration.h)")
            assert o["flag"] == flag and o["negated"] == (flag != "--" + keyword.replace("_", "-")), o
            assert shows_help(cli_help[flag], o["cli_help"]), (
                f"cshapes {' '.join(command)} {flag}: its help is not its declaration's: {cli_help[flag]!r}")
