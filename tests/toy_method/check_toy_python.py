#!/usr/bin/env python3
"""The toy method (tests/toy_method/method_toy.cpp) in a Python module built with it (build/toy_python, on
PYTHONPATH): listed by canonical_form_methods() with its keywords, computed by canonical_form(method='toy'),
its keywords refused by the other methods, shown in canonical_form()'s signature and docstring, and its
signature in the stub scripts/make_stub.py writes for this module (the committed stub, written for the library's methods, then fails the stub check). Run by CTest
(ToyMethod.PythonModuleAndStub); exits 1 at the first failed check."""
import importlib.util
import inspect
import sys
from pathlib import Path

import numpy as np

import cshapes

ROOT = Path(__file__).resolve().parents[2]


def check(condition, what):
    if not condition:
        print("FAILED:", what, file=sys.stderr)
        sys.exit(1)


methods = {m["name"]: m for m in cshapes.canonical_form_methods()}
check("toy" in methods, "canonical_form_methods() lists toy")
check(methods["toy"]["keywords"] == ["toy_scale", "toy_mirror"], f"toy's keywords: {methods['toy']}")

V, F = cshapes.generate("icosphere", subdivisions=1)
form = cshapes.canonical_form(V, F, method="toy", toy_scale=3.0, toy_mirror="x")
expected = (V - V.mean(axis=0)) * 3.0
expected[:, 0] *= -1
check(np.allclose(form.X, expected, atol=1e-12), "canonical_form(method='toy') is the scaled mirrored mesh")

for call, what in [(lambda: cshapes.coulomb(V, F, toy_scale=2.0), "coulomb() refuses toy_scale"),
                   (lambda: cshapes.canonical_form(V, F, method="toy", toy_scale=-1.0), "toy_scale > 0"),
                   (lambda: cshapes.canonical_form(V, F, method="toy", toy_mirror="w"), "toy_mirror's choices"),
                   (lambda: cshapes.canonical_form(V, F, method="toy", scheme="paper"), "toy refuses scheme")]:
    try:
        call()
        check(False, what)
    except ValueError as e:
        message = str(e)
        check("toy" in message or "scheme" in message, f"{what}: {message}")
try:
    cshapes.coulomb(V, F, toy_scale=2.0)
except ValueError as e:
    check("toy_scale applies to method 'toy' only, not 'coulomb'" in str(e), str(e))

# Its keywords in canonical_form()'s signature and documentation, from its own declarations (cshapes/_api.py).
signature = inspect.signature(cshapes.canonical_form)
check(signature.parameters["toy_scale"].default == 2.0 and signature.parameters["toy_mirror"].default == "none",
      f"canonical_form()'s signature shows the toy's keywords: {signature}")
check("toy_scale : float, default 2.0" in cshapes.canonical_form.__doc__,
      "canonical_form()'s docstring describes toy_scale")

spec = importlib.util.spec_from_file_location("make_stub", ROOT / "scripts" / "make_stub.py")
make_stub = importlib.util.module_from_spec(spec)
spec.loader.exec_module(make_stub)
block = make_stub.generate(cshapes._cshapes)
check('toy_scale: float = 2.0' in block and 'toy_mirror: Literal["none", "x", "y", "z"] = "none"' in block,
      "the generated stub has the toy's keywords:\n" + block)
check("toy_scale: toy" in block, "the generated stub's comment names toy as toy_scale's reader")
committed = (ROOT / "python" / "_cshapes.pyi").read_text()
check(block not in committed, "the committed stub (the library's methods) differs from this module's")
print("toy method: listed, computed, refused elsewhere, in the signature, the docstring and the generated stub")
