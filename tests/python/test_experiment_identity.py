"""Defaults in the library: cshapes.experiment_paper with its defaults writes what `cshapes experiment paper`
writes, byte for byte (report.md, which states the run's time, and the caches aside). The C++ side of the same
check is tests/experiment_identity_test.cpp."""
from pathlib import Path

import cshapes


def _outputs(root: Path):
    files = {}
    for path in sorted(root.rglob("*")):
        relative = path.relative_to(root).as_posix()
        if not path.is_file() or relative == "report.md" or relative.startswith("cache/"):
            continue
        files[relative] = path.read_bytes().replace(str(root).encode(), b"OUT")
    return files


def test_python_and_cli_runs_of_the_paper_experiment_write_the_same_files(cli, tmp_path):
    data = tmp_path / "data"
    cli("generate", "dataset", "--out", data, "--classes", "2", "--poses", "3", "--noisy", "0", "--vertices", "400")
    cli("experiment", "paper", "--data", data / "manifest.csv", "--out", tmp_path / "cli", "--no-table1",
        "--no-figure-data")
    summary = cshapes.experiment_paper(str(data / "manifest.csv"), str(tmp_path / "py"), table1=False,
                                       figure_data=False)
    assert summary["shapes"] == 8 and not summary["failures"]
    a, b = _outputs(tmp_path / "cli"), _outputs(tmp_path / "py")
    assert len(a) > 10 and "metrics.json" in a and "distances/smacof.csv" in a
    assert sorted(a) == sorted(b)
    differing = [name for name in a if a[name] != b[name]]
    assert differing == [], f"written differently by the CLI and Python: {differing}"


def test_python_and_cli_runs_of_the_retrieval_experiment_write_the_same_files(cli, tmp_path):
    """experiment_retrieval(resample=N) and `cshapes experiment retrieval --resample N`: the same files (the
    report, retrieval.json and the figures state times; left aside), and the Python result's measures are
    those of metrics.json."""
    import json

    data = tmp_path / "data"
    cli("generate", "dataset", "--out", data, "--classes", "2", "--poses", "3", "--noisy", "0", "--vertices", "400")
    cli("experiment", "retrieval", "--data", data / "manifest.csv", "--out", tmp_path / "cli", "--methods",
        "coulomb", "--resample", "300", "--no-draw")
    result = cshapes.experiment_retrieval(str(data / "manifest.csv"), str(tmp_path / "py"), methods=["coulomb"],
                                          resample=300, draw=False)
    assert result["shapes"] == 6 and result["resampled"] and not result["failures"]

    def files(root):
        return {k: v for k, v in _outputs(root).items()
                if k != "retrieval.json" and not k.startswith("figures/")}

    a, b = files(tmp_path / "cli"), files(tmp_path / "py")
    assert "coulomb/hausdorff.matrix" in a and "resampled/manifest.csv" in a and "classes.cla" in a
    assert sorted(a) == sorted(b)
    differing = [name for name in a if a[name] != b[name]]
    assert differing == [], f"written differently by the CLI and Python: {differing}"
    metrics = json.loads((tmp_path / "py" / "coulomb" / "hausdorff" / "metrics.json").read_text())
    assert result["measures"]["coulomb"]["hausdorff"]["map"] == metrics["map"]


def test_two_stage_retrieval_reports_recall_and_the_exact_measures(cli, tmp_path):
    """experiment_retrieval(two_stage_k=K, two_stage_reference=EXACT): the candidates' pairs only, recall@K in
    [0, 1], and the exact run's measures as that run computed them; a reference that is the output folder is
    refused before any work (the exact run would be lost)."""
    import pytest

    data = tmp_path / "data"
    cli("generate", "dataset", "--out", data, "--classes", "2", "--poses", "3", "--noisy", "0", "--vertices", "300")
    exact = cshapes.experiment_retrieval(str(data / "manifest.csv"), str(tmp_path / "exact"), methods=["lbo"],
                                         draw=False)
    assert "two_stage" not in exact
    quick = cshapes.experiment_retrieval(str(data / "manifest.csv"), str(tmp_path / "quick"), methods=["lbo"],
                                         draw=False, two_stage_k=1, two_stage_reference=str(tmp_path / "exact"))
    two = quick["two_stage"]["lbo"]
    assert two["k"] == 1 and 0 < two["pairs_aligned"] <= 6
    assert 0 <= two["recall_at_k"] <= 1
    assert two["exact"]["hausdorff"]["map"] == exact["measures"]["lbo"]["hausdorff"]["map"]
    with pytest.raises(Exception, match="the exact run would be lost"):
        cshapes.experiment_retrieval(str(data / "manifest.csv"), str(tmp_path / "exact"), methods=["lbo"],
                                     draw=False, two_stage_k=1, two_stage_reference=str(tmp_path / "exact"))
    assert (tmp_path / "exact" / "lbo" / "hausdorff.csv").exists()
