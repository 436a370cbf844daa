"""Issue 57 through the Python skin, and a seeded sample of scripts/trust_probe.py (the whole probe: a seed and
a count from the command line)."""
import os
import subprocess
import sys
from pathlib import Path

import pytest

import cshapes

ROOT = Path(__file__).resolve().parents[2]


def test_an_experiment_refuses_the_datasets_folder_and_leaves_its_files(cli, tmp_path):
    # Was: experiment_retrieval(cla, out) with out the dataset's folder rewrote its .cla.
    data = tmp_path / "data"
    cli("generate", "dataset", "--out", data, "--classes", "2", "--poses", "3", "--noisy", "0", "--vertices", "300")
    manifest = (data / "manifest.csv").read_bytes()
    with pytest.raises(ValueError, match="generate dataset"):
        cshapes.experiment_retrieval(str(data / "manifest.csv"), str(data), methods=["lbo"], draw=False)
    assert (data / "manifest.csv").read_bytes() == manifest
    assert not (data / "classes.cla").exists()


def test_methods_as_one_string_is_a_list_of_names(cli, tmp_path):
    # Was: methods='lbo' was taken letter by letter ("unknown canonization method 'l'").
    data = tmp_path / "data"
    cli("generate", "dataset", "--out", data, "--classes", "2", "--poses", "3", "--noisy", "0", "--vertices", "300")
    result = cshapes.experiment_retrieval(str(data), str(tmp_path / "out"), methods="lbo", draw=False)
    assert list(result["measures"]) == ["lbo"]
    with pytest.raises(ValueError, match="expected a list of method names"):
        cshapes.experiment_retrieval(str(data), str(tmp_path / "out"), methods=3, draw=False)


def test_a_seeded_sample_of_the_trust_probe_passes(tmp_path):
    cli_path = os.environ.get("CSHAPES_CLI", str(ROOT / "build" / "cshapes"))
    result = subprocess.run([sys.executable, str(ROOT / "scripts" / "trust_probe.py"), "--cshapes", cli_path,
                             "--seed", "7", "--count", "14", "--keep", str(tmp_path / "kept")],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "14 cases, 0 failed" in result.stdout
