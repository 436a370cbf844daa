"""Issue 36: every keyword of canonical_form() a method does not read is refused, naming the keyword, the
methods that read it and the method given; every keyword it reads is accepted.

The module derives its answer from the methods' own option lists (their registrations). The answer expected here
is written out independently, from what each method computes (the CLI's option groups), so a change to the
registry or to the module that lets a keyword through unread, or refuses one a method reads, fails here.
"""
import ast
import re
from pathlib import Path

import numpy as np
import pytest

import cshapes

ROOT = Path(__file__).resolve().parents[2]

METHODS = ["coulomb", "cmds", "smacof", "lbo", "diffusion", "spectral-mds"]
COULOMB = ["coulomb_preset", "scheme", "coulomb_start", "coulomb_start_landmarks", "flatten", "flatten_plane",
           "bridge_detour", "step_rule",
           "step_gradient", "step_factor", "fixed_step", "coulomb_steps", "move_limit", "projection_steps", "projection", "l1_floor",
           "dilation",
           "tear_fraction", "tear_after", "tear_times", "tear_interval", "tear_guard", "coulomb_max_iterations",
           "coulomb_window", "coulomb_tolerance", "momentum", "coulomb_stall_windows", "coulomb_summation", "coulomb_accuracy",
           "coulomb_fmm_rebuild_every",
           "coulomb_multiresolution_above", "coulomb_coarse_vertices", "coulomb_tear_rounds"]

# keyword -> the methods that read it.
READERS = {
    **{k: {"coulomb"} for k in COULOMB},
    # The geodesic matrix's solver (cmds, smacof) and spectral MDS's geodesic rows.
    "geodesics": {"cmds", "smacof", "spectral-mds"},
    # Full or landmark MDS of that matrix, and the landmark form's fold repair.
    "mds_solver": {"cmds", "smacof"}, "mds_landmarks": {"cmds", "smacof"},
    # The landmark form's fold repair is SMACOF's: classical MDS interpolates without one.
    "fold_overstretch": {"smacof"},
    **{k: {"smacof"} for k in ["smacof_max_iterations", "smacof_tolerance", "accelerate", "smacof_window", "init",
                               "weights"]},
    # The Laplace-Beltrami eigenpairs: lbo and diffusion count them, spectral-mds calls them its basis.
    "laplacian": {"lbo", "diffusion", "spectral-mds"}, "near_multiple_gap": {"lbo", "diffusion", "spectral-mds"},
    "eigenpairs": {"lbo", "diffusion"},
    "diffusion_time": {"diffusion"},
    "basis": {"spectral-mds"}, "sources": {"spectral-mds"},
    "knn": set(METHODS), "strict": set(METHODS),
}

# A valid value for each keyword (the stub's default unless given here), and the keywords it needs beside it.
VALUES = {"coulomb_max_iterations": 30, "mds_landmarks": 20, "fold_overstretch": 2.5, "eigenpairs": 6, "basis": 12,
          "sources": 40, "knn": 6}
COMPANIONS = {"fixed_step": {"step_rule": "fixed", "fixed_step": 0.01}, "l1_floor": {"projection": "l1"},
              "smacof_window": {"accelerate": "rre"}, "fold_overstretch": {"mds_solver": "landmarks"},
              "mds_landmarks": {"mds_solver": "landmarks"}}
# Kept small so that each accepted call is quick.
SMALL = {"coulomb": {"coulomb_max_iterations": 30}, "smacof": {"smacof_max_iterations": 10},
         "spectral-mds": {"basis": 12, "sources": 40}}


def stub_defaults():
    tree = ast.parse((ROOT / "python" / "_cshapes.pyi").read_text())
    node = next(n for n in tree.body if isinstance(n, ast.FunctionDef) and n.name == "canonical_form")
    return {a.arg: ast.literal_eval(d) for a, d in zip(node.args.kwonlyargs, node.args.kw_defaults)
            # method_timeout and method_version are a method from outside's (tests/python/test_outside_methods.py),
            # progress every long call's (tests/python/test_api.py)
            if d is not None and a.arg not in ("method", "method_timeout", "method_version", "progress")}


DEFAULTS = stub_defaults()
V, F = cshapes.generate("icosphere", subdivisions=2)  # 162 vertices
POINTS = V + 0.0
NO_FACES = np.zeros((0, 3), dtype=np.int64)


def test_the_table_here_covers_every_keyword_of_canonical_form():
    assert set(READERS) == set(DEFAULTS)
    assert [m["name"] for m in cshapes.canonical_form_methods()] == METHODS


@pytest.mark.parametrize("method", METHODS)
def test_a_keyword_the_method_does_not_read_is_refused_naming_its_readers(method):
    for keyword, readers in READERS.items():
        if method in readers:
            continue
        value = VALUES.get(keyword, DEFAULTS[keyword])
        with pytest.raises(ValueError) as e:
            cshapes.canonical_form(V, F, method=method, **{keyword: value})
        message = str(e.value)
        assert re.search(rf"\b{keyword} applies to method .* only, not '{re.escape(method)}'", message), message
        named = set(re.findall(r"'([a-z-]+)'", message.split(" only, not ")[0]))
        assert named == readers, (keyword, message)


@pytest.mark.parametrize("method", METHODS)
def test_a_keyword_the_method_reads_is_accepted(method):
    for keyword, readers in READERS.items():
        if method not in readers:
            continue
        kwargs = dict(SMALL.get(method, {}))
        kwargs.update(COMPANIONS.get(keyword, {}))
        kwargs.setdefault(keyword, VALUES.get(keyword, DEFAULTS[keyword]))
        if keyword == "knn" and method == "spectral-mds":
            # The registry has it read knn (a point cloud's graph), but spectral-mds refuses point clouds.
            with pytest.raises(ValueError, match="needs a mesh with faces"):
                cshapes.canonical_form(POINTS, NO_FACES, method=method, **kwargs)
            continue
        if keyword == "knn":  # point clouds only: a mesh's own edges are its graph
            form = cshapes.canonical_form(POINTS, NO_FACES, method=method, **kwargs)
        else:
            form = cshapes.canonical_form(V, F, method=method, **kwargs)
        assert form.X.shape == V.shape, (method, keyword)


# Issue 60: one name per meaning; an old keyword is refused naming the new one (pipeline/renamed_options.h, the
# table the CLI refuses the old flags from).
@pytest.mark.parametrize("call, old, new", [
    (lambda: cshapes.canonical_form(V, F, method="smacof", iters=5), "iters", "smacof_max_iterations"),
    (lambda: cshapes.canonical_form(V, F, method="smacof", tolerance=1e-3), "tolerance", "smacof_tolerance"),
    (lambda: cshapes.canonical_form(V, F, method="cmds", landmarks=20), "landmarks", "mds_landmarks"),
    (lambda: cshapes.coulomb(V, F, start_landmarks=20), "start_landmarks", "coulomb_start_landmarks"),
    (lambda: cshapes.smacof(np.ones((4, 4)) - np.eye(4), iters=5), "iters", "smacof_max_iterations"),
    (lambda: cshapes.smacof(np.ones((4, 4)) - np.eye(4), window=4), "window", "smacof_window"),
    (lambda: cshapes.icp(POINTS, POINTS, tolerance=1e-3), "tolerance", "icp_tolerance"),
])
def test_an_old_keyword_is_refused_naming_the_new_one(call, old, new):
    with pytest.raises(TypeError, match=rf"'{old}' is now {new}\b"):
        call()
