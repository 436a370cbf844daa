"""cshapes.experiment_invariance (`cshapes experiment invariance`): an eigenmap passes, a function whose form
follows the vertex numbers fails on the renumberings, the rows are those expected, the same options write the
same data as the CLI, and a resolution out of range is refused by name."""
import numpy as np
import pytest

import cshapes


@pytest.fixture(scope="module")
def data(cli, tmp_path_factory):
    folder = tmp_path_factory.mktemp("invariance-data")
    cli("generate", "dataset", "--out", folder, "--classes", "1", "--poses", "2", "--noisy", "0", "--vertices",
        "300", "--seed", "2")
    return folder / "manifest.csv"


def numbered(V, F):
    """The mesh with vertex i moved by 2% of its extent times (i mod 5): follows the numbering."""
    X = np.array(V, dtype=float)
    X[:, 0] += 0.02 * np.ptp(X, axis=0).max() * (np.arange(len(X)) % 5)
    return X


def test_an_eigenmap_passes_and_a_numbered_form_fails(data, tmp_path):
    r = cshapes.experiment_invariance(data, tmp_path / "out", methods=["lbo", ("numbered", numbered)], seeds=1)
    verdicts = {(v["method"], v["resolution"]): v for v in r["results"]["verdicts"]}
    assert verdicts[("lbo", "all")]["verdict"] == "pass", verdicts[("lbo", "all")]
    assert verdicts[("numbered", "all")]["verdict"] == "fail"
    assert "renumber" in verdicts[("numbered", 0)]["worst"]
    assert r["failures"] == []
    rows = (tmp_path / "out" / "invariance.csv").read_text().splitlines()
    assert len(rows) == 1 + 2 * 2 * (1 + 5 + 2)  # shapes × methods × (renumbering, 5 exact, 2 remeshes)
    assert (tmp_path / "out" / "invariance.md").exists()
    pytest.importorskip("matplotlib")
    assert r["results"]["figure"] == "invariance.png" and (tmp_path / "out" / "invariance.png").exists()


def test_python_and_the_cli_write_the_same_data(cli, data, tmp_path):
    cli("experiment", "invariance", "--data", data, "--out", tmp_path / "cli", "--methods", "lbo", "--seeds", "1",
        "--no-draw")
    cshapes.experiment_invariance(data, tmp_path / "py", methods="lbo", seeds=1, draw=False)
    for name in ("invariance_summary.csv", "invariance_pose.csv"):
        assert (tmp_path / "cli" / name).read_bytes() == (tmp_path / "py" / name).read_bytes(), name

    def measures(folder):  # invariance.csv without its last column, the seconds each form took
        return [line.rsplit(",", 1)[0] for line in (folder / "invariance.csv").read_text().splitlines()]

    assert measures(tmp_path / "cli") == measures(tmp_path / "py")


def test_a_resolution_out_of_range_is_refused(data, tmp_path):
    with pytest.raises(ValueError, match="vertices"):
        cshapes.experiment_invariance(data, tmp_path / "out", methods="lbo", vertices=[5])
