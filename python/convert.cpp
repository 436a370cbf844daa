#include "python/convert.h"

#include <omp.h>

#include <atomic>
#include <cmath>
#include <limits>

#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/support/threads.h"

namespace cshapes::python {

namespace {
const int g_default_threads = omp_get_max_threads();  // at import: OMP_NUM_THREADS or all cores
std::atomic<int> g_threads{0};
}  // namespace

void set_threads(int n) { g_threads = n; }
int threads() { return g_threads > 0 ? g_threads.load() : g_default_threads; }

namespace {

// A Ctrl-C during a long copy of an argument (the GIL held: 9,000² entries take a second or two, the first
// time in a process) is heard every 64 columns, not when the call ends.
void hear_ctrl_c(py::ssize_t column) {
  if (column % 64 == 0 && PyErr_CheckSignals() != 0) throw py::error_already_set();
}

}  // namespace

PendingSignals::PendingSignals() {
  if (PyErr_CheckSignals() != 0) throw py::error_already_set();
}

// OpenMP's thread count is a per-thread setting: set it in the thread that runs the work, lowered (as the
// CLI's) to the cores other tasks leave idle (support/threads.h; one /proc/loadavg read, ~20 µs).
// Long calls choose again between their stages (support/threads.h: refresh_threads).
Computing::Computing() {
  set_thread_request(threads());
  omp_set_num_threads(threads_for_computation(threads(), 1));
}

namespace {

std::string shape_text(const py::array& a) {
  std::string text = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) text += (d ? ", " : "") + std::to_string(a.shape(d));
  return text + (a.ndim() == 1 ? ",)" : ")");
}

std::string dtype_text(const py::array& a) { return py::str(a.dtype()).cast<std::string>(); }

// Any array-like as an ndarray (lists too), refusing object, string, bool and complex dtypes.
py::array as_array(const py::handle& object, const std::string& name, const char* kinds, const char* expected) {
  if (object.is_none()) fail(name, ": expected ", expected, ", got None");
  py::array a = py::array::ensure(object);
  if (!a) fail(name, ": expected ", expected, ", got ", py::str(py::type::of(object)).cast<std::string>());
  const char kind = a.dtype().kind();
  if (std::string(kinds).find(kind) == std::string::npos)
    fail(name, ": expected ", expected, ", got dtype ", dtype_text(a));
  return a;
}

void require_columns(const py::array& a, const std::string& name, py::ssize_t columns, const char* what) {
  if (a.ndim() != 2 || a.shape(1) != columns)
    fail(name, ": expected an array of shape (n, ", columns, ") of ", what, ", got shape ", shape_text(a));
}

}  // namespace

Points to_points(const py::handle& object, const std::string& name, bool allow_nonfinite) {
  py::array a = as_array(object, name, "fiu", "an (n, 3) array of coordinates");
  require_columns(a, name, 3, "coordinates");
  auto values = py::array_t<double, py::array::forcecast>::ensure(a);  // converts the dtype only
  auto r = values.unchecked<2>();                                       // any strides
  Points X(r.shape(0), 3);
  for (py::ssize_t i = 0; i < r.shape(0); ++i)
    for (int c = 0; c < 3; ++c) X(i, c) = r(i, c);
  if (!allow_nonfinite)
    for (Index i = 0; i < X.rows(); ++i)
      if (!X.row(i).allFinite()) fail(name, ": row ", i, " has a non-finite coordinate (NaN or Inf)");
  return X;
}

Faces to_faces(const py::handle& object, const std::string& name) {
  if (object.is_none()) return Faces(0, 3);
  py::array a = as_array(object, name, "iu", "an (m, 3) integer array of vertex indices");
  if (a.size() == 0) return Faces(0, 3);
  require_columns(a, name, 3, "vertex indices");
  auto values = py::array_t<long long, py::array::forcecast>::ensure(a);
  auto r = values.unchecked<2>();
  Faces F(r.shape(0), 3);
  for (py::ssize_t f = 0; f < r.shape(0); ++f)
    for (int c = 0; c < 3; ++c) {
      const long long v = r(f, c);
      if (v < 0 || v > std::numeric_limits<int>::max())
        fail(name, ": face ", f, " has vertex index ", v, ", expected 0..n-1");
      F(f, c) = static_cast<int>(v);
    }
  return F;
}

Mesh to_mesh(const py::handle& V, const py::handle& F) {
  Mesh mesh{to_points(V, "V"), to_faces(F, "F")};
  check_mesh_arrays(mesh, "mesh (V, F)");
  return mesh;
}

Eigen::MatrixXd to_matrix(const py::handle& object, const std::string& name) {
  py::array a = as_array(object, name, "fiu", "an (n, n) array of real numbers");
  if (a.ndim() != 2 || a.shape(0) != a.shape(1))
    fail(name, ": expected a square (n, n) array, got shape ", shape_text(a));
  Eigen::MatrixXd M(a.shape(0), a.shape(1));
  auto copy = [&M](const auto& r) {
    for (py::ssize_t j = 0; j < r.shape(1); ++j) {  // column-major target: walk columns outside
      hear_ctrl_c(j);
      for (py::ssize_t i = 0; i < r.shape(0); ++i) M(i, j) = static_cast<double>(r(i, j));
    }
  };
  // float32 (what cshapes.geodesics returns) is read as it is: numpy's own conversion to float64 would be a
  // second copy, which Ctrl-C cannot interrupt.
  if (py::isinstance<py::array_t<float>>(a))
    copy(py::array_t<float>::ensure(a).unchecked<2>());
  else
    copy(py::array_t<double, py::array::forcecast>::ensure(a).unchecked<2>());
  return M;
}

DistanceMatrix to_distance_matrix(const py::handle& object, const std::string& name) {
  py::array a = as_array(object, name, "fiu", "an (n, n) array of distances");
  if (a.ndim() != 2 || a.shape(0) != a.shape(1))
    fail(name, ": expected a square (n, n) array of distances, got shape ", shape_text(a));
  auto values = py::array_t<float, py::array::forcecast>::ensure(a);
  auto r = values.unchecked<2>();
  DistanceMatrix D = uninitialized_distance_matrix(r.shape(0), r.shape(1));
  for (py::ssize_t j = 0; j < r.shape(1); ++j) {  // column-major target: walk columns outside
    hear_ctrl_c(j);
    for (py::ssize_t i = 0; i < r.shape(0); ++i) D(i, j) = r(i, j);
  }
  return D;
}

Eigen::VectorXd to_vector(const py::handle& object, const std::string& name) {
  py::array a = as_array(object, name, "fiu", "a 1-D array of real numbers");
  if (a.ndim() != 1) fail(name, ": expected a 1-D array, got shape ", shape_text(a));
  auto values = py::array_t<double, py::array::forcecast>::ensure(a);
  auto r = values.unchecked<1>();
  Eigen::VectorXd v(r.shape(0));
  for (py::ssize_t i = 0; i < r.shape(0); ++i) v[i] = r(i);
  return v;
}

namespace {
template <typename Scalar, typename Matrix>
py::array_t<Scalar> matrix_to_numpy(const Matrix& M) {
  py::array_t<Scalar> out({static_cast<py::ssize_t>(M.rows()), static_cast<py::ssize_t>(M.cols())});
  auto w = out.template mutable_unchecked<2>();
  for (Index i = 0; i < M.rows(); ++i)
    for (Index j = 0; j < M.cols(); ++j) w(i, j) = static_cast<Scalar>(M(i, j));
  return out;
}
template <typename Scalar, typename Vector>
py::array_t<Scalar> vector_to_numpy(const Vector& v) {
  py::array_t<Scalar> out(static_cast<py::ssize_t>(v.size()));
  auto w = out.template mutable_unchecked<1>();
  for (Index i = 0; i < v.size(); ++i) w(i) = static_cast<Scalar>(v[i]);
  return out;
}
}  // namespace

py::array_t<double> to_numpy(const Eigen::MatrixXd& M) { return matrix_to_numpy<double>(M); }
py::array_t<double> to_numpy(const Points& X) { return matrix_to_numpy<double>(X); }
py::array_t<float> to_numpy(const DistanceMatrix& D) { return matrix_to_numpy<float>(D); }
py::array_t<double> to_numpy(const Eigen::VectorXd& v) { return vector_to_numpy<double>(v); }
py::array_t<int> to_numpy(const Faces& F) { return matrix_to_numpy<int>(F); }
py::array_t<int> to_numpy(const Eigen::VectorXi& v) { return vector_to_numpy<int>(v); }

std::string to_path(const py::handle& path, const std::string& name) {
  if (!py::isinstance<py::str>(path) && !py::hasattr(path, "__fspath__"))
    fail(name, ": expected a path (str or os.PathLike), got ", py::repr(path).cast<std::string>());
  py::object text = py::module_::import("os").attr("fspath")(path);
  if (!py::isinstance<py::str>(text)) fail(name, ": expected a text path, got bytes");
  return text.cast<std::string>();
}

py::object to_python(const nlohmann::json& j) {
  // Through the json module (already imported: sys.modules makes this a lookup). nlohmann writes a
  // non-finite number as null.
  return py::module_::import("json").attr("loads")(j.dump());
}

void warn(const std::string& message) {
  py::module_::import("warnings").attr("warn")(message, py::arg("stacklevel") = 2);
}

}  // namespace cshapes::python
