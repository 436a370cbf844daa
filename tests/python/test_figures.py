"""Figures a journal accepts (issue 60): every figure cshapes draws names what it shows, reads at the size a
two-column paper prints it, and can be written as PDF or SVG.

- `evaluate`'s pr, confusion and matrix figures are titled with the method, the distance and the data that
  `distmat` records in the labels file (or `--title`), never the CSV's name; read as SVG text, since SVG keeps
  text as text. Printed at their width (a column, 3.5 in, or the page, 7.16 in) no text is under 7 pt; every
  confusion cell has its count, 0 included, beside a colour bar in queries.
- `--figure-format pdf` writes PDF with TrueType fonts, not the Type 3 fonts journals' checkers refuse.
- `show` reads every format the library reads (OBJ here), titles a form's panel by its method, says a failing
  drawing script's own message, and takes any mix of paths, arrays and forms from Python.
"""
import json
import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import cshapes

ROOT = Path(__file__).resolve().parents[2]
SVG = "{http://www.w3.org/2000/svg}"
COLUMN, PAGE = 3.5 * 72, 7.16 * 72  # a two-column paper's column and page widths, in points


def can_draw():
    """Whether cshapes finds a Python with matplotlib (experiments/figures.h looks at $CSHAPES_PYTHON, then
    /usr/bin/python3, then python3)."""
    for python in (os.environ.get("CSHAPES_PYTHON"), "/usr/bin/python3", shutil.which("python3")):
        if python and Path(python).exists():
            if subprocess.run([python, "-c", "import matplotlib, numpy"], capture_output=True).returncode == 0:
                return True
    return False


needs_drawing = pytest.mark.skipif(not can_draw(), reason="no Python with matplotlib and numpy")


def svg_texts(path):
    """[(text, font size in pt)] of every <text> element of an SVG drawn by matplotlib with svg.fonttype none
    (its user unit is the point: 72 per inch); a text drawn by mathtext ("10" and a superscript) gives each of
    its <tspan> parts."""
    texts = []
    for text_element in ET.parse(path).getroot().iter(f"{SVG}text"):
        parts = [text_element] if text_element.get("style") else list(text_element.iter(f"{SVG}tspan"))
        for element in parts or [text_element]:
            text = "".join(element.itertext()).strip()
            style = element.get("style", "")
            size = re.search(r"font(?:-size)?:\s*(?:[a-z]+\s+)*([0-9.]+)px", style)
            assert size, f"{path}: a text without a font size: {style!r}"
            texts.append((text, float(size.group(1))))
    return texts


def svg_width(path):
    return float(re.match(r"[0-9.]+", ET.parse(path).getroot().get("width")).group(0))


def printed_size(font, width):
    """A text's size once the figure is printed in a two-column paper: a figure up to a column's width (with a
    little margin) goes in a column, a wider one across the page; scaled down only when wider than that."""
    room = COLUMN if width <= COLUMN * 1.05 else PAGE
    return font * min(1.0, room / width)


@pytest.fixture(scope="module")
def described_matrix(tmp_path_factory):
    """Eight shapes in four classes of two, and the labels file as distmat writes it: the method, distance and
    data in its comment lines."""
    folder = tmp_path_factory.mktemp("figures")
    classes = ["cat", "dog", "horse", "wolf"]
    names = [f"{c}{i}" for c in classes for i in range(2)]
    points = np.array([[classes.index(n[:-1]) + 0.3 * (int(n[-1]) - 0.5), 0.2 * k % 0.7] for k, n in
                       enumerate(names)])
    D = np.linalg.norm(points[:, None] - points[None], axis=2)
    matrix = folder / "coulomb-hausdorff.csv"
    matrix.write_text(",".join(names) + "\n" + "".join(",".join(f"{x:.6f}" for x in row) + "\n" for row in D))
    (folder / "coulomb-hausdorff.labels.csv").write_text(
        "# method: Coulomb\n# distance: Hausdorff\n# data: tosca5k\nname,class\n" +
        "".join(f"{n},{n[:-1]}\n" for n in names))
    return matrix


@needs_drawing
def test_evaluate_figures_name_the_method_distance_and_data(cli, described_matrix, tmp_path):
    out = tmp_path / "out"
    cli("evaluate", described_matrix, "--out", out, "--min-class-size", "2", "--figure-format", "svg")
    for name in ("pr", "confusion", "matrix"):
        figure = out / f"{name}.svg"
        assert figure.exists(), sorted(p.name for p in out.iterdir())
        words = " ".join(text for text, _ in svg_texts(figure))
        for named in ("Coulomb", "Hausdorff", "tosca5k", "8 shapes"):
            assert named in words, f"{name}.svg does not name {named!r}: {words}"
        assert "coulomb-hausdorff.csv" not in words, f"{name}.svg names the CSV: {words}"
    assert not list(out.glob("*.png")), "the format asked for, not PNG beside it"
    metrics = cli.json("evaluate", described_matrix, "--out", tmp_path / "json", "--min-class-size", "2",
                       "--no-draw", "--json")
    assert metrics["description"] == {"method": "Coulomb", "distance": "Hausdorff", "data": "tosca5k"}
    assert metrics["title"] == "Coulomb, Hausdorff distance, tosca5k: 8 shapes, 4 classes"


@needs_drawing
def test_evaluate_title_option_and_an_unknown_matrix(cli, described_matrix, tmp_path):
    given = tmp_path / "given"
    cli("evaluate", described_matrix, "--out", given, "--min-class-size", "2", "--figure-format", "svg",
        "--title", "SMACOF, Chamfer distance, TOSCA")
    assert "SMACOF, Chamfer distance, TOSCA" in " ".join(t for t, _ in svg_texts(given / "pr.svg"))
    # Classes from a plain labels file (no description): the figures say what they do not know.
    plain = tmp_path / "plain.csv"
    plain.write_text("".join(line + "\n" for line in described_matrix.with_suffix(".labels.csv").read_text()
                             .splitlines() if not line.startswith("#")))
    unknown = tmp_path / "unknown"
    cli("evaluate", described_matrix, "--labels", plain, "--out", unknown, "--min-class-size", "2",
        "--figure-format", "svg")
    words = " ".join(t for t, _ in svg_texts(unknown / "matrix.svg"))
    assert "unknown method and distance" in words and "coulomb-hausdorff.csv" not in words, words


@needs_drawing
def test_evaluate_figures_read_at_a_two_column_papers_size(cli, described_matrix, tmp_path):
    out = tmp_path / "out"
    cli("evaluate", described_matrix, "--out", out, "--min-class-size", "2", "--figure-format", "svg")
    for name in ("pr", "confusion", "matrix"):
        figure = out / f"{name}.svg"
        width = svg_width(figure)
        assert width <= PAGE * 1.05, f"{name}.svg is {width / 72:.2f} in wide, wider than a page"
        for text, size in svg_texts(figure):
            assert printed_size(size, width) >= 7 - 1e-6, f"{name}.svg: {text!r} prints at {size} pt"
    texts = [t for t, _ in svg_texts(out / "confusion.svg")]
    cells = [t for t in texts if re.fullmatch(r"[0-9]+(\.[0-9]+)?", t)]
    assert cells.count("0") >= 4 * 4 - 8, f"the empty cells say 0: {texts}"
    assert "queries" in texts, f"a colour bar in queries: {texts}"
    names = [t for t, _ in svg_texts(out / "matrix.svg")]
    assert "cat0" in names and "wolf1" in names, names


@needs_drawing
def test_a_pdf_figure_is_a_pdf_with_truetype_fonts(cli, described_matrix, tmp_path):
    out = tmp_path / "out"
    cli("evaluate", described_matrix, "--out", out, "--min-class-size", "2", "--figure-format", "pdf")
    for name in ("pr", "confusion", "matrix"):
        data = (out / f"{name}.pdf").read_bytes()
        assert data[:5] == b"%PDF-", name
        assert b"/Type3" not in data, f"{name}.pdf has Type 3 fonts, which journals refuse"
    r = cli("evaluate", described_matrix, "--out", out, "--figure-format", "jpeg", check=False)
    assert r.returncode == 2 and "png" in r.stderr and "svg" in r.stderr, r.stderr


@pytest.fixture(scope="module")
def obj_and_form(cli, shapes, tmp_path_factory):
    """A biped as OBJ, and its classical-MDS form as `cshapes canon` writes it (PLY, recording its method)."""
    folder = tmp_path_factory.mktemp("show-obj")
    mesh = folder / "biped0.obj"
    cli("convert", shapes[0], mesh)
    form = folder / "biped0-cmds.ply"
    cli("canon", mesh, "-o", form, "--method", "cmds")
    return mesh, form


@needs_drawing
def test_show_reads_obj_and_titles_the_form_by_its_method(cli, obj_and_form, tmp_path):
    mesh, form = obj_and_form
    picture = tmp_path / "pair.svg"
    cli("show", mesh, form, "-o", picture)
    texts = [t for t, _ in svg_texts(picture)]
    assert "biped0.obj" in texts and "classical MDS canonical form" in texts, texts
    width = svg_width(picture)
    for text, size in svg_texts(picture):
        assert printed_size(size, width) >= 7 - 1e-6, f"{text!r} prints at {size} pt"
    # --label titles the panels; --figure-format gives a picture without an extension its own.
    cli("show", mesh, form, "-o", tmp_path / "labelled", "--figure-format", "pdf", "--label", "input",
        "--label", "its form")
    assert (tmp_path / "labelled.pdf").read_bytes()[:5] == b"%PDF-"
    r = cli("show", mesh, "-o", tmp_path / "p.png", "--figure-format", "svg", check=False)
    assert r.returncode == 2 and "p.png" in r.stderr and "svg" in r.stderr, r.stderr
    long = "a panel title far longer than a column of a two-column paper is wide, which is broken into lines"
    cli("show", mesh, form, "-o", tmp_path / "long.svg", "--label", long)
    lines = [t for t, _ in svg_texts(tmp_path / "long.svg")]
    assert " ".join(lines).count("broken") == 1 and long not in lines, lines


@needs_drawing
def test_a_failing_drawing_script_is_reported_in_its_own_words(cli, obj_and_form, tmp_path):
    mesh, _ = obj_and_form
    plots = tmp_path / "plots"
    plots.mkdir()
    (plots / "show_figure.py").write_text("raise ValueError('the drawing failed: no room on the canvas')\n")
    env = dict(os.environ, CSHAPES_PLOTS=str(plots))
    binary = os.environ.get("CSHAPES_CLI", str(ROOT / "build" / "cshapes"))
    r = subprocess.run([binary, "show", str(mesh), "-o", str(tmp_path / "p.png")], capture_output=True, text=True,
                       env=env)
    assert r.returncode == 1, r.stderr
    assert "show_figure.py: the drawing failed: no room on the canvas" in r.stderr, r.stderr
    assert "ValueError" not in r.stderr and "exit status 256" not in r.stderr, r.stderr
    assert not (tmp_path / "p.png").exists()


@needs_drawing
def test_python_show_takes_any_mix_of_paths_arrays_and_forms(obj_and_form, tmp_path):
    mesh, form = obj_and_form
    V, F = cshapes.read_mesh(mesh)
    X, _ = cshapes.read_mesh(form)
    computed = cshapes.canonical_form(V, F, method="cmds")
    for k, (m, f) in enumerate([(mesh, X), ((V, F), form), (mesh, computed), (V, computed)]):
        assert cshapes.show(m, f, out=tmp_path / f"mix{k}.png") == str(tmp_path / f"mix{k}.png")
    picture = cshapes.show(mesh, computed, out=tmp_path / "method", figure_format="svg")
    assert picture == str(tmp_path / "method.svg")
    texts = [t for t, _ in svg_texts(picture)]
    assert "classical MDS canonical form" in texts and "biped0.obj" in texts, texts
    cshapes.show((V, F), X, out=tmp_path / "labels.svg", labels=["pose A", "pose A, classical MDS"])
    assert {"pose A", "pose A, classical MDS"} <= set(t for t, _ in svg_texts(tmp_path / "labels.svg"))
    with pytest.raises(ValueError, match="labels"):
        cshapes.show(mesh, out=tmp_path / "x.png", labels=["a", "b"])
    with pytest.raises(ValueError, match="figure format"):
        cshapes.show(mesh, out=tmp_path / "x.png", figure_format="jpeg")


def experiment_figure_data(folder):
    """Hand-made data files of `experiment paper` (Fig. 5, 7, 8, 9, for three methods of 15 shapes) and of
    `experiment noise` (six methods, five levels), as the C++ drivers write them."""
    methods = ["coulomb", "cmds", "lbo"]
    (folder / "convergence.csv").write_text("projection_steps,iteration,energy,mean_violation\n" + "".join(
        f"{k},{i},{1000.0 / i + k},{0.1 / (i + k)}\n" for k in (1, 10, 100) for i in range(1, 60)))
    (folder / "correspondence_error.csv").write_text("method,error,fraction\n" + "".join(
        f"{m},{0.05 * i},{min(1.0, 0.1 * i * s)}\n" for m, s in zip(methods, (1.5, 1.0, 0.8)) for i in range(11)))
    (folder / "metrics.json").write_text(json.dumps({"methods": {
        m: {"map": a, "pr": {"recall": [0.25, 0.5, 0.75, 1.0], "precision": [1.0, a, a * a, a ** 3]}}
        for m, a in zip(methods, (0.9, 0.7, 0.8))}}))
    names = [f"{c}{i}" for c in ("cat", "centaur", "david", "dog", "horse") for i in range(3)]
    (folder / "distances").mkdir()
    rng = np.random.default_rng(1)
    for m in methods:
        D = rng.uniform(1, 5, (15, 15))
        D = D + D.T
        np.fill_diagonal(D, 0)
        (folder / "distances" / f"{m}.csv").write_text(
            ",".join(names) + "\n" + "".join(",".join(f"{x:.4f}" for x in row) + "\n" for row in D))
    draw = ["fig5_convergence", "fig7_distance_matrices", "fig8_pr", "fig9_correspondence"]
    (folder / "figures.json").write_text(json.dumps({"draw": draw, "grids": {}, "methods": methods,
                                                     "data": "tosca5k"}))
    six = ["coulomb", "cmds", "smacof", "lbo", "diffusion", "spectral-mds"]
    rows = [{"method": m, "distance": d, "level": L, "map": 0.9 - 0.1 * L * (m != "coulomb"), "queries": 20,
             "form_poses": 24 if L < 4 else 17, "form_rms_median": 0.01 * L, "form_rms_mean": 0.012 * L}
            for m in six for d in ("hausdorff", "chamfer", "rmse") for L in range(5)]
    (folder / "noise.json").write_text(json.dumps({"rows": rows, "levels": list(range(5)), "methods": six,
                                                   "poses": [f"p{k}" for k in range(24)], "seed": 1,
                                                   "data": "../shared/data/tosca5k"}))
    classes = [f"class{k}" for k in range(20)]
    kinds = ("hausdorff", "chamfer", "rmse")
    (folder / "retrieval.json").write_text(json.dumps({"shapes": 400, "classes": classes, "distances": kinds,
                                                       "methods": [{"method": m, "distances": {kind: {
        "map": 0.8, "nn": 0.9, "pr": {"recall": [0.5, 1.0], "precision": [0.9, 0.7]},
        "classes": {c: {"map": 0.5 + 0.02 * k} for k, c in enumerate(classes)}, "class_names": classes,
        "confusion": (19 * np.eye(20) + 1).tolist()} for kind in kinds}} for m in six]}))
    return draw


@needs_drawing
def test_the_experiments_figures_read_at_a_two_column_papers_size(tmp_path):
    # Fig. 7 was 4.3 in a method wide (26 in for six), the noise figure 14 in, retrieval's confusion figure 4.2 in
    # a method and its per-class bars 74 in for 20 classes and six methods, their text printing at 1-5 pt;
    # each now fits a column or the page, with no text under 7 pt once printed, and names what it shows.
    draw = experiment_figure_data(tmp_path)
    plots = ROOT / "experiments" / "plots"
    for script in ("paper_figures.py", "noise_figure.py", "retrieval_figures.py"):
        result = subprocess.run([sys.executable, str(plots / script), str(tmp_path), "--format=svg"],
                                capture_output=True, text=True)
        assert result.returncode == 0, result.stderr
    # experiment retrieval's three figures: 400 shapes of 20 classes, six methods
    for name in draw + ["noise", "figures/pr", "figures/per_class", "figures/confusion"]:
        figure = tmp_path / f"{name}.svg"
        width = svg_width(figure)
        assert width <= PAGE * 1.05, f"{name}.svg is {width / 72:.2f} in wide, wider than a page"
        for text, size in svg_texts(figure):
            assert printed_size(size, width) >= 7 - 1e-6, f"{name}.svg: {text!r} prints at {size} pt"
    titles = " ".join(t for t, _ in svg_texts(tmp_path / "fig8_pr.svg"))
    assert "Hausdorff" in titles and "tosca5k" in titles, titles
    texts = [t for t, _ in svg_texts(tmp_path / "noise.svg")]
    assert sum(t in ("Coulomb", "classical MDS", "SMACOF", "LBO eigenmap") for t in texts) == 4, \
        f"one key of the methods, each named once: {texts}"
    assert any("tosca5k" in t for t in texts), texts


def other_experiment_figure_data(folder):
    """Hand-made data files of `experiment topkids` (six methods and the inputs, nine poses), `experiment pose`
    (the input and six forms), `experiment invariance` (six methods at four resolutions) and `compare` (seven
    methods from two runs), as the C++ drivers write them; {script: its folder}."""
    six = ["coulomb", "cmds", "smacof", "lbo", "diffusion", "spectral-mds"]
    rng = np.random.default_rng(2)
    topkids = folder / "topkids"
    topkids.mkdir()
    errors = np.linspace(0, 0.5, 101)
    methods = ["inputs"] + six
    (topkids / "curves.csv").write_text("method,forgiven,error,fraction\n" + "".join(
        f"{m},{kind},{e},{min(1.0, e * (1.5 + k / 3))}\n" for kind in ("vertex", "map") for k, m in enumerate(methods)
        for e in errors))
    poses = [f"kid{k:02d}" for k in range(7, 16)]
    rows = [{"method": m, "pose": p, "mean_error": float(rng.uniform(0.1, 0.6)), "mirrored": bool(k % 3 == 0),
             "direct_mean_error": float(rng.uniform(0.3, 0.6))} for m in methods for k, p in enumerate(poses)]
    summary = [{"method": m, "poses": 9, "mirrored_poses": 3, "median_pose_mean_error": 0.2, "mean_error": 0.25,
                "median_error": 0.2, "under_0.25": 0.6, "whole_map_mean_error": 0.3, "whole_map_under_0.25": 0.5}
               for m in methods]
    (topkids / "topkids.json").write_text(json.dumps({"summary": summary, "poses": poses, "rows": rows,
                                                      "samples_per_pose": 1000}))
    pose = folder / "pose"
    pose.mkdir()
    forms = ["input"] + six
    (pose / "pose_residuals.json").write_text(json.dumps({
        "a": "cat0", "b": "cat2", "class": "cat", "forms": forms, "rms": {f: 0.05 for f in forms},
        "chosen_by": "the pair with the median Coulomb pose RMS (3 of 6 pairs by increasing RMS)",
        "titles": {"input": "input", "coulomb": "Coulomb", "cmds": "classical MDS", "smacof": "SMACOF",
                   "lbo": "LBO eigenmap", "diffusion": "diffusion map", "spectral-mds": "spectral MDS"}}))
    P = rng.normal(size=(900, 3)) * [3.0, 1.0, 0.3]
    (pose / "pose_residuals.csv").write_text(f"sample,vertex,x,y,z,part,{','.join(forms)}\n" + "".join(
        f"{k},{k},{p[0]},{p[1]},{p[2]},0," + ",".join(f"{abs(r):.4f}" for r in rng.normal(0, 0.05, len(forms)))
        + "\n" for k, p in enumerate(P)))
    invariance = folder / "invariance"
    invariance.mkdir()
    transformations = ["renumber", "face-order", "rigid", "scale-1e-6", "scale-1e3", "jitter", "remesh-0.8",
                       "remesh-1.2"]
    resolutions = [1000, 2000, 3500, 5000]
    (invariance / "invariance.csv").write_text(
        "resolution,shape,method,transformation,group,seed,vertices,rmse_percent\n" + "".join(
            f"{n},cat{s},{m},{t},{'remeshed' if t.startswith('remesh') else 'exact'},1,{n},"
            f"{0.0 if t == 'face-order' and m == 'cmds' else 10 ** rng.uniform(-14, 0.5)}\n"
            for n in resolutions for s in range(3) for m in six for t in transformations))
    (invariance / "invariance.json").write_text(json.dumps({
        "resolutions": resolutions, "methods": six, "transformations": transformations,
        "tolerance": {"floor_percent": 0.05, "pose_percent": 1.0},
        "verdicts": [{"resolution": n, "method": m, "verdict": "pass", "tolerance_percent": 0.05 if m != "lbo"
                      else 0.08, "pose_rmse_percent": 3.0} for n in resolutions for m in six]}))
    compare = folder / "compare"
    compare.mkdir()
    classes = [f"class{k}" for k in range(4)]
    kinds = ["hausdorff", "chamfer", "rmse"]
    (compare / "compare.json").write_text(json.dumps({"shapes": 24, "classes": classes, "distances": kinds,
                                                      "methods": [{"method": m, "title": m, "distances": {kind: {
        "map": 0.8, "pr": {"recall": [0.25, 0.5, 0.75, 1.0], "precision": [1.0, 0.9, 0.8, 0.6]}} for kind in kinds}}
        for m in six + ["principal-axes"]]}))
    return {"topkids_figure.py": topkids, "pose_figure.py": pose, "invariance_figure.py": invariance,
            "compare_figure.py": compare}


@needs_drawing
def test_topkids_pose_invariance_and_compare_figures_read_at_a_papers_size(tmp_path):
    # The TOPKIDS figure was 16 in wide (its legends carried tables), the pose figure 13 in, the invariance
    # figure 14 in, compare's PR figure at matplotlib's 10 pt: each now fits a column or the page, no text under
    # 7 pt once printed.
    plots = ROOT / "experiments" / "plots"
    drawn = {"topkids_figure.py": "topkids", "pose_figure.py": "pose_residuals",
             "invariance_figure.py": "invariance", "compare_figure.py": "pr"}
    for script, folder in other_experiment_figure_data(tmp_path).items():
        result = subprocess.run([sys.executable, str(plots / script), str(folder), "--format=svg"],
                                capture_output=True, text=True)
        assert result.returncode == 0, f"{script}: {result.stderr}"
        figure = folder / f"{drawn[script]}.svg"
        width = svg_width(figure)
        assert width <= PAGE * 1.05, f"{figure.name} is {width / 72:.2f} in wide, wider than a page"
        for text, size in svg_texts(figure):
            assert printed_size(size, width) >= 7 - 1e-6, f"{figure.name}: {text!r} prints at {size} pt"
    texts = [t for t, _ in svg_texts(tmp_path / "topkids" / "topkids.svg")]
    assert any("TOPKIDS" in t for t in texts) and texts.count("Coulomb") == 1, texts
    titles = " ".join(t for t, _ in svg_texts(tmp_path / "pose" / "pose_residuals.svg"))
    assert "cat0 against cat2" in titles and "spectral MDS" in titles, titles
