"""A seeded sample of scripts/kept_tree_check.py (the long run: --seed 2 --count 48, docs/coulomb-defaults.md):
Coulomb forms with the fast sum's tree kept for 10 iterations against a tree built at every iteration, on two
generated meshes where the fast sum runs, as made and scaled by 1e12."""
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]


def test_sample_of_the_kept_tree_check(tmp_path):
    cli = os.environ.get("CSHAPES_CLI", str(ROOT / "build" / "cshapes"))
    result = subprocess.run(
        [sys.executable, str(ROOT / "scripts" / "kept_tree_check.py"), "--seed", "2", "--count", "2",
         "--min-vertices", "3000", "--max-vertices", "3600", "--cli", cli],
        capture_output=True, text=True, env=dict(os.environ), timeout=600)
    assert result.returncode == 0, result.stdout + result.stderr
    rows = [json.loads(line) for line in result.stdout.splitlines()]
    assert [r["variant"] for r in rows] == ["as-made", "scaled-1e12"]
    for r in rows:
        assert "error" not in r, r
        assert r["vertices"] >= 3000, r  # the fast sum runs (auto: from 3,000 points)
        # The kept tree changes the form in its last digits only: far below a hundredth of the diagonal.
        assert np.isfinite(r["kept_percent"]) and r["kept_percent"] < 0.01, r
        assert np.isfinite(r["accuracy_percent"]), r
