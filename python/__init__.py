"""cshapes: Coulomb shapes and MDS canonical forms, ICP shape distances and retrieval measures.

Arrays: V (n, 3) float64 coordinates, F (m, 3) int32/int64 vertex indices, D (n, n) distances; any real
dtype and any strides are accepted (copied once into the library's layout). Every function shows its options
with their defaults (help(cshapes.coulomb), inspect.signature); options are keywords, named as the CLI names
them in snake_case, with the library's defaults. Long computations release the GIL and report progress
(progress=True, or a function; by default a bar on a terminal for calls longer than a second).

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

from ._cshapes import Alignment, CanonicalForm  # noqa: E402
from . import _api  # noqa: E402

# The functions: the extension's, each with its signature (from the stub and the methods' option
# declarations), numpy-style documentation and progress= (cshapes/_api.py).
_functions = _api.wrapped_functions()
add_topological_noise = _functions["add_topological_noise"]
build_info = _functions["build_info"]
canonical_form = _functions["canonical_form"]
canonical_form_methods = _functions["canonical_form_methods"]
classical_mds = _functions["classical_mds"]
compare_runs = _functions["compare_runs"]
coulomb = _functions["coulomb"]
distance_matrix = _functions["distance_matrix"]
experiment_invariance = _functions["experiment_invariance"]
experiment_noise = _functions["experiment_noise"]
experiment_paper = _functions["experiment_paper"]
experiment_pose = _functions["experiment_pose"]
experiment_retrieval = _functions["experiment_retrieval"]
experiment_topkids = _functions["experiment_topkids"]
generate = _functions["generate"]
geodesics = _functions["geodesics"]
get_num_threads = _functions["get_num_threads"]
icp = _functions["icp"]
mesh_info = _functions["mesh_info"]
method_options = _functions["method_options"]
option_declarations = _functions["option_declarations"]
read_mesh = _functions["read_mesh"]
retrieval_measures = _functions["retrieval_measures"]
set_num_threads = _functions["set_num_threads"]
shape_distance = _functions["shape_distance"]
show = _functions["show"]
smacof = _functions["smacof"]
write_mesh = _functions["write_mesh"]
ProgressBar = _api.ProgressBar

__version__ = _cshapes.__version__
__all__ = [
    "Alignment", "CanonicalForm", "ProgressBar", "add_topological_noise", "build_info", "canonical_form",
    "canonical_form_methods", "classical_mds", "compare_runs", "coulomb", "distance_matrix",
    "experiment_invariance", "experiment_noise", "experiment_paper", "experiment_pose", "experiment_retrieval",
    "experiment_topkids", "generate", "geodesics", "get_num_threads", "icp", "mesh_info", "method_options",
    "option_declarations", "read_mesh", "retrieval_measures", "set_num_threads", "shape_distance", "show",
    "smacof", "write_mesh",
]
