"""cshapes.show() and `cshapes show` (experiments/show_mesh.h): the same picture from files and from arrays,
a canonical form's dropped vertices left out, and the refusals (another vertex count, a picture that is an
input, an unknown format) before anything is written. Figures for a paper (OBJ, titles, SVG and PDF, mixes of
paths and arrays): tests/python/test_figures.py."""
import struct

import numpy as np
import pytest

import cshapes

pytest.importorskip("matplotlib")


def png_size(path):
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path} is no PNG"
    return struct.unpack(">II", data[16:24])


@pytest.fixture(scope="module")
def biped_and_form(cli, shapes, tmp_path_factory):
    folder = tmp_path_factory.mktemp("show")
    form = folder / "form.ply"
    cli("canon", shapes[0], "-o", form, "--method", "cmds")
    return shapes[0], form


def test_the_cli_draws_a_mesh_and_its_form_side_by_side(cli, biped_and_form, tmp_path):
    mesh, form = biped_and_form
    cli("show", mesh, form, "-o", tmp_path / "pair.png", "--title", "biped")
    cli("show", mesh, "-o", tmp_path / "one.png")
    (width, height), (one_width, one_height) = png_size(tmp_path / "pair.png"), png_size(tmp_path / "one.png")
    assert 200 <= height <= 4000 and height == one_height
    assert width > 1.8 * one_width
    assert sorted(p.name for p in tmp_path.iterdir()) == ["one.png", "pair.png"]  # no temporary file left


def test_files_and_arrays_give_the_same_kind_of_picture(biped_and_form, tmp_path):
    mesh, form = biped_and_form
    V, F = cshapes.read_mesh(mesh)
    X, _ = cshapes.read_mesh(form)
    assert cshapes.show(mesh, form, out=tmp_path / "files.png") == str(tmp_path / "files.png")
    cshapes.show((V, F), X, out=tmp_path / "arrays.png", title="from arrays")
    cshapes.show((V, F), cshapes.canonical_form(V, F, method="cmds"), out=tmp_path / "form.png")
    sizes = {png_size(tmp_path / name) for name in ("files.png", "arrays.png", "form.png")}
    assert len(sizes) == 1, sizes
    cshapes.show((V, F), out=tmp_path / "mesh.pdf", view="z")
    assert (tmp_path / "mesh.pdf").read_bytes()[:4] == b"%PDF"


def test_dropped_vertices_are_left_out(biped_and_form, tmp_path):
    mesh, _ = biped_and_form
    V, F = cshapes.read_mesh(mesh)
    X = V * 2.0
    X[::5] = np.nan  # vertices a method dropped
    cshapes.show((V, F), X, out=tmp_path / "dropped.png")
    assert png_size(tmp_path / "dropped.png")[0] > 0
    # The same form as a file, as `cshapes canon` writes one: NaN rows with valid = 0.
    cshapes.write_mesh(tmp_path / "dropped.ply", X, F, valid=np.isfinite(X).all(axis=1).astype(float))
    cshapes.show(mesh, tmp_path / "dropped.ply", out=tmp_path / "dropped_file.png")
    assert png_size(tmp_path / "dropped_file.png")[0] > 0


def test_a_form_of_another_vertex_count_is_refused_naming_both(cli, biped_and_form, tmp_path):
    mesh, _ = biped_and_form
    roll = tmp_path / "roll.off"
    cli("generate", "swissroll", "-o", roll)
    r = cli("show", mesh, roll, "-o", tmp_path / "p.png", check=False)
    assert r.returncode == 1, r.stderr
    assert str(mesh) in r.stderr and str(roll) in r.stderr and "561" in r.stderr, r.stderr
    assert not (tmp_path / "p.png").exists()
    with pytest.raises(ValueError, match="561"):
        cshapes.show(mesh, roll, out=tmp_path / "p.png")
    V, F = cshapes.read_mesh(mesh)
    with pytest.raises(ValueError, match="vertices"):
        cshapes.show((V, F), V[:10], out=tmp_path / "p.png")
    assert not (tmp_path / "p.png").exists()


def test_a_picture_that_is_an_input_or_not_png_pdf_or_svg_is_refused(cli, biped_and_form, tmp_path):
    mesh, form = biped_and_form
    before = form.read_bytes()
    r = cli("show", mesh, form, "-o", form, check=False)
    assert r.returncode == 2 and "is the input" in r.stderr, r.stderr
    assert form.read_bytes() == before
    with pytest.raises(ValueError, match="is the input"):
        cshapes.show(mesh, form, out=form)
    r = cli("show", mesh, "-o", tmp_path / "p.jpg", check=False)
    assert r.returncode == 2 and ".png" in r.stderr, r.stderr
    with pytest.raises(ValueError, match="view"):
        cshapes.show(mesh, out=tmp_path / "p.png", view="sideways")
    # A path and an array mix (tests/python/test_figures.py), but the counts must still agree.
    with pytest.raises(ValueError, match="the form has 3 vertices"):
        cshapes.show(mesh, np.zeros((3, 3)), out=tmp_path / "p.png")
    assert list(tmp_path.iterdir()) == []
