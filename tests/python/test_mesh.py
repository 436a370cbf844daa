"""Meshes in and out: read/write round trips, mesh_info against `cshapes info`, geodesics against
`cshapes geodesics`, errors with the CLI's messages, and every numpy layout giving the same answer."""
import numpy as np
import pytest

import cshapes


def test_version():
    assert isinstance(cshapes.__version__, str) and cshapes.__version__.count(".") == 2


def test_read_write_round_trip_is_exact(shapes, tmp_path):
    V, F = cshapes.read_mesh(shapes[0])
    assert V.dtype == np.float64 and V.shape[1] == 3 and V.flags.c_contiguous
    assert F.dtype == np.int32 and F.shape[1] == 3 and F.min() == 0 and F.max() == len(V) - 1
    for name, binary in [("a.ply", False), ("b.ply", True), ("c.off", False), ("d.obj", False)]:
        cshapes.write_mesh(tmp_path / name, V, F, binary=binary)
        V2, F2 = cshapes.read_mesh(tmp_path / name)
        np.testing.assert_array_equal(V2, V)
        np.testing.assert_array_equal(F2, F)


def test_vertex_fields_go_to_ply(shapes, tmp_path):
    V, F = cshapes.read_mesh(shapes[0])
    heat = np.linspace(0, 1, len(V))
    cshapes.write_mesh(tmp_path / "f.ply", V, F, heat=heat)
    V2, F2, fields = cshapes.read_mesh(tmp_path / "f.ply", fields=True)
    np.testing.assert_array_equal(fields["heat"], heat)
    with pytest.raises(ValueError, match="written to .ply only"):
        cshapes.write_mesh(tmp_path / "f.off", V, F, heat=heat)
    with pytest.raises(ValueError, match="values for"):
        cshapes.write_mesh(tmp_path / "g.ply", V, F, heat=heat[:-1])
    assert not (tmp_path / "g.ply").exists()


def test_read_errors_name_the_file_and_line(tmp_path):
    with pytest.raises(OSError, match="no such file"):
        cshapes.read_mesh(tmp_path / "missing.off")
    bad = tmp_path / "bad.off"
    bad.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n")
    with pytest.raises(ValueError, match=r"bad\.off:6.*7"):
        cshapes.read_mesh(bad)


def test_mesh_info_is_the_cli_info(cli, shapes):
    expected = cli.json("info", shapes[0], "--json")
    info = cshapes.mesh_info(*cshapes.read_mesh(shapes[0]))
    expected.pop("file")
    assert info == expected


def test_mesh_info_reports_defects():
    V, F = cshapes.generate("icosphere", subdivisions=1)
    # a second copy of face 0, and an isolated vertex
    V = np.vstack([V, [[5.0, 5.0, 5.0]]])
    F = np.vstack([F, F[:1]])
    info = cshapes.mesh_info(V, F)
    assert info["defects"]["duplicate_faces"]["count"] == 1
    assert info["defects"]["isolated_vertices"]["count"] == 1
    assert info["components"] == 2


def test_geodesics_match_the_cli(cli, shapes, tmp_path):
    V, F = cshapes.read_mesh(shapes[0])
    row = cshapes.geodesics(V, F, 17, method="fmm")
    out = tmp_path / "row.csv"
    cli("geodesics", shapes[0], "--method", "fmm", "--source", "17", "--csv", "-o", out)
    reference = np.loadtxt(out, delimiter=",", skiprows=1)[:, 1]
    np.testing.assert_allclose(row, reference, rtol=1e-9, atol=1e-12 * row.max())  # CSV keeps 10 digits
    assert row[17] == 0 and row.shape == (len(V),)
    rows = cshapes.geodesics(V, F, [17, 3], method="fmm")
    assert rows.shape == (2, len(V))
    np.testing.assert_array_equal(rows[0], row)
    D = cshapes.geodesics(V, F, method="heat")
    assert D.shape == (len(V), len(V)) and D.dtype == np.float32
    cli("geodesics", shapes[0], "--method", "heat", "-o", tmp_path / "D.bin")
    raw = (tmp_path / "D.bin").read_bytes()
    n = int(np.frombuffer(raw[8:16], dtype=np.uint64)[0])
    np.testing.assert_array_equal(D, np.frombuffer(raw[16:], dtype=np.float32).reshape(n, n))


def test_geodesics_of_a_mesh_with_an_extra_piece_are_at_the_input_vertices():
    V, F = cshapes.generate("icosphere", subdivisions=2)
    V2 = np.vstack([V, V[:3] + 10.0])
    F2 = np.vstack([F, [[len(V), len(V) + 1, len(V) + 2]]])
    with pytest.warns(UserWarning, match="smaller components dropped 1"):
        row = cshapes.geodesics(V2, F2, 0, method="fmm")
    assert row.shape == (len(V2),)
    assert np.isnan(row[len(V):]).all() and np.isfinite(row[: len(V)]).all()
    np.testing.assert_array_equal(row[: len(V)], cshapes.geodesics(V, F, 0, method="fmm"))
    with pytest.raises(ValueError, match="component"):
        cshapes.geodesics(V2, F2, 0, method="fmm", strict=True)


@pytest.mark.parametrize("variant", ["float32", "fortran", "strided", "int64 faces", "uint32 faces", "lists"])
def test_every_numpy_layout_gives_the_same_answer(shapes, variant):
    V, F = cshapes.read_mesh(shapes[0])
    reference = cshapes.geodesics(V, F, 5, method="fmm")
    if variant == "float32":
        V = V.astype(np.float32)
        reference = cshapes.geodesics(V.astype(np.float64), F, 5, method="fmm")
    elif variant == "fortran":
        V, F = np.asfortranarray(V), np.asfortranarray(F)
    elif variant == "strided":
        wide = np.zeros((2 * len(V), 9))
        wide[::2, ::3] = V
        V = wide[::2, ::3]  # every other row, every third column: a view with strides (144, 24)
        assert not V.flags.c_contiguous and not V.flags.f_contiguous
    elif variant == "int64 faces":
        F = F.astype(np.int64)
    elif variant == "uint32 faces":
        F = F.astype(np.uint32)
    elif variant == "lists":
        V, F = V.tolist(), F.tolist()
    np.testing.assert_array_equal(cshapes.geodesics(V, F, 5, method="fmm"), reference)


@pytest.mark.parametrize(
    "V, F, message",
    [
        (np.zeros((4, 2)), [[0, 1, 2]], r"V: expected an array of shape \(n, 3\).*got shape \(4, 2\)"),
        (np.zeros(12), [[0, 1, 2]], r"V: expected an array of shape \(n, 3\).*\(12,\)"),
        ([[0, 0, 0], [1, 0, 0], [0, float("nan"), 0]], [[0, 1, 2]], "V: row 2 has a non-finite coordinate"),
        (np.eye(3), [[0, 1, 3]], r"face 0 has vertex index 3, expected 0\.\.2"),
        (np.eye(3), [[0, 1, -1]], "face 0 has vertex index -1"),
        (np.eye(3), np.array([[0.0, 1.0, 2.0]]), "F: expected an .* integer array.*float64"),
        (np.eye(3), [[0, 1]], r"F: expected an array of shape \(n, 3\)"),
        (np.array([["a", "b", "c"]]), [[0, 0, 0]], "V: expected .*dtype <U1"),
        (None, [[0, 1, 2]], "V: expected .* got None"),
        (np.zeros((0, 3)), None, "empty mesh"),
    ],
)
def test_bad_arrays_raise_with_a_clear_message(V, F, message):
    with pytest.raises(ValueError, match=message):
        cshapes.mesh_info(V, F)


def test_topological_noise_adds_handles_and_keeps_vertices(shapes):
    V, F = cshapes.read_mesh(shapes[0])
    V2, F2, info = cshapes.add_topological_noise(V, F, glue=1, seed=1, return_info=True)
    np.testing.assert_array_equal(V2, V)
    assert len(info["pairs"]) == 1
    assert cshapes.mesh_info(V2, F2)["genus"] == cshapes.mesh_info(V, F)["genus"] + 1
    with pytest.raises(ValueError, match="found only 1 of 2 admissible pairs"):
        cshapes.add_topological_noise(V, F, glue=2, seed=1)
    with pytest.raises(TypeError, match="unexpected keyword argument 'glues'"):
        cshapes.add_topological_noise(V, F, glues=2)


def test_generate_matches_the_cli_files(cli, tmp_path):
    V, F = cshapes.generate("swissroll")
    cli("generate", "swissroll", "-o", tmp_path / "roll.off")
    V2, F2 = cshapes.read_mesh(tmp_path / "roll.off")
    np.testing.assert_array_equal(F, F2)
    np.testing.assert_allclose(V, V2, atol=1e-6)  # the CLI writes 6 decimals
    poses = cshapes.generate("articulated", class_="hand", poses=2, vertices=600, seed=1)
    assert len(poses) == 2 and np.array_equal(poses[0][1], poses[1][1])
    with pytest.raises(ValueError, match="unknown kind 'cube'"):
        cshapes.generate("cube")


def test_the_package_bounds_the_spin_as_the_cli_does():
    import os
    from pathlib import Path

    init = Path(cshapes.__file__).read_text()
    assert f'_os.environ["GOMP_SPINCOUNT"] = "{cshapes._cshapes.GOMP_SPINCOUNT}"' in init
    assert cshapes.get_num_threads() >= 1


def test_importing_restores_the_environment(tmp_path):
    """A fresh interpreter without OpenMP settings: the spin bound is set while the extension loads, then
    removed from the environment again."""
    import os
    import subprocess
    import sys

    env = {k: v for k, v in os.environ.items() if k not in ("OMP_WAIT_POLICY", "GOMP_SPINCOUNT")}
    code = "import os, cshapes; print('GOMP_SPINCOUNT' in os.environ)"
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_a_real_scan_with_a_non_manifold_edge_goes_through(cli):
    """kid00 (SHREC'16 TOPKIDS) has a non-manifold edge and a duplicate face: described like `info`, and its
    geodesics from a vertex of that edge are the CLI's, at the input's 12,000 vertices."""
    import os
    from pathlib import Path

    data = Path(os.environ.get("CSHAPES_DATA", Path(__file__).resolve().parents[3] / "shared" / "data"))
    kid = data / "topkids" / "kid00.off"
    if not kid.exists():
        pytest.skip(f"no shared data at {data}")
    V, F = cshapes.read_mesh(kid)
    info = cshapes.mesh_info(V, F)
    expected = cli.json("info", kid, "--json")
    expected.pop("file")
    assert info == expected and info["defects"]["nonmanifold_edges"]["count"] == 1
    with pytest.warns(UserWarning, match="repaired for geodesics"):
        row = cshapes.geodesics(V, F, 8425, method="fmm")
    reference = [float(line.split(",")[1]) for line in
                 cli("geodesics", kid, "--method", "fmm", "--source", "8425", "--csv").stdout.splitlines()[1:]]
    assert row.shape == (len(V),)
    np.testing.assert_allclose(row, reference, rtol=1e-9, atol=1e-9 * np.nanmax(row), equal_nan=True)
