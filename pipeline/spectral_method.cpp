#include "cshapes/pipeline/spectral_method.h"

#include "cshapes/canon/form_quality.h"
#include "cshapes/support/format.h"
#include "cshapes/support/error.h"
#include "cshapes/support/timing.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/form_quality_json.h"

namespace cshapes {

SpectralSolve spectral_eigenpairs(const Mesh& mesh, const LaplaceBeltramiOptions& laplacian,
                                  const CanonicalFormOptions& options, const std::string& method) {
  auto start = WallClock::now();
  if (mesh.is_point_cloud()) {
    const Components components = connected_components(mesh.num_vertices(), knn_graph(mesh.V, options.knn));
    CSHAPES_REQUIRE(components.count == 1, options.name, ": the ", options.knn.k,
                    "-nearest-neighbour graph has ", components.count,
                    " components (its Laplacian has as many zero eigenvalues): raise --knn");
  }
  SpectralSolve s;
  LaplaceBeltramiOptions lo = laplacian;
  if (!lo.progress) lo.progress = polls_of(options.progress);  // the form's stop, in each Lanczos product
  s.eigen = laplace_beltrami_eigen(laplace_beltrami_matrices(mesh, lo, options.knn), lo,
                                   options.name + ": " + method);
  s.seconds = seconds_since(start);
  const LaplaceBeltramiEigen& e = s.eigen;
  std::vector<double> values(e.values.data(), e.values.data() + e.values.size());
  s.summary = {{"laplacian", e.laplacian},
               {"solver", e.solver},
               {"eigenvalues", values},
               {"area", e.area},
               {"operator_products", e.operator_products},
               {"intrinsic_flips", e.flips},
               {"near_multiple", e.near_multiple},
               {"near_multiple_gap", laplacian.near_multiple_gap},
               {"eigen_seconds", e.seconds}};
  say(options.note, method + ": " + std::to_string(e.values.size()) + " eigenpairs of the " + e.laplacian +
                        " Laplacian by " + e.solver + " in " + significant(s.seconds) + " s; λ1..λ3 " +
                        significant(e.values[1]) + ", " + significant(e.values[2]) + ", " +
                        significant(e.values[3]));
  const std::string near = near_multiple_description(e);
  if (!near.empty()) say(options.note, method + ": " + near);
  for (const std::vector<int>& group : e.near_multiple) {
    if (group.front() <= 3 && group.back() >= 4) {
      const std::string warning =
          "λ3 and λ4 are near-multiple (relative gap below " + significant(laplacian.near_multiple_gap) +
          "): the form's third axis is one direction of a near-degenerate eigenspace, not set by the shape";
      s.summary["warning"] = warning;
      say(options.note, "warning: " + method + ": " + warning);
    }
  }
  return s;
}

std::string spectral_summary(const Mesh& mesh, const CanonicalFormOptions& options, const Points& X,
                             nlohmann::json summary, const std::string& method) {
  const FormQuality quality = form_quality(mesh.V, constraint_edges(mesh, options.knn), X);
  say(options.note, method + ": form quality " + quality.description);
  summary["form_quality"] = form_quality_json(quality);
  return summary.dump();
}

CanonicalFormMethod spectral_method_base(const std::string& name) {
  CanonicalFormMethod m;
  m.name = name;
  // As cmds: one component (a second would add a zero eigenvalue and eigenvectors of its own) and a
  // manifold surface (a pinched vertex or edge would couple two sheets through one point, which is
  // topological noise, not the surface's spectrum; splitting it gives each sheet its own).
  m.requirements = MeshRequirements::manifold_surface();
  m.repair_purpose = name + " (its Laplace-Beltrami eigenpairs need one manifold component)";
  m.uses_geodesic_matrix = false;
  m.options_not_read = {"coulomb", "geodesics", "cmds", "smacof", "smacof_init", "smacof_weights",
                        "distances_file", "spectral_mds", "mds_solver"};
  m.options_not_read.push_back(name == "lbo" ? "diffusion" : "lbo");  // the other one's
  return m;
}

}  // namespace cshapes
