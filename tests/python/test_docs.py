"""The Python side of the documentation (scripts/docs.py): the API reference page is what the module's
docstrings say now, and the Python tutorial runs from top to bottom, each block printing what the page shows
under it."""
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "scripts" / "docs.py"


def test_the_python_api_reference_is_current(tmp_path):
    out = tmp_path / "python.md"
    subprocess.run([sys.executable, str(DOCS), "python-api", str(out)], check=True)
    committed = (ROOT / "docs" / "reference" / "python.md").read_text()
    assert out.read_text() == committed, (
        "docs/reference/python.md is out of date: run "
        "PYTHONPATH=build/python /usr/bin/python3 scripts/docs.py python-api docs/reference/python.md")


def test_the_python_tutorial_runs(tmp_path):
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(str(Path(p).resolve()) for p in env.get("PYTHONPATH", "").split(os.pathsep) if p)
    r = subprocess.run([sys.executable, str(DOCS), "run-python", str(ROOT / "docs" / "tutorial-python.md"),
                        str(tmp_path)], env=env, capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "mAP" in r.stdout


def test_the_outside_methods_page_runs(tmp_path):
    """docs/outside-methods.md: its shell blocks (which write the data and the method) run first, as
    tests/check_docs.sh does, then its Python block, in the same folder."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(str(Path(p).resolve()) for p in env.get("PYTHONPATH", "").split(os.pathsep) if p)
    cshapes = ROOT / "build" / "cshapes"
    if os.environ.get("CSHAPES_CLI"):
        cshapes = Path(os.environ["CSHAPES_CLI"])
    page = str(ROOT / "docs" / "outside-methods.md")
    r = subprocess.run([sys.executable, str(DOCS), "run-shell", page, str(tmp_path), str(cshapes)], env=env,
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    r = subprocess.run([sys.executable, str(DOCS), "run-python", page, str(tmp_path)], env=env,
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "pca mAP" in r.stdout
