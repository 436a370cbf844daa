"""cshapes.compare_runs and `cshapes compare` (experiments/compare_runs.h): two retrieval runs of different
methods on one generated collection, one by the CLI and one from Python, merged the same way by both (the same
compare.json and report.md); a run on other data raises ValueError and writes nothing."""
import json

import pytest

import cshapes


def test_python_and_cli_compare_the_same_runs_the_same_way(cli, tmp_path):
    data = tmp_path / "data"
    cli("generate", "dataset", "--out", data, "--classes", "2", "--poses", "3", "--noisy", "0", "--vertices", "300")
    cli("experiment", "retrieval", "--data", data, "--out", tmp_path / "cmds", "--methods", "cmds", "--no-draw",
        "--geodesics", "graph")
    cshapes.experiment_retrieval(str(data), str(tmp_path / "lbo"), methods="lbo", draw=False)
    runs = [str(tmp_path / "cmds"), str(tmp_path / "lbo")]
    result = cshapes.compare_runs(runs, tmp_path / "py", draw=False)
    cli("compare", *runs, "--out", tmp_path / "cli", "--no-draw")
    assert result["shapes"] == 6 and result["runs"] == {"cmds": runs[0], "lbo": runs[1]}
    for name in ("compare.json", "report.md"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    merged = json.loads((tmp_path / "py" / "compare.json").read_text())
    own = json.loads((tmp_path / "lbo" / "retrieval.json").read_text())
    assert merged["inputs"]["digest"] == own["inputs"]["digest"]
    assert result["measures"]["lbo"]["hausdorff"]["map"] == own["methods"][0]["distances"]["hausdorff"]["map"]

    other = tmp_path / "other"
    cli("generate", "dataset", "--out", other, "--classes", "2", "--poses", "3", "--noisy", "0", "--vertices", "300",
        "--seed", "2")
    cshapes.experiment_retrieval(str(other), str(tmp_path / "lbo-other"), methods="lbo", draw=False)
    with pytest.raises(ValueError, match="not run on the same data"):
        cshapes.compare_runs([runs[0], str(tmp_path / "lbo-other")], tmp_path / "refused")
    assert not (tmp_path / "refused").exists()
