"""ICP, shape distances, distance matrices and retrieval measures from Python against known answers and the
CLI (`cshapes align`, `distmat`, `evaluate`)."""
import numpy as np
import pytest

import cshapes


def random_rotation(seed):
    q, r = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    q *= np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def test_icp_recovers_a_rigid_motion(shapes):
    A, _ = cshapes.read_mesh(shapes[0])
    R, t = random_rotation(4), np.array([0.3, -2.0, 1.0])
    B = A @ R.T + t
    a = cshapes.icp(A, B)
    scale = np.linalg.norm(A - A.mean(0), axis=1).max()
    np.testing.assert_allclose(a.R, R, atol=1e-6)
    np.testing.assert_allclose(a.t, t, atol=1e-6 * scale)
    np.testing.assert_allclose(a.aligned, B, atol=1e-6 * scale)
    assert not a.reflection and a.hausdorff < 1e-6 * scale
    np.testing.assert_array_equal(a.correspondences, np.arange(len(A)))
    mirrored = cshapes.icp(A, B * [1, 1, -1])
    assert mirrored.reflection and mirrored.hausdorff < 1e-6 * scale
    assert cshapes.icp(A, B * [1, 1, -1], no_reflections=True).hausdorff > 1e-3 * scale


def test_shape_distance_is_the_cli_align(cli, shapes):
    A, _ = cshapes.read_mesh(shapes[0])
    B, _ = cshapes.read_mesh(shapes[1])
    expected = cli.json("align", shapes[0], shapes[1], "--json")
    assert cshapes.shape_distance(A, B) == expected["hausdorff"]
    assert cshapes.shape_distance(A, B, kind="chamfer") == expected["chamfer"]
    a = cshapes.icp(A, B)
    np.testing.assert_array_equal(a.R, np.array(expected["rotation"]))
    assert cshapes.shape_distance(A, A, align=False) == 0
    with pytest.raises(ValueError, match="kind: expected"):
        cshapes.shape_distance(A, B, kind="frechet")


def test_distance_matrix_and_retrieval_measures_match_distmat_and_evaluate(cli, tmp_path):
    data = tmp_path / "data"
    cli("generate", "dataset", "--out", data, "--classes", "2", "--poses", "3", "--noisy", "0", "--vertices", "500")
    cli("distmat", data, "-o", tmp_path / "D.csv", "--method", "coulomb")
    header = (tmp_path / "D.csv").read_text().splitlines()[0].split(",")
    D_cli = np.loadtxt(tmp_path / "D.csv", delimiter=",", skiprows=1)
    forms = [cshapes.coulomb(*cshapes.read_mesh(data / f"{name}.off")) for name in header]
    D = cshapes.distance_matrix(forms, cache=str(tmp_path / "pairs"))
    assert D.shape == (6, 6) and np.array_equal(D, D.T) and not np.diag(D).any()
    # distmat aligns each pair in the order of its cache keys, this call in the order of the coordinates'
    # hashes: the same ICP from the other side, equal to its tolerance
    np.testing.assert_allclose(D, D_cli, rtol=2e-2, atol=1e-9)
    again = cshapes.distance_matrix([f.X for f in forms], cache=str(tmp_path / "pairs"))
    np.testing.assert_array_equal(again, D)  # from the cache

    classes = [name.rstrip("0123456789") for name in header]
    measures = cshapes.retrieval_measures(D_cli, classes, names=header)
    expected = cli.json("evaluate", tmp_path / "D.csv", "--out", tmp_path / "eval", "--json")
    for key in ["map", "nn", "ft", "st", "e", "dcg", "pr", "classes", "queries"]:
        assert measures[key] == expected[key], key
    assert np.array(measures["confusion"]).sum() == 6
    with pytest.raises(ValueError, match="labels: 5 labels for a 6x6 matrix"):
        cshapes.retrieval_measures(D, classes[:5])


def test_retrieval_measures_known_answer():
    # two classes of three, perfectly separated: every measure is 1
    D = np.ones((6, 6)) - np.eye(6)
    D[:3, :3] = D[3:, 3:] = 0.1
    np.fill_diagonal(D, 0)
    m = cshapes.retrieval_measures(D, [0, 0, 0, 1, 1, 1])
    assert m["map"] == 1 and m["nn"] == 1 and m["ft"] == 1
    assert m["confusion"] == [[3, 0], [0, 3]]


def test_retrieval_measures_ties_are_expectations():
    # issue 57: a constant matrix was ranked by index (mAP 0.505, the first class 1.0). Every measure is its
    # expectation over the orders of the tied shapes: a brute force over the C(11, 3) equally likely places of
    # a query's 3 relevant shapes among its 11 results is the reference.
    from itertools import combinations

    places = list(combinations(range(1, 12), 3))
    expected_ap = sum(sum((k + 1) / rank for k, rank in enumerate(p)) / 3 for p in places) / len(places)
    labels = ["a"] * 4 + ["b"] * 4 + ["c"] * 4
    for value in (0.0, 5.0):
        m = cshapes.retrieval_measures(np.full((12, 12), value), labels)
        assert m["map"] == pytest.approx(expected_ap, abs=1e-12)
        assert m["nn"] == pytest.approx(3 / 11, abs=1e-15)
        assert {c: round(v["map"], 12) for c, v in m["classes"].items()} == {c: round(expected_ap, 12) for c in "abc"}
        assert m["tied_queries"] == 12
        assert np.allclose(m["confusion"], 4 * (np.full((3, 3), 4 / 11) - np.eye(3) / 11))


def test_retrieval_measures_one_class_is_refused():
    # every result relevant: every measure would be 1 whatever the distances
    with pytest.raises(ValueError, match="one class"):
        cshapes.retrieval_measures(np.ones((5, 5)), ["x"] * 5)


DEGENERATE = {
    "one point": np.array([[1.0, 2.0, 3.0]]),
    "50 copies of one point": np.tile([0.1, 0.2, 0.3], (50, 1)),
    "points on a line": np.outer(np.linspace(0, 1, 30), [1.0, -1.0, 2.0]) + [1.0, 2.0, 3.0],
}


@pytest.mark.parametrize("name", sorted(DEGENERATE))
def test_sets_that_span_no_plane_are_refused_by_name(name):
    """Issue 57: icp and shape_distance ended the interpreter (exit 139) on such a set."""
    points = DEGENERATE[name]
    V, _ = cshapes.generate("icosphere", subdivisions=2)
    for call, which in [(lambda: cshapes.icp(points, V), "source set (A)"),
                        (lambda: cshapes.shape_distance(V, points), "target set (B)"),
                        (lambda: cshapes.distance_matrix([V, points]), "shape 1")]:
        with pytest.raises(ValueError, match="span a plane") as error:
            call()
        assert which in str(error.value)


def test_sets_of_incomparable_sizes_are_refused_and_one_scale_works():
    """Issue 57: a shape scaled by 1e-150 aligned with the unscaled one ended the interpreter; scaled together
    by any finite factor, the distance scales with them."""
    V, _ = cshapes.generate("icosphere", subdivisions=2)
    for s in (1e-150, 1e150):
        with pytest.raises(ValueError, match="size"):
            cshapes.shape_distance(V * s, V)
        assert cshapes.shape_distance(V * s, 0.9 * V * s) / s == pytest.approx(
            cshapes.shape_distance(V, 0.9 * V), rel=1e-9)
        assert cshapes.distance_matrix([V * s, 0.9 * V * s])[0, 1] / s == pytest.approx(
            cshapes.distance_matrix([V, 0.9 * V])[0, 1], rel=1e-9)
