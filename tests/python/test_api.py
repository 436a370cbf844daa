"""The Python API documents itself (issue 60, item 4; the reprs of item 3): every public function has an
explicit signature (inspect.signature lists every option with its default, no **kwargs standing in for
them), a numpy-style docstring (Parameters, Returns, Examples) that describes every parameter and names no
CLI spelling; options given by position are answered in one line without the array; long calls report
progress to a callable or a bar; reprs read as a person reads them; __version__ is the project's."""
import inspect
import io
import re
import sys
from pathlib import Path

import numpy as np
import pytest

import cshapes

ROOT = Path(__file__).resolve().parents[2]

FUNCTIONS = sorted(n for n in cshapes.__all__ if not inspect.isclass(getattr(cshapes, n)))
# The calls that can take more than a few seconds, each with its progress= keyword.
LONG_CALLS = ["add_topological_noise", "canonical_form", "classical_mds", "coulomb", "distance_matrix",
              "experiment_invariance", "experiment_noise", "experiment_paper", "experiment_pose",
              "experiment_retrieval", "experiment_topkids", "generate", "geodesics", "smacof"]  # generate: a dataset

HAND = cshapes.generate("articulated", class_="hand", poses=2, vertices=400, seed=3)
V, F = HAND[0]


def test_every_function_of_the_module_is_a_documented_python_function():
    extension = {n for n in dir(cshapes._cshapes) if not n.startswith("_")
                 and callable(getattr(cshapes._cshapes, n)) and not inspect.isclass(getattr(cshapes._cshapes, n))}
    assert extension <= set(FUNCTIONS), extension - set(FUNCTIONS)
    for name in FUNCTIONS:
        function = getattr(cshapes, name)
        assert function.__module__ == "cshapes" and function.__name__ == name
        assert function.__wrapped__ is getattr(cshapes._cshapes, name)


@pytest.mark.parametrize("name", FUNCTIONS)
def test_the_signature_lists_every_option_with_its_default(name):
    signature = inspect.signature(getattr(cshapes, name))
    for p in signature.parameters.values():
        # **kwargs only where the names are the caller's own (write_mesh's per-vertex fields).
        assert p.kind is not inspect.Parameter.VAR_KEYWORD or (name, p.name) == ("write_mesh", "vertex_fields")
        if p.kind is inspect.Parameter.KEYWORD_ONLY and p.name != "out":
            assert p.default is not inspect.Parameter.empty, f"{name}(): {p.name} has no default"
        assert p.annotation is not inspect.Parameter.empty, f"{name}(): {p.name} has no type"
    assert (name in LONG_CALLS) == ("progress" in signature.parameters), name


def test_canonical_form_shows_every_method_option_with_its_declared_default():
    signature = inspect.signature(cshapes.canonical_form)
    assert str(signature).startswith("(V: ArrayLike, F: ArrayLike, *, method: Method = 'coulomb', ")
    for option in cshapes.method_options():
        assert signature.parameters[option["name"]].default == option["default"], option["name"]
    for name, default in [("knn", 8), ("strict", False), ("method_timeout", 86400.0), ("method_version", ""),
                          ("progress", None)]:
        assert signature.parameters[name].default == default
    coulomb = inspect.signature(cshapes.coulomb)
    keywords = next(m["keywords"] for m in cshapes.canonical_form_methods() if m["name"] == "coulomb")
    assert [p for p in coulomb.parameters if p in keywords] == keywords


def read_keywords(call):
    """The keywords the extension reads on this call's path: from its refusal of an unknown one."""
    with pytest.raises(TypeError) as e:
        call(__probe__=1)
    m = re.search(r"its options: (.*)$", str(e.value))
    assert m, str(e.value)
    return set(m.group(1).split(", "))


@pytest.mark.parametrize("name,call", [
    ("coulomb", lambda **k: cshapes.coulomb(V, F, **k)),
    ("canonical_form", lambda **k: cshapes.canonical_form(V, F, method="spectral-mds", **k)),
    ("smacof", lambda **k: cshapes.smacof(np.eye(4), **k)),
    ("icp", lambda **k: cshapes.icp(V, V, **k)),
    ("distance_matrix", lambda **k: cshapes.distance_matrix([V, V], **k)),
    ("add_topological_noise", lambda **k: cshapes.add_topological_noise(V, F, **k)),
    ("experiment_paper", lambda **k: cshapes.experiment_paper("/nonexistent", "/nonexistent", **k)),
    ("experiment_noise", lambda **k: cshapes.experiment_noise("/nonexistent", "/nonexistent", **k)),
])
def test_the_signature_holds_every_keyword_the_extension_reads(name, call):
    assert read_keywords(call) <= set(inspect.signature(getattr(cshapes, name)).parameters)


@pytest.mark.parametrize("name", FUNCTIONS)
def test_numpy_sections_describe_every_parameter(name):
    function = getattr(cshapes, name)
    doc = function.__doc__
    signature = inspect.signature(function)
    assert doc and not doc.startswith(name + "("), name  # a summary line, not pybind's signature
    sections = re.findall(r"^(\w+)\n-+$", doc, re.M)
    expected = (["Parameters"] if signature.parameters else []) + ["Returns"]
    assert sections[:len(expected)] == expected, (name, sections)
    assert "Examples" in sections, name
    for p in signature.parameters.values():
        head = ("**" if p.kind is inspect.Parameter.VAR_KEYWORD else "") + p.name
        assert re.search(rf"^{re.escape(head)} : \S", doc, re.M), f"{name}(): {p.name} not in Parameters"
        if p.default is not inspect.Parameter.empty and p.default is not None and name != "generate":
            assert re.search(rf"^{re.escape(head)} : .*default {re.escape(repr(p.default))}$", doc, re.M), \
                f"{name}(): {p.name}'s default not in Parameters"


@pytest.mark.parametrize("name", FUNCTIONS)
def test_docstrings_name_no_cli_spelling(name):
    doc = getattr(cshapes, name).__doc__
    assert not re.search(r"--[a-z]", doc), re.findall(r".{30}--[a-z].{20}", doc)
    assert "PyCapsule" not in doc


def test_help_shows_a_python_function():
    import pydoc
    text = pydoc.render_doc(cshapes.canonical_form, renderer=pydoc.plaintext)
    assert "builtins.PyCapsule" not in text and "**kwargs" not in text
    assert "tear_fraction: float = 0.01" in text and "progress: " in text
    assert "\n    Parameters\n    ----------\n" in text


def one_line_error(call, *needles):
    with pytest.raises(TypeError) as e:
        call()
    message = str(e.value)
    assert "\n" not in message, message
    assert "array(" not in message and "incompatible" not in message, message
    assert len(message) < 300, message
    for needle in needles:
        assert needle in message, message
    return message


def test_options_given_by_position_are_answered_in_one_line():
    one_line_error(lambda: cshapes.canonical_form(V, F, "lbo"),
                   "canonical_form() takes 2 positional arguments (V, F) but 3 were given",
                   "options are keywords: method='lbo'")
    one_line_error(lambda: cshapes.coulomb(V, F, "paper", "momentum"),
                   "coulomb() takes 2 positional arguments (V, F) but 4 were given",
                   "coulomb_preset='paper', scheme='momentum'")
    one_line_error(lambda: cshapes.icp(V, V, V), "icp() takes 2 positional arguments (A, B) but 3 were given",
                   "no_reflections=<array (400, 3) float64>")


def test_missing_and_mistyped_arguments_are_answered_in_one_line():
    one_line_error(lambda: cshapes.canonical_form(V), "canonical_form() missing 1 required argument: 'F'")
    one_line_error(lambda: cshapes.canonical_form(V, F, F=F), "multiple values for argument 'F'")
    one_line_error(lambda: cshapes.classical_mds(np.eye(3), dim="two"), "classical_mds()", "dim='two'",
                   "D=<array (3, 3) float64>")


def test_a_renamed_keyword_still_names_the_new_one():
    with pytest.raises(TypeError, match="'iters' is now smacof_max_iterations"):
        cshapes.canonical_form(V, F, method="smacof", iters=5)
    with pytest.raises(TypeError, match="'tolerance' is now icp_tolerance"):
        cshapes.icp(V, V, tolerance=1e-3)


class Recorder:
    def __init__(self):
        self.calls = []

    def __call__(self, stage, fraction, seconds_left):
        self.calls.append((stage, fraction, seconds_left))


def check_reports(calls, stage):
    assert calls, "the callback was never called"
    stages = [c[0] for c in calls]
    assert stage in stages, stages
    for s in set(stages):
        fractions = [c[1] for c in calls if c[0] == s]
        assert fractions == sorted(fractions), (s, fractions)  # never decreasing within a stage
        assert all(0 <= f <= 1 for f in fractions)
    assert [c[1] for c in calls if c[0] == stage][-1] == 1.0
    assert all(c[2] is None or c[2] >= 0 for c in calls)
    assert all(isinstance(c[0], str) and c[0] for c in calls)


def test_progress_callback_of_a_canonical_form():
    recorder = Recorder()
    form = cshapes.coulomb(V, F, progress=recorder)
    check_reports(recorder.calls, "coulomb")
    assert len(recorder.calls) >= 2
    recorder = Recorder()
    cshapes.canonical_form(V, F, method="smacof", progress=recorder)
    check_reports(recorder.calls, "smacof")
    assert form.X.shape == V.shape


def test_progress_callback_of_distances_and_geodesics():
    recorder = Recorder()
    cshapes.distance_matrix([V, HAND[1][0], V + 1], progress=recorder)
    check_reports(recorder.calls, "distances")
    recorder = Recorder()
    cshapes.geodesics(V, F, method="fmm", progress=recorder)
    check_reports(recorder.calls, "geodesics")


def test_progress_callback_of_a_generated_dataset():
    # Making a dataset is one of the long calls: its progress counts the shapes made.
    recorder = Recorder()
    shapes = cshapes.generate("dataset", classes=1, poses=2, noisy=0, vertices=800, progress=recorder)
    check_reports(recorder.calls, "dataset")
    assert len(shapes) == 2 and len(recorder.calls) >= 2
    with pytest.raises(TypeError, match="progress"):
        cshapes.generate("icosphere", progress=recorder)  # only the dataset reads it


def test_the_callbacks_exception_stops_the_call_and_is_raised():
    def fails(stage, fraction, seconds_left):
        raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        cshapes.coulomb(V, F, progress=fails)

    def interrupts(stage, fraction, seconds_left):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        cshapes.distance_matrix([V, V + 1], progress=interrupts)


def test_progress_true_draws_a_bar_and_the_default_draws_none_off_a_terminal(capsys):
    cshapes.coulomb(V, F, progress=True)
    err = capsys.readouterr().err
    assert "[coulomb]" in err and "100.0% in " in err and err.endswith("\n"), err
    assert "\r" in err
    cshapes.coulomb(V, F)  # stderr is not a terminal here: no bar
    cshapes.coulomb(V, F, progress=False)
    assert capsys.readouterr().err == ""
    with pytest.raises(TypeError, match="progress: expected None, True, False or a function"):
        cshapes.coulomb(V, F, progress="yes")


def test_the_default_draws_the_bar_on_a_terminal_for_calls_longer_than_a_second(monkeypatch):
    class Terminal(io.StringIO):
        def isatty(self):
            return True

    monkeypatch.setattr(sys, "stderr", Terminal())
    cshapes.coulomb(V, F)  # done within the bar's delay: nothing
    assert sys.stderr.getvalue() == ""
    monkeypatch.setattr(cshapes._api, "DEFAULT_BAR_DELAY", 0.0)
    cshapes.coulomb(V, F)
    assert "[coulomb] 100.0% in " in sys.stderr.getvalue()


def test_the_bar_ends_its_line_when_the_call_fails(capsys):
    bar = cshapes.ProgressBar()
    bar("coulomb", 0.25, None)
    bar("coulomb", 0.5, 12.4)
    bar.close()
    assert capsys.readouterr().err == "\r[coulomb]  25.0%\r[coulomb]  50.0% (about 12 s left)\n"


def significant_figures(number):
    digits = re.sub(r"e[+-]\d+$", "", number).replace(".", "").lstrip("0")
    return len(digits)


def test_canonical_form_repr():
    form = cshapes.coulomb(V, F, progress=False)
    text = repr(form)
    m = re.fullmatch(r"<cshapes\.CanonicalForm: coulomb, 400 points, ([\d,]+) (iterations?), ([\d.e+-]+) s>", text)
    assert m, text
    assert (m.group(1) == "1") == (m.group(2) == "iteration")
    assert significant_figures(m.group(3)) <= 3, text
    one = cshapes.smacof(cshapes.geodesics(V, F, method="fmm").astype(float), smacof_max_iterations=1)
    assert repr(one).startswith("<cshapes.CanonicalForm: smacof, 400 points, 1 iteration, "), repr(one)
    line = np.abs(np.subtract.outer(np.arange(5.0), np.arange(5.0)))  # 5 points on a line
    flat = cshapes.classical_mds(line, dim=2)
    assert re.fullmatch(r"<cshapes\.CanonicalForm: cmds, 5 points in 2-D, \d+ iterations?, [\d.e+-]+ s>",
                        repr(flat)), repr(flat)


def test_a_thousand_points_are_grouped():
    (W, G), = cshapes.generate("articulated", class_="hand", poses=1, vertices=1500, seed=1)
    form = cshapes.canonical_form(W, G, method="cmds", progress=False)
    assert re.search(r"cmds, 1,\d{3} points", repr(form)), repr(form)


def test_alignment_repr():
    a = cshapes.icp(HAND[1][0], V)
    m = re.fullmatch(r"<cshapes\.Alignment: hausdorff (\S+) \((\S+)% of B's bbox diagonal\), rmse (\S+) "
                     r"\((\S+)%\) in the inputs' units, (\d+) ICP iterations?(, a reflection)?>", repr(a))
    assert m, repr(a)
    for number in m.groups()[:4]:
        assert significant_figures(number) <= 3, repr(a)
    assert float(m.group(1)) == pytest.approx(a.hausdorff, rel=5e-3)
    same = cshapes.icp(V, V)
    assert repr(same).startswith("<cshapes.Alignment: hausdorff 0 (0% of B's bbox diagonal), rmse 0 (0%)")


def test_version_is_the_projects():
    project = re.search(r"project\(cshapes\s+VERSION\s+([\d.]+)", (ROOT / "CMakeLists.txt").read_text())
    assert project, "CMakeLists.txt: project(cshapes VERSION ...)"
    assert cshapes.__version__ == project.group(1) == cshapes.build_info()["version"]


@pytest.mark.parametrize("name", ["build_info", "canonical_form_methods", "generate", "geodesics", "mesh_info",
                                  "method_options"])
def test_the_examples_that_need_no_files_print_what_they_show(name):
    """The Examples of the functions whose examples are quick and deterministic, run as doctests (the others
    read files or print timings)."""
    import doctest
    test = doctest.DocTestParser().get_doctest(getattr(cshapes, name).__doc__, {"cshapes": cshapes}, name,
                                               None, 0)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    runner.run(test)
    assert runner.failures == 0 and runner.tries > 0, name


def test_warnings_point_at_the_callers_line():
    W, G = cshapes.generate("icosphere", subdivisions=1)
    two = (np.vstack([W, W + 3]), np.vstack([G, G + len(W)]))  # two components: repaired, with a warning
    with pytest.warns(UserWarning, match="cshapes.geodesics") as caught:
        cshapes.geodesics(*two, 0, method="graph")
    assert caught[0].filename == __file__, caught[0].filename
