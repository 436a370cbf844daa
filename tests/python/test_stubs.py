"""The type stubs (python/_cshapes.pyi) against the module, so what editors and help() readers see cannot drift:
every public function of the module is in the stubs and every stub is a function of the module; every keyword
a function reads is in its stub (the module lists the keywords it reads when refusing an unknown one), and none
is in a stub that no call path reads; and each stub default gives the same result as leaving the keyword out.
"""
import ast
import inspect
import re
from pathlib import Path

import numpy as np
import pytest

import cshapes

ROOT = Path(__file__).resolve().parents[2]
STUB = ROOT / "python" / "_cshapes.pyi"


def stub_functions():
    """{name: [ast.FunctionDef, ...]} (overloads give several)."""
    tree = ast.parse(STUB.read_text())
    out = {}
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            out.setdefault(node.name, []).append(node)
    return out


def stub_keywords(defs):
    """{keyword: default} of the keyword-only and defaulted parameters of every overload."""
    out = {}
    for d in defs:
        a = d.args
        positional = a.posonlyargs + a.args
        for arg, default in zip(positional[len(positional) - len(a.defaults):], a.defaults):
            out[arg.arg] = ast.literal_eval(default)
        for arg, default in zip(a.kwonlyargs, a.kw_defaults):
            if default is not None:
                out[arg.arg] = ast.literal_eval(default)
    return out


def overload_for(defs, kind):
    """The overload of generate() whose `kind` is Literal[kind]."""
    for d in defs:
        annotation = ast.unparse(d.args.args[0].annotation)
        if f"'{kind}'" in annotation or f'"{kind}"' in annotation:
            return [d]
    raise AssertionError(f"no overload for {kind!r}")


def read_keywords(call):
    """The keywords the function reads on this call's path: from its refusal of an unknown one."""
    with pytest.raises(TypeError) as e:
        call(__probe__=1)
    m = re.search(r"its options: (.*)$", str(e.value))
    assert m, str(e.value)
    return set(m.group(1).split(", ")) if m.group(1) else set()


def explicit_keywords(function):
    """The keywords pybind11 declares itself (its signature line), with their defaults."""
    line = (function.__doc__ or "").splitlines()[0]
    signature = re.sub(r"->.*$", "", line)
    names = re.findall(r"(\w+): [^,()=]+(?:\[[^\]]*\])?(?: = ([^,)]+))?", signature)
    return {n for n, _ in names}


V, F = cshapes.generate("icosphere", subdivisions=1)
HAND = cshapes.generate("articulated", class_="hand", poses=2, vertices=400, seed=3)
A, B = HAND[0][0], HAND[1][0]
D = cshapes.geodesics(*HAND[0], method="fmm").astype(np.float64)


def test_every_function_is_in_the_stubs_and_back():
    stubs = stub_functions()
    public = {n for n in dir(cshapes._cshapes) if not n.startswith("_")
              and callable(getattr(cshapes._cshapes, n)) and not inspect.isclass(getattr(cshapes._cshapes, n))}
    assert public == set(stubs), (public ^ set(stubs))


CALLS = {
    # name: [(a call on this path, {its keywords in the stub that this path reads})]
    # A hand, not a sphere: its Coulomb form takes hundreds of iterations, so tearing and stopping defaults show.
    "coulomb": [lambda **k: cshapes.coulomb(*HAND[0], **k)],
    "canonical_form": [lambda **k: cshapes.canonical_form(*HAND[0], method="coulomb", **k),
                       lambda **k: cshapes.canonical_form(*HAND[0], method="cmds", **k),
                       lambda **k: cshapes.canonical_form(*HAND[0], method="smacof", **k),
                       lambda **k: cshapes.canonical_form(*HAND[0], method="lbo", **k),
                       lambda **k: cshapes.canonical_form(*HAND[0], method="diffusion", **k),
                       lambda **k: cshapes.canonical_form(*HAND[0], method="spectral-mds", **k),
                       lambda **k: cshapes.canonical_form(*HAND[0], method=("outside", lambda V, F: V), **k)],
    "smacof": [lambda **k: cshapes.smacof(D, **k)],
    "icp": [lambda **k: cshapes.icp(A, B, **k)],
    "shape_distance": [lambda **k: cshapes.shape_distance(A, B, **k)],
    "distance_matrix": [lambda **k: cshapes.distance_matrix([A, B], **k)],
    "add_topological_noise": [lambda **k: cshapes.add_topological_noise(*cshapes.generate("hand")["separated"], **k)],
    "generate": [lambda **k: cshapes.generate("swissroll", **k),
                 lambda **k: cshapes.generate("icosphere", **k),
                 lambda **k: cshapes.generate("articulated", **k),
                 lambda **k: cshapes.generate("hand", **k),
                 lambda **k: cshapes.generate("dataset", **k)],
    "experiment_paper": [lambda **k: cshapes.experiment_paper("/nonexistent", "/nonexistent", **k)],
    "experiment_retrieval": [lambda **k: cshapes.experiment_retrieval("/nonexistent", "/nonexistent", **k)],
    "experiment_invariance": [lambda **k: cshapes.experiment_invariance("/nonexistent", "/nonexistent", **k)],
}


@pytest.mark.parametrize("name", sorted(CALLS))
def test_the_stub_lists_exactly_the_keywords_the_function_reads(name):
    function = getattr(cshapes._cshapes, name)  # the extension's own, whose docstring pybind11 begins
    in_stub = set(stub_keywords(stub_functions()[name]))
    read = set()
    for call in CALLS[name]:
        read |= read_keywords(call)
    declared = explicit_keywords(function)
    assert read - in_stub == set(), f"{name}: keywords the module reads but the stub lacks"
    assert in_stub - read - declared == set(), f"{name}: keywords in the stub that the module never reads"


def same(a, b):
    if isinstance(a, cshapes.CanonicalForm):
        return np.allclose(a.X, b.X, equal_nan=True)
    if isinstance(a, cshapes.Alignment):
        return np.allclose(a.transform, b.transform)
    if isinstance(a, (tuple, list)):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(same(a[k], b[k]) for k in a if k not in ("seconds",))
    if isinstance(a, np.ndarray):
        return np.array_equal(a, b, equal_nan=True)
    if isinstance(a, float):
        return a == pytest.approx(b)
    return a == b


DEFAULT_CHECKS = ["coulomb", "canonical_form", "smacof", "icp", "shape_distance", "distance_matrix", "generate"]


# Calls made small where the defaults make a large result: each keyword's default is checked with the others
# kept small (and itself left out of SMALL).
SMALL = {("generate", 2): {"vertices": 400, "poses": 2},
         ("generate", 4): {"vertices": 800, "classes": 1, "poses": 1, "noisy": 1}}


@pytest.mark.parametrize("name", DEFAULT_CHECKS)
def test_each_stub_default_is_the_default(name):
    checked = 0
    bases = {}  # the call without the keyword, once per set of small keywords
    for k, call in enumerate(CALLS[name]):
        defs = stub_functions()[name]
        if name == "generate":
            defs = overload_for(defs, ["swissroll", "icosphere", "articulated", "hand", "dataset"][k])
        defaults = stub_keywords(defs)
        reads = read_keywords(call)
        for keyword in sorted(reads):
            if keyword not in defaults or defaults[keyword] is None:
                continue
            small = {x: v for x, v in SMALL.get((name, k), {}).items() if x != keyword}
            key = (k, tuple(sorted(small.items())))
            if key not in bases:
                bases[key] = call(**small)
            base = bases[key]
            try:
                result = call(**small, **{keyword: defaults[keyword]})
            except ValueError as e:  # given at all, it needs another option (fixed_step needs step_rule='fixed')
                assert "only" in str(e) or "needs" in str(e) or "with" in str(e), f"{name}({keyword}=...): {e}"
                continue
            assert same(result, base), f"{name}: {keyword}={defaults[keyword]!r} in the stub is not its default"
            checked += 1
    assert checked > 0


def test_the_method_signatures_are_generated_from_the_methods_options():
    """coulomb()'s and canonical_form()'s signatures are scripts/make_stub.py's output for this module: a method
    option added, renamed or given another default reaches the stub by running the script, never by hand."""
    import importlib.util
    spec = importlib.util.spec_from_file_location("make_stub", ROOT / "scripts" / "make_stub.py")
    make_stub = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(make_stub)
    text = STUB.read_text()
    start, stop = text.index(make_stub.BEGIN), text.index(make_stub.END) + len(make_stub.END)
    assert text[start:stop] == make_stub.generate(cshapes._cshapes), "run scripts/make_stub.py"
