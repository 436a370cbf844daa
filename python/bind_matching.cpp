// cshapes.icp and shape_distance: rigid alignment of two point sets and the paper's distances after it
// (matching/icp.h, matching/shape_distance.h), as `cshapes align` computes them.
#include "cshapes/matching/icp.h"
#include "cshapes/matching/shape_distance.h"
#include "cshapes/support/error.h"
#include "cshapes/support/format.h"
#include "python/bindings.h"
#include "python/convert.h"
#include "python/interrupt.h"
#include "python/kwargs.h"
#include "python/declared_options.h"

namespace cshapes::python {

namespace {

struct PyAlignment {
  py::object R, t, transform, aligned, correspondences, correspondence_distances;
  bool reflection = false;
  double rmse = 0, hausdorff = 0, chamfer = 0, icp_rmse = 0, seconds = 0;
  double diagonal = 0;  // B's bounding-box diagonal: the scale the repr gives the distances against
  int iterations = 0;
  std::string stop_reason;
};

// "<cshapes.Alignment: hausdorff 0.0123 (0.615% of B's bbox diagonal), rmse 0.00456 (0.228%) in the inputs'
// units, 12 ICP iterations>": three significant figures, in the inputs' units and against B's bounding-box
// diagonal (the scale the benchmark's distances are read at); the full precision is in the attributes.
std::string alignment_repr(const PyAlignment& a) {
  const auto percent = [&](double d) { return significant(100 * d / a.diagonal) + "%"; };
  const bool scaled = a.diagonal > 0;
  return "<cshapes.Alignment: hausdorff " + significant(a.hausdorff) +
         (scaled ? " (" + percent(a.hausdorff) + " of B's bbox diagonal)" : "") + ", rmse " +
         significant(a.rmse) + (scaled ? " (" + percent(a.rmse) + ")" : "") + " in the inputs' units, " +
         counted(a.iterations, "ICP iteration") + (a.reflection ? ", a reflection>" : ">");
}

PyAlignment icp_py(const py::object& A_in, const py::object& B_in, const py::kwargs& kwargs) {
  const Points A = to_points(A_in, "A"), B = to_points(B_in, "B");
  Kwargs k(kwargs, "icp");
  IcpOptions options = read_icp_options(k);
  k.done();
  options.progress = stop_on_python_signals();  // Ctrl-C (python/interrupt.h)
  IcpResult r;
  ShapeDistance d;
  {
    Computing computing;
    d = aligned_shape_distance(A, B, options, &r);
  }
  PyAlignment out;
  out.R = to_numpy(Eigen::MatrixXd(r.transform.rotation));
  out.t = to_numpy(Eigen::VectorXd(r.transform.translation));
  out.transform = to_numpy(Eigen::MatrixXd(r.transform.matrix()));
  out.aligned = to_numpy(r.transform.apply(A));
  out.correspondences = to_numpy(r.source_to_target);
  out.correspondence_distances = to_numpy(r.source_to_target_distance);
  out.reflection = r.transform.is_reflection();
  out.rmse = d.rmse;
  out.hausdorff = d.hausdorff;
  out.chamfer = d.chamfer;
  out.icp_rmse = r.rmse;
  out.iterations = r.total_iterations;
  out.stop_reason = r.stop_reason;
  out.seconds = r.seconds;
  if (B.rows() > 0) out.diagonal = (B.colwise().maxCoeff() - B.colwise().minCoeff()).norm();
  return out;
}

double shape_distance_py(const py::object& A_in, const py::object& B_in, const std::string& kind, bool align,
                         const py::kwargs& kwargs) {
  // Rows with a NaN (vertices a repair dropped from a canonical form) are left out, as in distance_matrix.
  const Points A = to_points(A_in, "A", true), B = to_points(B_in, "B", true);
  CSHAPES_REQUIRE(kind == "hausdorff" || kind == "chamfer" || kind == "rmse",
                  "shape_distance(): kind: expected 'hausdorff', 'chamfer' or 'rmse', got '", kind, "'");
  Kwargs k(kwargs, "shape_distance");
  IcpOptions options = read_icp_options(k);
  k.done();
  options.progress = stop_on_python_signals();  // Ctrl-C (python/interrupt.h)
  CSHAPES_REQUIRE(align || kwargs.size() == 0, "shape_distance(): ICP options need align=True");
  ShapeDistance d;
  {
    Computing computing;
    d = align ? aligned_shape_distance(A, B, options) : shape_distance(A, B);
  }
  return kind == "hausdorff" ? d.hausdorff : kind == "chamfer" ? d.chamfer : d.rmse;
}

}  // namespace

// The `cshapes align` options.
IcpOptions read_icp_options(Kwargs& k) {
  IcpOptions o;
  o.allow_reflections = !k.flag(icp_options::kNoReflections, false);
  o.symmetric = !k.flag(icp_options::kOneWay, false);
  o.try_axis_swaps = k.flag(icp_options::kAxisSwaps, o.try_axis_swaps);
  o.trim_fraction = k.number(icp_options::kTrim, o.trim_fraction);
  o.relative_tolerance = k.number(icp_options::kTolerance, o.relative_tolerance);
  return o;
}

void bind_matching(py::module_& m) {
  declare_keywords("icp", icp_options::kAll);
  declare_keywords("shape_distance", icp_options::kAll);
  py::class_<PyAlignment>(
      m, "Alignment", "A rigid alignment of A onto B: B ≈ A @ R.T + t (R orthogonal; det -1 when reflection)")
      .def_readonly("R", &PyAlignment::R, "(3, 3) orthogonal matrix")
      .def_readonly("t", &PyAlignment::t, "(3,) translation")
      .def_readonly("transform", &PyAlignment::transform, "(4, 4) homogeneous matrix")
      .def_readonly("aligned", &PyAlignment::aligned, "(n, 3): A after the alignment")
      .def_readonly("reflection", &PyAlignment::reflection)
      .def_readonly("rmse", &PyAlignment::rmse, "RMS nearest-neighbour distance, both directions")
      .def_readonly("hausdorff", &PyAlignment::hausdorff,
                    "the paper's distance: the largest nearest-neighbour distance")
      .def_readonly("chamfer", &PyAlignment::chamfer, "mean nearest-neighbour distance, both directions")
      .def_readonly("icp_rmse", &PyAlignment::icp_rmse, "RMS of the pairs ICP kept at its last step")
      .def_readonly("correspondences", &PyAlignment::correspondences,
                    "(n,) int32: for each point of A, its nearest point of B after the alignment")
      .def_readonly("correspondence_distances", &PyAlignment::correspondence_distances)
      .def_readonly("iterations", &PyAlignment::iterations, "ICP steps over every start and level")
      .def_readonly("stop_reason", &PyAlignment::stop_reason)
      .def_readonly("seconds", &PyAlignment::seconds)
      .def("__repr__", &alignment_repr);
  // One-line docstrings: cshapes/_api.py documents the Python functions (signature, numpy sections).
  m.def("icp", &icp_py, py::arg("A"), py::arg("B"),
        "Rigid ICP alignment of A onto B: see help(cshapes.icp).");
  m.def("shape_distance", &shape_distance_py, py::arg("A"), py::arg("B"), py::kw_only(),
        py::arg("kind") = "hausdorff", py::arg("align") = true,
        "Distance between two point sets after ICP: see help(cshapes.shape_distance).");
}

}  // namespace cshapes::python
