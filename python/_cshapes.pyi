# Type stubs of cshapes._cshapes: every function with its keywords and their defaults, for editors, type
# checkers and readers (the functions themselves take most keywords through **kwargs, in the CLI's names).
# tests/python/test_stubs.py checks this file against the module: every function and keyword here exists,
# every keyword the module reads is here, and each default here gives the same result as leaving it out.
from os import PathLike
from typing import Any, Literal, Sequence, overload

import numpy as np
import numpy.typing as npt

_Path = str | PathLike[str]
_Array = npt.ArrayLike
_Geodesics = Literal["fmm", "heat", "heat-cgal", "exact", "graph"]

__version__: str
GOMP_SPINCOUNT: int

def build_info() -> dict[str, Any]:
    """{'version', 'build', 'simd', 'simd_supported'}: the module's version, build and kernels' instruction set."""

class CanonicalForm:
    """A canonical form: X (n, 3), valid (n,), torn (n,) or None, history, iterations, summary, seconds."""
    X: np.ndarray
    valid: np.ndarray
    torn: np.ndarray | None
    history: dict[str, np.ndarray]
    iterations: int
    summary: dict[str, Any]
    seconds: float

class Alignment:
    """A rigid alignment of A onto B: B ≈ A @ R.T + t (R orthogonal; det -1 when reflection)."""
    R: np.ndarray
    t: np.ndarray
    transform: np.ndarray
    aligned: np.ndarray
    reflection: bool
    rmse: float
    hausdorff: float
    chamfer: float
    icp_rmse: float
    correspondences: np.ndarray
    correspondence_distances: np.ndarray
    iterations: int
    stop_reason: str
    seconds: float

# Meshes
def read_mesh(path: _Path, *, fields: bool = False) -> tuple[np.ndarray, np.ndarray] | tuple[np.ndarray, np.ndarray, dict[str, np.ndarray]]: ...
def write_mesh(path: _Path, V: _Array, F: _Array, *, binary: bool = False, **vertex_fields: _Array) -> None: ...
def mesh_info(V: _Array, F: _Array) -> dict[str, Any]: ...
def geodesics(V: _Array, F: _Array, sources: int | Sequence[int] | None = None, *,
              method: Literal["heat", "heat-cgal", "fmm", "exact", "graph"] = "heat",
              heat_mode: Literal["idt", "direct"] | None = None, strict: bool = False) -> np.ndarray: ...
def add_topological_noise(V: _Array, F: _Array, *, glue: int = 1, seed: int = 0, max_gap: float = 0.0,
                          gap_edges: float = 6.0, min_ratio: float = 5.0, min_fraction: float = 0.1,
                          separation: float = 0.15, relax: int = 0, geodesics: _Geodesics = "graph",
                          return_info: bool = False) -> Any: ...
@overload
def generate(kind: Literal["swissroll"], *, vertices: int = 561) -> tuple[np.ndarray, np.ndarray]: ...
@overload
def generate(kind: Literal["icosphere"], *, subdivisions: int = 3, radius: float = 1.0) -> tuple[np.ndarray, np.ndarray]: ...
@overload
def generate(kind: Literal["articulated"], *, class_: Literal["biped", "quadruped", "hand", "spider"] = "biped",
             poses: int = 5, seed: int = 0, vertices: int = 3500, amplitude: float = 1.0) -> list[tuple[np.ndarray, np.ndarray]]: ...
@overload
def generate(kind: Literal["hand"], *, seed: int = 0, glue: int = 3) -> dict[str, Any]: ...
@overload
def generate(kind: Literal["dataset"], *, classes: int = 4, poses: int = 5, noisy: int = 1, glue: int = 2,
             seed: int = 0, vertices: int = 3500) -> list[dict[str, Any]]: ...

# Canonical forms
def canonical_form_methods() -> list[dict[str, Any]]: ...
def coulomb(V: _Array, F: _Array, *, scheme: Literal["paper", "momentum"] = "momentum",
            coulomb_start: Literal["landmark-mds", "input"] = "landmark-mds", start_landmarks: int = 50,
            flatten: float = 0.001,
            step_rule: Literal["max-edge", "mean-edge", "median-edge", "fixed"] = "mean-edge",
            step_gradient: Literal["max", "mean"] = "mean", step_factor: float = 0.1, fixed_step: float = 0.0,
            coulomb_steps: int = 1, projection_steps: int = 10, projection: Literal["l2", "l1"] = "l2",
            l1_floor: float = 0.05, dilation: float = 1.0, tear_fraction: float = 0.01, tear_after: int = 300,
            tear_times: int = 3, tear_interval: int = 50, tear_guard: Literal["connected", "vertex"] = "connected",
            coulomb_max_iterations: int = 3000, coulomb_window: int = 20, coulomb_tolerance: float = 0.001,
            momentum: float = 0.9,
            coulomb_summation: Literal["auto", "direct", "direct-float", "fast"] = "auto",
            coulomb_accuracy: float = 0.01, coulomb_multiresolution_above: int = 8000,
            coulomb_coarse_vertices: int = 5000, coulomb_tear_rounds: int = 20, knn: int = 8,
            strict: bool = False) -> CanonicalForm: ...
# Each method reads its own keywords (coulomb: those of coulomb(); cmds, smacof and spectral-mds: geodesics;
# cmds and smacof: mds_solver, landmarks; smacof: fold_overstretch to weights; lbo, diffusion,
# spectral-mds: laplacian, near_multiple_gap; lbo and diffusion: eigenpairs; diffusion: diffusion_time;
# spectral-mds: basis, sources; every method: knn, strict) and refuses the others, naming the methods that read
# them (the method registry's table: help(cshapes.canonical_form) lists it).
def canonical_form(V: _Array, F: _Array, *, method: str = "coulomb",
                   scheme: Literal["paper", "momentum"] = "momentum",
                   coulomb_start: Literal["landmark-mds", "input"] = "landmark-mds", start_landmarks: int = 50,
                   flatten: float = 0.001,
                   step_rule: Literal["max-edge", "mean-edge", "median-edge", "fixed"] = "mean-edge",
                   step_gradient: Literal["max", "mean"] = "mean", step_factor: float = 0.1,
                   fixed_step: float = 0.0, coulomb_steps: int = 1, projection_steps: int = 10,
                   projection: Literal["l2", "l1"] = "l2", l1_floor: float = 0.05, dilation: float = 1.0,
                   tear_fraction: float = 0.01, tear_after: int = 300, tear_times: int = 3,
                   tear_interval: int = 50, tear_guard: Literal["connected", "vertex"] = "connected",
                   coulomb_max_iterations: int = 3000, coulomb_window: int = 20,
                   coulomb_tolerance: float = 0.001, momentum: float = 0.9,
                   coulomb_summation: Literal["auto", "direct", "direct-float", "fast"] = "auto",
                   coulomb_accuracy: float = 0.01, coulomb_multiresolution_above: int = 8000,
                   coulomb_coarse_vertices: int = 5000, coulomb_tear_rounds: int = 20, knn: int = 8,
                   geodesics: _Geodesics = "heat",
                   mds_solver: Literal["full", "landmarks", "auto"] = "auto", landmarks: int = 300,
                   fold_overstretch: float = 3.0, iters: int = 300, tolerance: float = 1e-05,
                   accelerate: Literal["none", "rre", "mpe"] = "none", window: int = 6,
                   init: Literal["cmds", "mesh"] = "cmds", weights: Literal["uniform", "area"] = "uniform",
                   laplacian: Literal["intrinsic-delaunay", "cotangent"] = "intrinsic-delaunay",
                   eigenpairs: int = 10, near_multiple_gap: float = 0.02, diffusion_time: float = 1.0,
                   basis: int = 40, sources: int = 120,
                   strict: bool = False) -> CanonicalForm: ...
def classical_mds(D: _Array, dim: int = 3) -> CanonicalForm: ...
def smacof(D: _Array, X0: _Array | None = None, *, iters: int = 300, tolerance: float = 1e-05,
           accelerate: Literal["none", "rre", "mpe"] = "none", window: int = 6,
           weights: _Array | None = None) -> CanonicalForm: ...

# Matching and evaluation
def icp(A: _Array, B: _Array, *, no_reflections: bool = False, one_way: bool = False, axis_swaps: bool = False,
        trim: float = 0.0, tolerance: float = 0.001) -> Alignment: ...
def shape_distance(A: _Array, B: _Array, *, kind: Literal["hausdorff", "chamfer", "rmse"] = "hausdorff",
                   align: bool = True, no_reflections: bool = False, one_way: bool = False,
                   axis_swaps: bool = False, trim: float = 0.0, tolerance: float = 0.001) -> float: ...
def distance_matrix(forms: Sequence[_Array | CanonicalForm], *,
                    metric: Literal["hausdorff", "chamfer", "rmse"] = "hausdorff", cache: _Path | None = None,
                    threads: int = 0, no_reflections: bool = False, one_way: bool = False,
                    axis_swaps: bool = False, trim: float = 0.0, tolerance: float = 0.001) -> np.ndarray: ...
def retrieval_measures(D: _Array, labels: Sequence[Any], *, names: Sequence[str] | None = None,
                       min_class_size: int = 3) -> dict[str, Any]: ...

# Experiments
def experiment_paper(data: _Path, out: _Path, methods: Sequence[str] | None = None, poses_per_class: int = 4,
                     noisy_per_class: int = 1, table1: bool = True, figure_data: bool = True, draw: bool = True, *,
                     glue: int = 2, seed: int = 1, timing_repeats: int = 5, correspondence_samples: int = 300,
                     strict: bool = False, geodesics: _Geodesics = "heat", resample: int = 0) -> dict[str, Any]: ...
def experiment_retrieval(data: _Path, out: _Path, methods: Sequence[str] | None = None, resample: int = 0,
                         draw: bool = True, *, strict: bool = False, geodesics: _Geodesics = "heat",
                         e_depth: int = 32, min_class_size: int = 3) -> dict[str, Any]: ...
# Pictures
def show(mesh: _Path | tuple[_Array, _Array], form: _Path | _Array | tuple[_Array, _Array] | CanonicalForm | None = None,
         *, out: _Path, title: str | None = None, view: Literal["pca", "x", "y", "z"] = "pca") -> str: ...

# Threads
def set_num_threads(n: int) -> None: ...
def get_num_threads() -> int: ...
