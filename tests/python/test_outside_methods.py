"""Methods from outside through the Python door (docs/outside-methods.md): a function (V, F) -> X enters an
experiment under the built-ins' protocol; the command door from Python gives the same distances; a function
that raises, or returns a broken form, leaves that shape out for it by name, and the run goes on."""
import json

import numpy as np
import pytest

import cshapes


def principal_axes(V, F):
    X = V - V.mean(axis=0)
    _, vectors = np.linalg.eigh(X.T @ X)
    X = X @ vectors[:, ::-1]
    return X * np.where((X ** 3).sum(axis=0) < 0, -1.0, 1.0)


@pytest.fixture(scope="module")
def dataset(cli, tmp_path_factory):
    folder = tmp_path_factory.mktemp("outside-data")
    cli("generate", "dataset", "--out", folder / "data", "--classes", "2", "--poses", "3", "--noisy", "0",
        "--vertices", "300", "--seed", "2")
    return folder


def test_a_function_and_a_command_give_the_same_distances(dataset, tmp_path):
    script = tmp_path / "pca.py"
    script.write_text("import sys, numpy as np\n"
                      "w = open(sys.argv[1]).read().split(); n = int(w[1])\n"
                      "V = np.array(w[4:4 + 3 * n], dtype=float).reshape(n, 3)\n"
                      "X = V - V.mean(axis=0); _, E = np.linalg.eigh(X.T @ X); X = X @ E[:, ::-1]\n"
                      "np.save(sys.argv[2], X * np.where((X ** 3).sum(axis=0) < 0, -1.0, 1.0))\n")
    by_function = cshapes.experiment_retrieval(dataset / "data", tmp_path / "fn", methods=[("pca", principal_axes)],
                                               draw=False)
    by_command = cshapes.experiment_retrieval(
        dataset / "data", tmp_path / "cmd", methods=[("pca", f"cmd:/usr/bin/python3 {script} {{mesh}} {{form.npy}}")],
        draw=False)
    assert by_function["measures"] == by_command["measures"]
    assert (tmp_path / "fn" / "pca" / "hausdorff.csv").read_bytes() == \
        (tmp_path / "cmd" / "pca" / "hausdorff.csv").read_bytes()
    doors = json.loads((tmp_path / "fn" / "outside-methods.json").read_text())
    assert doors == [{"name": "pca", "door": "python", "text": "principal_axes"}]
    # Registered for the call only.
    assert "pca" not in [m["name"] for m in cshapes.canonical_form_methods()]


def test_a_function_that_fails_on_a_shape_leaves_that_shape_out_by_name(dataset, tmp_path):
    calls = []

    def broken(V, F):  # the second shape: NaN; the third: 3 points (retrieval takes any 4); the others: good
        calls.append(len(V))
        if len(calls) == 2:
            return np.full((len(V), 3), np.nan)
        return principal_axes(V, F)[:3] if len(calls) == 3 else principal_axes(V, F)

    r = cshapes.experiment_retrieval(dataset / "data", tmp_path / "out", methods=["lbo", ("broken", broken)],
                                     draw=False)
    left_out = {f["name"]: f["reason"] for f in r["failures"] if f["method"] == "broken"}
    assert len(left_out) == 2, r["failures"]
    reasons = " ".join(left_out.values())
    assert "not finite" in reasons and "the form has 3 rows, expected at least 4 points" in reasons
    assert not [f for f in r["failures"] if f["method"] == "lbo" and f["left_out"]]
    assert r["measures"]["broken"]["hausdorff"]["map"] > 0

    def raises(V, F):
        raise ValueError("this method needs a watertight mesh")

    with pytest.raises(ValueError, match="at least 2"):  # every shape left out: nothing to measure
        cshapes.experiment_retrieval(dataset / "data", tmp_path / "out2", methods=[("raises", raises)], draw=False)


def test_a_name_of_the_library_and_a_bad_door_are_refused(dataset, tmp_path):
    with pytest.raises(ValueError, match="cshapes's own"):
        cshapes.experiment_retrieval(dataset / "data", tmp_path / "a", methods=[("lbo", principal_axes)], draw=False)
    with pytest.raises(ValueError, match="cmd:COMMAND or forms:DIR"):
        cshapes.experiment_retrieval(dataset / "data", tmp_path / "b", methods=[("x", "ssh:true")], draw=False)
    with pytest.raises(ValueError, match="expected a function"):
        cshapes.experiment_retrieval(dataset / "data", tmp_path / "c", methods=[("x", 3)], draw=False)


def test_canonical_form_takes_a_function_and_checks_its_form(dataset):
    V, F = cshapes.read_mesh(dataset / "data" / "biped0.off")
    form = cshapes.canonical_form(V, F, method=principal_axes)
    np.testing.assert_array_equal(form.X, principal_axes(V, F))
    assert form.summary["method"] == "principal_axes" and form.summary["door"] == "python"
    assert form.summary["form_quality"]["ok"]
    named = cshapes.canonical_form(V, F, method=("mine", principal_axes))
    np.testing.assert_array_equal(named.X, form.X)
    assert "mine" not in [m["name"] for m in cshapes.canonical_form_methods()]  # for the call only
    with pytest.raises(ValueError, match="method wrong: the form has 5 rows, expected one per vertex"):
        cshapes.canonical_form(V, F, method=("wrong", lambda V, F: V[:5]))
    with pytest.raises(ValueError, match="not finite"):
        cshapes.canonical_form(V, F, method=lambda V, F: V * np.nan)
    with pytest.raises(ValueError, match="a function fn"):
        cshapes.canonical_form(V, F, method=3)
    with pytest.raises(TypeError, match="method_timeout"):  # a built-in method has no time limit
        cshapes.canonical_form(V, F, method="lbo", method_timeout=5)
