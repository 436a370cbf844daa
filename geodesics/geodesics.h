// Geodesic distances on a triangle mesh: single-source, multi-source and all-pairs, by one of several
// methods.
//
// Methods (GeodesicOptions::method; names as parse_geodesic_method takes them):
//   heat       the heat method of our own (geodesics/heat_method.h): both systems factorised once (CHOLMOD),
//              sources solved in blocks of right-hand sides, in parallel. The fastest for all-pairs.
//              heat_mode IntrinsicDelaunay (default) or Direct, the same discretisations as CGAL's modes.
//   heat-cgal  CGAL's Heat_method_3 (geodesics/geodesics_cgal.h), one source at a time, heat_mode Direct or
//              IntrinsicDelaunay: the reference implementation.
//   fmm        fast marching on triangulated domains (Kimmel & Sethian 1998; geodesics/fast_marching.h).
//   exact      exact polyhedral geodesics (CGAL's Surface_mesh_shortest_path): slow, for validation.
//   graph      Dijkstra along mesh edges: exact on the edge graph, an upper bound of the surface geodesic
//              (typically 5-10% longer on irregular triangulations). Works on point-cloud kNN graphs too.
// Accuracy and cost: fmm and heat (intrinsic Delaunay) are within a few % of exact geodesics and closer on
// finer meshes; heat-mode direct is far off on needle triangles; heat is the cheapest per source, exact by
// far the dearest (the measurements, `cshapes bench geodesics`: docs/design.md, "Measured figures behind
// choices in the code").
//
// Distances are in the mesh's units. Unreachable vertices (other components) get +infinity in the
// single-source functions; all-pairs refuses disconnected meshes (an n×n matrix of infinities is useless to
// MDS). Every other distance is checked finite before it is returned, whatever the method: a NaN or infinity
// between two connected vertices throws a cshapes::Error naming the method, the source and the vertex (our
// heat method continues by fast marching where its heat underflows, see geodesics/heat_method.h; CGAL's does not
// and returns NaN on long shapes). Coarse meshes: see heat_method_warning (geodesics/heat_method.h).
#pragma once

#include <string>
#include <vector>

#include "cshapes/support/distance_matrix.h"
#include "cshapes/geodesics/geodesics_cgal.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/support/option_fields.h"
#include "cshapes/support/progress.h"
#include "cshapes/support/option_declaration.h"

namespace cshapes {

enum class GeodesicMethod {
  Heat,          // our block heat method
  HeatCgal,      // CGAL's Heat_method_3, one source at a time
  FastMarching,  // Kimmel & Sethian
  Exact,         // CGAL's Surface_mesh_shortest_path
  Graph,         // Dijkstra on the edge graph
};

// Parses "heat", "heat-cgal", "fmm", "exact", "graph"; throws listing the known names otherwise.
GeodesicMethod parse_geodesic_method(const std::string& name);
std::string to_string(GeodesicMethod method);
// {"heat", "heat-cgal", "fmm", "exact", "graph"}: the names parse_geodesic_method takes, in the enum's order.
const std::vector<std::string>& geodesic_method_names();

// The options of `cshapes geodesics` and geodesics() in Python, each declared once
// (support/option_declaration.h).
namespace geodesic_options {
inline const OptionDeclaration kMethod{
    "method", "--method",
    "heat (ours: block solves, CHOLMOD; the fastest), heat-cgal (CGAL's Heat_method_3, one source at a "
    "time), "
    "fmm (fast marching), exact (CGAL's Surface_mesh_shortest_path; slow) or graph (Dijkstra on the edges)",
    std::nullopt, geodesic_method_names()};
inline const OptionDeclaration kHeatMode{
    "heat_mode",
    "--heat-mode",
    "heat and heat-cgal only: idt (intrinsic Delaunay, the default; accurate on poor triangles) or direct",
    std::nullopt,
    {"idt", "direct"}};
}  // namespace geodesic_options

struct GeodesicOptions {
  GeodesicMethod method = GeodesicMethod::Heat;  // see the table above
  CgalHeatMode heat_mode =
      CgalHeatMode::IntrinsicDelaunay;  // heat and heat-cgal: Direct or IntrinsicDelaunay
  double heat_time_factor = 1.0;        // heat (ours): t = factor · h²
  ProgressFn progress;  // all pairs: called as sources finish; one source: polled first (support/progress.h)

  // Every field by name, for cache keys (support/option_fields.h). Self: GeodesicOptions, const or not.
  template <class Self, class Visit>
  static void for_each_field(Self& o, Visit&& visit) {
    visit("method", o.method);
    visit("heat_mode", o.heat_mode);
    visit("heat_time_factor", o.heat_time_factor);
    visit("progress", o.progress, kNoEffect);  // reports, computes nothing
  }
};

// Why `method` refuses `mesh` up front, "" when it accepts it. Only CGAL's methods refuse a mesh, one with a
// face of area below kExactMinFaceArea × (mean edge length)², naming it: exact (Surface_mesh_shortest_path
// unfolds faces through their angles and returns NaN across such a face) and heat-cgal (Heat_method_3
// requires non-degenerate faces; its intrinsic Delaunay flips never ended on two such meshes of the stress
// corpus). Our heat method, fast marching and graph accept it (ours works on mollified lengths). Every
// geodesic function below calls this first and throws the reason.
constexpr double kExactMinFaceArea = 1e-10;
std::string geodesic_method_refusal(const Mesh& mesh, GeodesicMethod method);

// Distances from the nearest of `sources` to every vertex (n values); +infinity where unreachable.
Eigen::VectorXd geodesic_distances(const Mesh& mesh, const std::vector<int>& sources,
                                   const GeodesicOptions& options = {});

// All n×n distances, symmetrised ((D + Dᵀ)/2), zero diagonal, OpenMP over sources.
// Refuses up front, with the figures, when n² floats do not fit in the available memory, and refuses
// disconnected meshes (naming the component sizes) since their distances are infinite.
DistanceMatrix all_pairs_geodesics(const Mesh& mesh, const GeodesicOptions& options = {});

// Replaces D by (D + Dᵀ)/2 in place, tile by tile (cache-friendly at n = 20K+), and zeroes the diagonal.
void symmetrize_distances(DistanceMatrix& D);

// Dijkstra on an arbitrary weighted edge graph (rest lengths as weights) from several sources.
Eigen::VectorXd dijkstra(Index num_vertices, const Adjacency& adj, const Eigen::VectorXd& edge_weights,
                         const std::vector<int>& sources);

}  // namespace cshapes
