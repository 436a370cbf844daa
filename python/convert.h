// numpy ⇄ Eigen at the Python module's edge, with the library's checks and messages.
//
// Inputs are read through any dtype of the right kind and any strides (C or Fortran order, slices, views):
// each is copied once into the library's own layout (an O(n) copy next to O(n log n) and costlier
// computations). Outputs are new C-contiguous arrays owned by numpy. Errors are cshapes::Error (ValueError in
// Python) naming the argument and what was expected.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cshapes/support/distance_matrix.h"
#include "cshapes/mesh/mesh.h"
#include "python/interrupt.h"

namespace cshapes::python {

namespace py = pybind11;

// n×3 real coordinates (float or integer dtype). allow_nonfinite: NaN rows pass (canonical forms whose
// repair dropped vertices); otherwise a non-finite coordinate is refused by its row.
Points to_points(const py::handle& array, const std::string& name, bool allow_nonfinite = false);
// m×3 vertex indices (integer dtype; 0×3 or None for a point cloud). Ranges are checked with the vertices
// (to_mesh).
Faces to_faces(const py::handle& array, const std::string& name);
// V, F as a Mesh, checked like a file's contents (mesh/io.h check_mesh_arrays).
Mesh to_mesh(const py::handle& V, const py::handle& F);
// n×n real matrix (any dtype of real numbers), square.
Eigen::MatrixXd to_matrix(const py::handle& array, const std::string& name);
// n×n distances as the library stores them (float32).
DistanceMatrix to_distance_matrix(const py::handle& array, const std::string& name);
// A 1-D array of n reals (name: the argument).
Eigen::VectorXd to_vector(const py::handle& array, const std::string& name);

// The scope of a computation: the GIL released (other Python threads run, and other computations start) and
// the module's thread count (set_num_threads) applied to this thread's OpenMP loops, fewer when other tasks
// keep cores busy (support/threads.h, as in the CLI); Ctrl-C heard by the progress callbacks of
// stop_on_python_signals (python/interrupt.h).
// A Ctrl-C that came while the arguments were converted (with the GIL held, before the InterruptScope: 0.7 s
// to copy a 9,000² matrix) is heard when the computation would start: KeyboardInterrupt, instead of at the
// call's end.
struct PendingSignals {
  PendingSignals();
};
struct Computing {
  Computing();
  PendingSignals pending;  // first: it needs the GIL
  InterruptScope interrupt;
  py::gil_scoped_release release;
};
// set_num_threads(n): 0 restores the default (OpenMP's at import). threads(): the count calls use.
void set_threads(int n);
int threads();

py::array_t<double> to_numpy(const Eigen::MatrixXd& M);  // rows × cols, C order
py::array_t<double> to_numpy(const Points& X);
py::array_t<float> to_numpy(const DistanceMatrix& D);
py::array_t<double> to_numpy(const Eigen::VectorXd& v);  // 1-D
py::array_t<int> to_numpy(const Faces& F);               // m×3 int32
py::array_t<int> to_numpy(const Eigen::VectorXi& v);     // 1-D int32

// A str or os.PathLike (pathlib.Path) as a path; anything else is refused naming the argument.
std::string to_path(const py::handle& path, const std::string& name);

// A UserWarning shown at the line that called the cshapes function: two frames up, past the Python wrapper
// every function has (cshapes/_api.py).
void warn(const std::string& message);

// JSON as Python objects (dict, list, str, float, int, bool, None), the CLI's --json output in Python form.
py::object to_python(const nlohmann::json& j);

}  // namespace cshapes::python
