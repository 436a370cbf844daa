// The stress run: every geodesic method, every canonical form and ICP on the corpus of failure-prone meshes
// (data/stress_corpus.h), each checked against a reference, so that a method that fails on some mesh is
// found by code and its mesh kept as a regression test.
//
// Per mesh (one StressCase):
//   geodesics  from `sources` vertices, by each method (heat, heat-direct, heat-cgal, fmm, exact, graph), with
//              geodesics/geodesics.h's own checks (finite, no longer than all edges). The reference is CGAL's exact
//              geodesics up to exact_max_vertices vertices, fast marching above; the error is the mean of
//              |d - d_ref| / d_ref over the vertices more than 3 mean edge lengths from the source (as in
//              `cshapes bench geodesics`), per method. A method fails on a mesh when it throws, or when its
//              error exceeds its tolerance (geodesic_tolerance) on a mesh the method accepts as fine: meshes
//              for which heat_method_warning speaks (too coarse) are exempt from the heat methods' tolerance,
//              not from the finiteness check. A method that refuses the mesh up front by its stated
//              precondition (geodesic_method_refusal: exact and heat-cgal on zero-area faces) is recorded as refused, not
//              failed, and the reference is then fast marching.
//   canon      Coulomb, classical MDS and SMACOF (pipeline/canonical_forms.h, defaults; MDS on fast marching)
//              up to canon_max_vertices vertices: fails when it throws or a valid vertex is not finite; the
//              form-quality verdict is recorded, not judged (a pathological mesh may give a poor form).
//   icp        the mesh against a rigidly moved copy of itself (random rotation, possibly a reflection,
//              translation): fails when the Hausdorff distance after alignment exceeds 1e-3 of the diagonal.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cshapes/data/stress_corpus.h"

namespace cshapes {

struct GeodesicStressOptions {
  std::vector<std::string> geodesic_methods = {"heat", "heat-direct", "heat-cgal", "fmm", "exact", "graph"};
  int sources = 3;                   // source vertices per mesh (drawn from the case's seed)
  Index exact_max_vertices = 6000;   // exact geodesics (the reference) up to this size, fast marching above
  bool canon = true;                 // run the canonical forms
  Index canon_max_vertices = 4000;   // ... on meshes up to this size
  std::vector<std::string> canon_methods;  // ... of these methods; empty: every registered one
  bool icp = true;                   // run ICP against a moved copy
};

// The largest acceptable mean relative error of `method` against the reference (see above): heat and
// heat-cgal (intrinsic Delaunay) 10%, fmm 10%, exact 1e-6 (it is the reference up to exact_max_vertices),
// graph 25% (an upper bound along edges), heat-direct none (infinity: without intrinsic Delaunay flips the
// method has no accuracy guarantee on needles and obtuse fans, which is why it is not the default; only its
// finiteness is checked, and its error reported). These catch broken distance fields (a wrong field is off by tens of percent), not accuracy:
// the methods' accuracy is what the stress table reports (median and worst per method; the heat method is
// about 1-3% on meshes of 1,000+ vertices and up to 5-6% near its 300-vertex limit).
double geodesic_tolerance(const std::string& method);

struct StressOutcome {
  std::string what;           // method name ("heat", "coulomb", "icp")
  bool ran = false;           // false: skipped (size limit)
  bool failed = false;        // threw, non-finite, or beyond its tolerance
  std::string error;          // the exception's message, or why it counts as failed
  std::string refused;        // geodesics: the method refused the mesh up front (geodesic_method_refusal)
  double mean_error = -1;     // geodesics: mean relative error vs the reference; icp: Hausdorff / diagonal
  double max_error = -1;      // geodesics: the largest relative error over the measured vertices
  bool exempt = false;        // geodesics: the mesh is too coarse for the method's tolerance (heat warning)
  std::string verdict;        // canon: the form-quality line
  double seconds = 0;
};

struct StressCaseResult {
  StressCase stress_case;
  Index vertices = 0, faces = 0;
  Index boundary_edges = 0;
  long genus = 0;
  double min_face_area_ratio = 0;  // smallest face area over the median face area
  std::string reference;           // "exact" or "fmm"
  std::vector<StressOutcome> geodesics, canon;
  StressOutcome icp;
  double seconds = 0;
  bool failed() const;  // any outcome failed
};

// Runs one mesh through everything (see above). Never throws for a method's failure (it is recorded);
// throws only when the reference itself cannot be computed.
StressCaseResult run_stress_case(const StressCase& c, const Mesh& mesh, const GeodesicStressOptions& options = {});

// One case's result as a JSON object (what `cshapes stress` prints, one line per case, and
// scripts/stress_geodesics.py reads): case, kind, base, amount, vertices, faces, boundary_edges, genus,
// min_face_area_ratio, reference, seconds, failed, and per outcome {method: {ran, failed, error, mean_error,
// max_error, exempt, verdict, seconds}} under "geodesics", "canon" and "icp".
nlohmann::json stress_result_json(const StressCaseResult& result);

}  // namespace cshapes
