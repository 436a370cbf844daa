"""The figure scripts of `experiment topkids` and `experiment pose` on small hand-made data files, as the C++
drivers write them (experiments/plots/topkids_figure.py, experiments/plots/pose_figure.py)."""
import csv
import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PLOTS = ROOT / "experiments" / "plots"

pytest.importorskip("matplotlib")
pytest.importorskip("numpy")


def run_script(name, out, *args):
    result = subprocess.run([sys.executable, str(PLOTS / name), str(out), *args], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr


def test_topkids_figure_draws_curves_and_the_per_pose_strip(tmp_path):
    with open(tmp_path / "curves.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["method", "forgiven", "error", "fraction"])
        for forgiven in ("vertex", "map"):
            for method in ("inputs", "coulomb"):
                for k in range(11):
                    w.writerow([method, forgiven, 0.05 * k, min(1.0, 0.1 * k)])
    rows = []
    for i, (mean, direct, mirrored) in enumerate([(0.1, 0.1, False), (0.12, 0.45, True), (0.55, 0.56, False)]):
        for method in ("inputs", "coulomb"):
            rows.append({"pose": f"kid{7 + i:02d}", "method": method, "mean_error": mean,
                         "direct_mean_error": direct, "mirrored": mirrored and method == "coulomb"})
    summary = [{"method": m, "mean_error": 0.26, "median_error": 0.12, "under_0.25": 0.6,
                "whole_map_mean_error": 0.3, "whole_map_under_0.25": 0.5, "poses": 3,
                "mirrored_poses": 1 if m == "coulomb" else 0, "median_pose_mean_error": 0.12}
               for m in ("inputs", "coulomb")]
    (tmp_path / "topkids.json").write_text(json.dumps(
        {"poses": ["kid07", "kid08", "kid09"], "samples_per_pose": 100, "summary": summary, "rows": rows}))
    run_script("topkids_figure.py", tmp_path)
    assert (tmp_path / "topkids.png").stat().st_size > 0


@pytest.mark.parametrize("fmt", ["pdf", "svg"])
def test_the_figure_scripts_write_the_format_asked_for(tmp_path, fmt):
    # --format, as every command's --figure-format passes it (experiments/figures.h): the figure in that format
    # only, PDF with TrueType fonts (journals refuse Type 3), SVG with its text as text.
    (tmp_path / "curves.csv").write_text("method,forgiven,error,fraction\ncoulomb,vertex,0,0\ncoulomb,vertex,0.5,1\n")
    run_script("topkids_figure.py", tmp_path, f"--format={fmt}")
    data = (tmp_path / f"topkids.{fmt}").read_bytes()
    assert not (tmp_path / "topkids.png").exists()
    if fmt == "pdf":
        assert data[:5] == b"%PDF-" and b"/Type3" not in data
    else:
        assert b"<text" in data and b"TOPKIDS" in data


def test_topkids_figure_reads_a_folder_without_per_pose_rows(tmp_path):
    # A folder written before the per-pose columns existed: the curves alone.
    (tmp_path / "curves.csv").write_text("method,forgiven,error,fraction\ncoulomb,vertex,0,0\ncoulomb,vertex,0.5,1\n")
    run_script("topkids_figure.py", tmp_path)
    assert (tmp_path / "topkids.png").exists()


def test_pose_figure_draws_one_panel_per_form(tmp_path):
    forms = ["input", "coulomb", "cmds"]
    with open(tmp_path / "pose_residuals.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["sample", "vertex", "x", "y", "z", "part"] + forms)
        for k in range(60):
            residuals = [0.01 * (k % 7), 0.002 * (k % 5), ""]  # cmds: one empty (dropped) column
            w.writerow([k, 3 * k, k % 10, k // 10, 0.1 * (k % 3), k % 4 - 1] + residuals)
    (tmp_path / "pose_residuals.json").write_text(json.dumps(
        {"a": "biped0", "b": "biped1", "class": "biped", "chosen_by": "the pair with the median Coulomb pose RMS",
         "forms": forms, "titles": {"input": "input", "coulomb": "Coulomb", "cmds": "classical MDS"},
         "rms": {"input": 0.04, "coulomb": 0.01, "cmds": None}}))
    run_script("pose_figure.py", tmp_path)
    assert (tmp_path / "pose_residuals.png").stat().st_size > 0


def test_paper_figures_drawn_by_two_processes_are_the_pictures_drawn_one_at_a_time(tmp_path):
    # paper_figures.py draws a run's figures in two processes; each picture must be the one drawn alone.
    (tmp_path / "convergence.csv").write_text("projection_steps,iteration,energy,mean_violation\n" + "".join(
        f"{k},{i},{1000.0 / i + k},{0.1 / (i + k)}\n" for k in (1, 10) for i in range(1, 30)))
    (tmp_path / "correspondence_error.csv").write_text("method,error,fraction\n" + "".join(
        f"{m},{0.05 * i},{min(1.0, 0.1 * i * s)}\n" for m, s in (("coulomb", 1.5), ("cmds", 1.0)) for i in range(11)))
    (tmp_path / "metrics.json").write_text(json.dumps({"methods": {
        m: {"map": a, "pr": {"recall": [0.25, 0.5, 0.75, 1.0], "precision": [1.0, a, a * a, a ** 3]}}
        for m, a in (("coulomb", 0.9), ("cmds", 0.7))}}))
    names = ["fig5_convergence", "fig8_pr", "fig9_correspondence"]
    (tmp_path / "figures.json").write_text(json.dumps({"draw": names, "grids": {}}))
    alone = tmp_path / "alone"
    alone.mkdir()
    for name in ("convergence.csv", "correspondence_error.csv", "metrics.json", "figures.json"):
        (alone / name).write_bytes((tmp_path / name).read_bytes())
    run_script("paper_figures.py", tmp_path)
    for name in names:  # each figure in a process of its own, the way a run with one figure draws it
        (alone / "figures.json").write_text(json.dumps({"draw": [name], "grids": {}}))
        run_script("paper_figures.py", alone)
    for name in names:
        assert (tmp_path / f"{name}.png").read_bytes() == (alone / f"{name}.png").read_bytes(), name
