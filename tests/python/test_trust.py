"""Issue 36's Python cases: no crash, no silently wrong number (the CLI's limits hold in Python too).

A call that used to crash the interpreter runs in a child interpreter, so a crash fails this test and not
the whole session.
"""
import os
import subprocess
import sys
import textwrap



def run_python(code):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, env=env)


def test_distance_matrix_caps_threads_as_the_cli_does():
    # threads=100000 crashed inside the OpenMP runtime (SIGSEGV); the CLI caps --threads at 4 per core.
    result = run_python(
        """
        import warnings
        import numpy as np
        import cshapes
        rng = np.random.default_rng(0)
        A = rng.standard_normal((60, 3))
        B = A @ np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1.0]]) + 0.5
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            D = cshapes.distance_matrix([A, B], threads=100000)
        print(D.shape, bool(np.isfinite(D).all() and D[0, 0] == 0), any("4 per core" in str(w.message) for w in caught))
        """
    )
    assert result.returncode == 0, f"exit {result.returncode}: {result.stderr}"
    assert result.stdout.split() == ["(2,", "2)", "True", "True"], result.stdout + result.stderr


def _separated_classes():
    import numpy as np

    D = np.ones((6, 6)) - np.eye(6)
    D[:3, :3] = D[3:, 3:] = 0.1
    np.fill_diagonal(D, 0)
    return D


def test_retrieval_measures_applies_the_rules_of_evaluate():
    import numpy as np
    import pytest

    import cshapes

    D = _separated_classes()
    labels = [0, 0, 0, 1, 1, 1]
    negative = D.copy()
    negative[0, 4] = negative[4, 0] = -1.0
    with pytest.raises(ValueError, match="expected >= 0"):
        cshapes.retrieval_measures(negative, labels)
    with pytest.raises(ValueError, match="min_class_size"):
        cshapes.retrieval_measures(D, labels, min_class_size=0)
    with pytest.raises(ValueError, match="'a'"):
        cshapes.retrieval_measures(D, labels, names=["a", "a", "b", "c", "d", "e"])
    # A label is its value: 1 and 1.0 are one class, as 1 and "1" are.
    as_floats = cshapes.retrieval_measures(D, [0.0, 0.0, 0.0, 1.0, 1.0, 1.0])
    as_text = cshapes.retrieval_measures(D, ["0", "0", "0", "1", "1", "1"])
    assert as_floats["map"] == as_text["map"] == 1
    assert as_floats["class_names"] == as_text["class_names"] == ["0", "1"]
    assert np.isfinite(cshapes.retrieval_measures(D, labels)["map"])


def test_keywords_a_call_would_ignore_are_refused_as_in_the_cli():
    import numpy as np
    import pytest

    import cshapes

    t = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    rows = [np.c_[np.cos(t) * r, np.sin(t) * r, np.full(12, z)] for r, z in ((1, 0), (1, 1), (1, 2))]
    V = np.vstack(rows)
    F = []
    for ring in range(2):
        for i in range(12):
            a, b = ring * 12 + i, ring * 12 + (i + 1) % 12
            F += [[a, b, b + 12], [a, b + 12, a + 12]]
    F = np.array(F)
    with pytest.raises(ValueError, match="heat_mode applies to method 'heat' or 'heat-cgal' only"):
        cshapes.geodesics(V, F, 0, method="fmm", heat_mode="direct")
    assert np.isfinite(cshapes.geodesics(V, F, 0, method="fmm")).all()
    with pytest.raises(ValueError, match="knn applies to point clouds"):
        cshapes.canonical_form(V, F, method="cmds", knn=6)


def test_sources_take_numpy_arrays_and_name_an_index_out_of_range():
    import numpy as np
    import pytest

    import cshapes

    t = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    V = np.vstack([np.c_[np.cos(t), np.sin(t), np.full(12, z)] for z in (0, 1, 2)])
    F = np.array([[r * 12 + i, r * 12 + (i + 1) % 12, r * 12 + (i + 1) % 12 + 12] for r in range(2) for i in range(12)]
                 + [[r * 12 + i, r * 12 + (i + 1) % 12 + 12, r * 12 + i + 12] for r in range(2) for i in range(12)])
    rows = cshapes.geodesics(V, F, np.array([0, 5]), method="fmm")
    assert rows.shape == (2, 36)
    assert np.array_equal(rows, cshapes.geodesics(V, F, [0, 5], method="fmm"))
    assert np.array_equal(cshapes.geodesics(V, F, np.int64(5), method="fmm"), rows[1])
    with pytest.raises(ValueError, match="9223372036854775808 is not a vertex index"):
        cshapes.geodesics(V, F, 2**63, method="fmm")
