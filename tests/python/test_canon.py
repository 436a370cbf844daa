"""Canonical forms from Python against the CLI on the same input (identical forms for identical options),
option handling, and the GIL released while they run."""
import subprocess
import sys
import threading

import numpy as np
import pytest

import cshapes


def cli_form(cli, mesh, tmp_path, *args):
    out = tmp_path / "form.ply"
    summary = cli.json("canon", mesh, "-o", out, "--json", *args)
    X, F, fields = cshapes.read_mesh(out, fields=True)
    return X, fields, summary


def test_coulomb_is_the_cli_canon(cli, shapes, tmp_path):
    V, F = cshapes.read_mesh(shapes[0])
    form = cshapes.coulomb(V, F)
    X, fields, summary = cli_form(cli, shapes[0], tmp_path, "--method", "coulomb")
    np.testing.assert_array_equal(form.X, X)
    np.testing.assert_array_equal(form.torn, fields["torn"])
    assert form.iterations == summary["iterations"]
    assert form.summary["energy"] == summary["energy"]
    assert set(form.history) >= {"energy", "mean_violation"}
    assert len(form.history["energy"]) == form.iterations


def test_coulomb_options_are_the_cli_options(cli, shapes, tmp_path):
    V, F = cshapes.read_mesh(shapes[1])
    form = cshapes.coulomb(V, F, scheme="paper", tear_fraction=0, coulomb_max_iterations=40, step_factor=0.05)
    X, _, _ = cli_form(cli, shapes[1], tmp_path, "--scheme", "paper", "--tear-fraction", "0",
                       "--coulomb-max-iterations", "40", "--step-factor", "0.05")
    np.testing.assert_array_equal(form.X, X)
    assert form.iterations == 40 and not form.torn.any()


def test_multiresolution_options_are_the_cli_options(cli, shapes, tmp_path):
    V, F = cshapes.read_mesh(shapes[0])  # ~900 vertices: through a 400-vertex version when above 600
    kwargs = dict(coulomb_multiresolution_above=600, coulomb_coarse_vertices=400, coulomb_tear_rounds=2,
                  coulomb_max_iterations=60, tear_after=30)
    form = cshapes.coulomb(V, F, **kwargs)
    X, _, summary = cli_form(cli, shapes[0], tmp_path, "--coulomb-multiresolution-above", "600",
                             "--coulomb-coarse-vertices", "400", "--coulomb-tear-rounds", "2",
                             "--coulomb-max-iterations", "60", "--tear-after", "30")
    np.testing.assert_array_equal(form.X, X)
    assert summary["multiresolution"].startswith("multiresolution: 9")  # ~900 vertices through ~400
    assert form.summary["multiresolution"].startswith("multiresolution: 9")
    single = cshapes.coulomb(V, F, coulomb_multiresolution_above=0, coulomb_max_iterations=20)
    assert single.summary["multiresolution"] == "single level (multiresolution off)"
    with pytest.raises(ValueError, match="coulomb_coarse_vertices"):
        cshapes.coulomb(V, F, coulomb_multiresolution_above=0, coulomb_coarse_vertices=400)


def test_fold_overstretch_is_read_for_landmark_smacof_only(shapes):
    V, F = cshapes.read_mesh(shapes[0])
    form = cshapes.canonical_form(V, F, method="smacof", mds_solver="landmarks", mds_landmarks=40,
                                  smacof_max_iterations=10, fold_overstretch=0)
    assert form.summary["smacof"]["fold_repair"]["replaced_points"] == 0
    with pytest.raises(ValueError, match="fold_overstretch"):
        cshapes.canonical_form(V, F, method="smacof", mds_solver="full", fold_overstretch=2)
    with pytest.raises(ValueError, match="above 1"):
        cshapes.canonical_form(V, F, method="smacof", mds_solver="landmarks", fold_overstretch=0.5)
    with pytest.raises((TypeError, ValueError), match="fold_overstretch"):
        cshapes.canonical_form(V, F, method="cmds", fold_overstretch=2)


@pytest.mark.parametrize("method, args", [("cmds", []), ("smacof", ["--smacof-max-iterations", "15"])])
def test_mds_forms_are_the_cli_canon(cli, shapes, tmp_path, method, args):
    V, F = cshapes.read_mesh(shapes[0])
    kwargs = {"smacof_max_iterations": 15} if method == "smacof" else {}
    form = cshapes.canonical_form(V, F, method=method, **kwargs)
    X, _, summary = cli_form(cli, shapes[0], tmp_path, "--method", method, *args)
    np.testing.assert_array_equal(form.X, X)
    assert form.torn is None


@pytest.mark.parametrize("method, kwargs, args", [
    ("lbo", {}, []),
    ("lbo", {"laplacian": "cotangent", "eigenpairs": 8}, ["--laplacian", "cotangent", "--eigenpairs", "8"]),
    ("diffusion", {"diffusion_time": 0.5}, ["--diffusion-time", "0.5"]),
    ("spectral-mds", {"basis": 20, "sources": 60, "geodesics": "heat"},
     ["--basis", "20", "--sources", "60", "--geodesics", "heat"]),
])
def test_spectral_forms_are_the_cli_canon(cli, shapes, tmp_path, method, kwargs, args):
    V, F = cshapes.read_mesh(shapes[0])
    form = cshapes.canonical_form(V, F, method=method, **kwargs)
    X, _, summary = cli_form(cli, shapes[0], tmp_path, "--method", method, *args)
    np.testing.assert_array_equal(form.X, X)
    assert form.summary["eigenvalues"] == summary["eigenvalues"]
    assert len(summary["eigenvalues"]) == kwargs.get("eigenpairs", kwargs.get("basis", 10))
    assert summary["laplacian"] == kwargs.get("laplacian", "intrinsic-delaunay")


def test_spectral_options_are_checked_by_name(shapes):
    V, F = cshapes.read_mesh(shapes[0])
    with pytest.raises(ValueError, match="diffusion_time applies to method 'diffusion' only"):
        cshapes.canonical_form(V, F, method="lbo", diffusion_time=2.0)
    with pytest.raises(ValueError, match="eigenpairs applies to method 'lbo' or 'diffusion' only, not 'cmds'"):
        cshapes.canonical_form(V, F, method="cmds", eigenpairs=12)
    with pytest.raises(ValueError, match="laplacian: unknown 'graph'; known: intrinsic-delaunay, cotangent"):
        cshapes.canonical_form(V, F, method="lbo", laplacian="graph")
    with pytest.raises(ValueError, match="eigenpairs: expected an integer 5..500, got 2"):
        cshapes.canonical_form(V, F, method="diffusion", eigenpairs=2)


def test_classical_mds_and_smacof_of_a_matrix_recover_a_point_set():
    rng = np.random.default_rng(0)
    P = rng.normal(size=(60, 3)) * [3.0, 2.0, 1.0]
    D = np.linalg.norm(P[:, None] - P[None], axis=2)
    X = cshapes.classical_mds(D).X
    np.testing.assert_allclose(np.linalg.norm(X[:, None] - X[None], axis=2), D, atol=1e-8 * D.max())
    assert cshapes.classical_mds(D, dim=2).X.shape == (60, 2)
    s = cshapes.smacof(D.astype(np.float32), smacof_max_iterations=50)
    assert s.summary["smacof"]["normalized_stress"] < 1e-6
    assert len(s.history["normalized_stress"]) == s.iterations + 1
    start = cshapes.smacof(D, X0=P + 0.01, smacof_max_iterations=200)
    assert start.summary["smacof"]["normalized_stress"] < 1e-6
    assert cshapes.classical_mds(D).summary["classical_mds"]["explained_energy"] > 1 - 1e-9
    with pytest.raises(ValueError, match="dim"):
        cshapes.classical_mds(D, dim=4)
    with pytest.raises(ValueError, match=r"D: expected a square \(n, n\)"):
        cshapes.classical_mds(D[:5])


def test_options_are_checked_by_name(shapes):
    V, F = cshapes.read_mesh(shapes[0])
    with pytest.raises(TypeError, match="unexpected keyword argument 'tear_fractoin'.*tear_fraction"):
        cshapes.coulomb(V, F, tear_fractoin=0.1)
    with pytest.raises(ValueError, match="fixed_step applies to step_rule='fixed' only"):
        cshapes.coulomb(V, F, fixed_step=0.1)
    with pytest.raises(ValueError, match="scheme: unknown 'fast'; known: paper, momentum"):
        cshapes.coulomb(V, F, scheme="fast")
    with pytest.raises(ValueError, match="step_factor: expected a number > 0, got -1"):
        cshapes.coulomb(V, F, step_factor=-1)
    with pytest.raises(ValueError, match="step_factor: expected a number"):
        cshapes.coulomb(V, F, step_factor="big")
    with pytest.raises(ValueError, match="smacof_max_iterations applies to method 'smacof' only"):
        cshapes.canonical_form(V, F, method="cmds", smacof_max_iterations=3)
    with pytest.raises(ValueError, match="tear_fraction applies to method 'coulomb' only"):
        cshapes.canonical_form(V, F, method="smacof", tear_fraction=0.1)


def test_methods_are_the_library_registry(shapes):
    methods = cshapes.canonical_form_methods()
    assert [m["name"] for m in methods] == ["coulomb", "cmds", "smacof", "lbo", "diffusion", "spectral-mds"]
    assert [m["title"] for m in methods] == ["Coulomb", "classical MDS", "SMACOF", "LBO eigenmap", "diffusion map",
                                             "spectral MDS"]
    assert [m["uses_geodesic_matrix"] for m in methods] == [False, True, True, False, False, False]
    V, F = cshapes.read_mesh(shapes[0])
    with pytest.raises(ValueError, match="unknown canonization method 'pca'; known: coulomb, cmds, smacof, lbo, "
                                         "diffusion, spectral-mds"):
        cshapes.canonical_form(V, F, method="pca")
    with pytest.raises(ValueError, match="init: unknown 'random'; known: cmds, mesh"):
        cshapes.canonical_form(V, F, method="smacof", init="random")
    with pytest.raises(ValueError, match="weights: unknown 'areas'; known: uniform, area"):
        cshapes.canonical_form(V, F, method="smacof", weights="areas")


def test_integers_beyond_range_are_named_by_keyword(shapes):
    # Issue 22: coulomb_max_iterations=2**70 gave "Unable to cast Python instance to C++ type".
    V, F = cshapes.read_mesh(shapes[0])
    with pytest.raises(ValueError, match=r"coulomb\(\): coulomb_max_iterations: expected an integer 0..100000000, "
                                         r"got 1180591620717411303424"):
        cshapes.coulomb(V, F, coulomb_max_iterations=2**70)
    with pytest.raises(ValueError, match=r"coulomb_window: expected an integer 1..100000000, got 4294967296"):
        cshapes.coulomb(V, F, coulomb_window=2**32)
    with pytest.raises(ValueError, match=r"coulomb_window: expected an integer 1..100000000, got 2.5"):
        cshapes.coulomb(V, F, coulomb_window=2.5)


NEGATIVE_KEYWORDS = [
    # (function, keyword, bad value, the limit's words)
    ("coulomb", "coulomb_max_iterations", -5, "an integer 0..100000000"),
    ("coulomb", "coulomb_window", -1, "an integer 1..100000000"),
    ("coulomb", "coulomb_tolerance", -1.0, "a number >= 0"),
    ("coulomb", "coulomb_accuracy", -1.0, "a number in [1e-12, 1]"),
    ("coulomb", "coulomb_steps", -1, "an integer 1..1000000"),
    ("coulomb", "projection_steps", -1, "an integer 0..1000000"),
    ("coulomb", "dilation", -1.0, "a number >= 1"),
    ("coulomb", "step_factor", -1.0, "a number > 0"),
    ("coulomb", "tear_fraction", -1.0, "a number in [0, 0.99]"),
    ("coulomb", "tear_after", -1, "an integer 0..100000000"),
    ("coulomb", "momentum", -1.0, "a number in [0, 0.999]"),
    ("smacof", "smacof_max_iterations", -1, "an integer 0..100000000"),
    ("smacof", "smacof_tolerance", -1.0, "a number >= 0"),
    ("add_topological_noise", "glue", -1, "an integer 0..10000"),
    ("add_topological_noise", "max_gap", -1.0, "a number >= 0"),
    ("add_topological_noise", "separation", -1.0, "a number in [0, 1]"),
    ("add_topological_noise", "min_ratio", 0.5, "a number >= 1"),
    ("add_topological_noise", "relax", -1, "an integer 0..100"),
    ("icp", "trim", -1.0, "a number in [0, 0.9]"),
    ("icp", "icp_tolerance", -1.0, "a number >= 0"),
]


@pytest.mark.parametrize("function,keyword,value,words", NEGATIVE_KEYWORDS)
def test_a_keyword_out_of_its_limit_is_named_by_the_keyword(shapes, function, keyword, value, words):
    # Issue 22: negative keywords were named by their C++ field ("coulomb: max_iterations must be >= 0"),
    # not by the keyword; the limit is the library's, as the CLI's help shows it (support/option_limits.h).
    V, F = cshapes.read_mesh(shapes[0])
    if function == "smacof":
        call = lambda: cshapes.smacof(np.ones((5, 5)) - np.eye(5), **{keyword: value})
    elif function == "icp":
        call = lambda: cshapes.icp(V, V, **{keyword: value})
    else:
        call = lambda: getattr(cshapes, function)(V, F, **{keyword: value})
    with pytest.raises(ValueError) as error:
        call()
    message = str(error.value)
    assert f"{function}(): {keyword}: expected {words}, got" in message, message


def test_generate_refuses_values_beyond_its_limits():
    with pytest.raises(ValueError, match=r"generate\(\): radius: expected a number > 0, got -1"):
        cshapes.generate("icosphere", radius=-1.0)
    with pytest.raises(ValueError, match=r"generate\(\): amplitude: expected a number in \[0, 1\], got -1"):
        cshapes.generate("articulated", amplitude=-1.0)
    with pytest.raises(ValueError, match=r"generate\(\): poses: expected an integer 1..100000, got 0"):
        cshapes.generate("articulated", poses=0)


def test_geodesics_refuse_an_empty_list_of_sources(shapes):
    # Issue 22: sources=[] returned an empty float64 array instead of saying the list is empty.
    V, F = cshapes.read_mesh(shapes[0])
    with pytest.raises(ValueError, match="sources: an empty list"):
        cshapes.geodesics(V, F, [])


CTRL_C_CHILD = """
import os, signal, sys, threading
import numpy as np
import cshapes
# A shell without job control starts background jobs with SIGINT ignored, and children inherit that;
# the test is about what cshapes does with a Ctrl-C the interpreter hears, so hear it.
signal.signal(signal.SIGINT, signal.default_int_handler)
V, F = cshapes.read_mesh(sys.argv[1])
threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
try:
    cshapes.{call}
except KeyboardInterrupt:
    # The next call is not stopped by the Ctrl-C that stopped this one.
    assert np.isfinite(cshapes.geodesics(V, F, 0, method="fmm")).all()
    sys.exit(3)
sys.exit(0)
"""


@pytest.mark.parametrize(
    "call",
    [
        "coulomb(V, F, coulomb_max_iterations=10**8, coulomb_tolerance=0, tear_fraction=0)",
        "canonical_form(V, F, method='smacof', geodesics='graph', smacof_max_iterations=10**8,"
        " smacof_tolerance=0)",
        # Issue 22: Ctrl-C in every long call, also those whose loops run in OpenMP regions (minutes each).
        "geodesics(*cshapes.generate('icosphere', subdivisions=4), method='exact')",
        "canonical_form(*cshapes.generate('icosphere', subdivisions=4), method='cmds', geodesics='exact')",
        "distance_matrix([np.random.default_rng(i).normal(size=(4000, 3)) for i in range(80)])",
    ],
)
def test_ctrl_c_stops_a_long_call(shapes, call):
    # Issue 22: Ctrl-C during cshapes.coulomb was honoured only when the call returned (469 s in the probe).
    # The calls below would run for days; the child hears Ctrl-C half a second in. The timeout only guards
    # against the hang the bug was: it is no measurement.
    result = subprocess.run(
        [sys.executable, "-c", CTRL_C_CHILD.replace("{call}", call), str(shapes[0])],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert result.returncode == 3, result.stderr


def test_a_mesh_with_two_pieces_is_repaired_and_keeps_its_vertex_count():
    V, F = cshapes.generate("icosphere", subdivisions=3)
    V2 = np.vstack([V, V[:3] * 0.1 + 5])
    F2 = np.vstack([F, [[len(V), len(V) + 1, len(V) + 2]]])
    form = cshapes.coulomb(V2, F2, coulomb_max_iterations=30)
    assert form.X.shape == (len(V2), 3)
    assert np.isnan(form.X[len(V):]).all() and np.isfinite(form.X[: len(V)]).all()
    np.testing.assert_array_equal(form.valid, np.r_[np.ones(len(V)), np.zeros(3)])
    assert "largest component" in form.summary["repair"]
    with pytest.raises(ValueError, match="components"):
        cshapes.coulomb(V2, F2, strict=True)


def test_two_threads_canonize_at_once_with_the_gil_released(shapes):
    """Both threads get the serial answer, and the interpreter keeps running Python while they compute:
    with the GIL held, the counting loop below could not advance during the computations."""
    meshes = [cshapes.read_mesh(path) for path in shapes]
    options = dict(tear_fraction=0, coulomb_max_iterations=300, coulomb_tolerance=0)
    cshapes.set_num_threads(1)
    try:
        serial = [cshapes.coulomb(V, F, **options).X for V, F in meshes]
        results = [None, None]

        def work(k):
            results[k] = cshapes.coulomb(*meshes[k], **options).X

        threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]
        count = 0
        for t in threads:
            t.start()
        while any(t.is_alive() for t in threads):
            count += 1
        for t in threads:
            t.join()
    finally:
        cshapes.set_num_threads(0)
    for k in range(2):
        np.testing.assert_array_equal(results[k], serial[k])
    # 300 iterations on ~900 vertices take a good fraction of a second; the loop turns millions of times a
    # second when it holds the interpreter, and at most a few thousand when the workers hold the GIL.
    assert count > 100_000, count
