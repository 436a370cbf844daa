"""cshapes: Coulomb shapes and MDS canonical forms, ICP shape distances and retrieval measures.

Arrays: V (n, 3) float64 coordinates, F (m, 3) int32/int64 vertex indices, D (n, n) distances; any real
dtype and any strides are accepted (copied once into the library's layout). Keyword options carry the
CLI's names (--tear-fraction -> tear_fraction) and defaults. Long computations release the GIL.

The extension is cshapes._cshapes. Before loading it (and with it libgomp, which reads its settings once)
this package bounds OpenMP's spin-wait as the CLI does (GOMP_SPINCOUNT=1000, docs/python.md) unless
OMP_WAIT_POLICY or GOMP_SPINCOUNT is set, and restores the environment afterwards. If another module loaded
libgomp first, its setting stays.
"""
import os as _os

_chosen = "OMP_WAIT_POLICY" in _os.environ or "GOMP_SPINCOUNT" in _os.environ
if not _chosen:
    _os.environ["GOMP_SPINCOUNT"] = "1000"  # = cshapes._cshapes.GOMP_SPINCOUNT (support/threads.h)
try:
    from . import _cshapes
finally:
    if not _chosen:
        del _os.environ["GOMP_SPINCOUNT"]

from ._cshapes import (  # noqa: E402
    Alignment,
    CanonicalForm,
    add_topological_noise,
    canonical_form,
    canonical_form_methods,
    classical_mds,
    build_info,
    compare_runs,
    coulomb,
    distance_matrix,
    experiment_invariance,
    experiment_noise,
    experiment_paper,
    experiment_pose,
    experiment_retrieval,
    experiment_topkids,
    generate,
    geodesics,
    get_num_threads,
    icp,
    mesh_info,
    read_mesh,
    retrieval_measures,
    set_num_threads,
    shape_distance,
    show,
    smacof,
    write_mesh,
)

__version__ = _cshapes.__version__
__all__ = [
    "Alignment", "CanonicalForm", "add_topological_noise", "build_info", "canonical_form", "classical_mds",
    "compare_runs", "coulomb", "distance_matrix", "experiment_invariance", "experiment_noise", "experiment_paper", "experiment_pose", "experiment_retrieval",
    "experiment_topkids", "generate", "geodesics", "get_num_threads",
    "icp", "mesh_info", "read_mesh",
    "retrieval_measures", "set_num_threads", "shape_distance", "show", "smacof", "write_mesh",
]
