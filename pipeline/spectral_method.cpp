#include "cshapes/pipeline/spectral_method.h"

#include "cshapes/support/format.h"
#include "cshapes/support/error.h"
#include "cshapes/support/timing.h"
#include "cshapes/pipeline/canonical_form_methods.h"

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

CanonicalFormMethod spectral_method_base(const std::string& name) {
  CanonicalFormMethod m;
  m.name = name;
  // As cmds: one component (a second would add a zero eigenvalue and eigenvectors of its own) and a
  // manifold surface (a pinched vertex or edge would couple two sheets through one point, which is
  // topological noise, not the surface's spectrum; splitting it gives each sheet its own).
  m.requirements = MeshRequirements::manifold_surface();
  m.repair_purpose = name + " (its Laplace-Beltrami eigenpairs need one manifold component)";
  m.uses_geodesic_matrix = false;
  return m;
}

namespace {
using Ref = CanonicalFormOptions&;
// The Laplace–Beltrami options in each spectral method's group of CanonicalFormOptions.
std::vector<LaplaceBeltramiOptions*> laplacians(CanonicalFormOptions& c) {
  return {&c.lbo.laplacian, &c.diffusion.laplacian, &c.spectral_mds.laplacian};
}
}  // namespace

MethodOption laplacian_option() {
  MethodOption o = option_of("laplacian", MethodOption::Type::Choice,
                             "cotangent Laplacian on the intrinsic-delaunay triangulation or on the mesh's own "
                             "triangles (cotangent); point clouds use their kNN graph",
                             {"lbo", "diffusion", "spectral_mds"});
  o.choices = {"intrinsic-delaunay", "cotangent"};
  o.get = [](const CanonicalFormOptions& c) {
    return OptionValue(std::string(c.lbo.laplacian.intrinsic_delaunay ? "intrinsic-delaunay" : "cotangent"));
  };
  o.set = [](CanonicalFormOptions& c, const OptionValue& v) {
    for (LaplaceBeltramiOptions* l : laplacians(c)) l->intrinsic_delaunay = std::get<std::string>(v) == "intrinsic-delaunay";
  };
  return o;
}

MethodOption eigenpairs_option() {
  MethodOption o = integer_option<int>(
      "eigenpairs",
      "eigenpairs computed, the constant one included (the form uses 3; the rest detect near-multiple "
      "eigenvalues)",
      laplace_beltrami_limits::kEigenpairs, {"lbo", "diffusion"}, [](Ref c) -> int& { return c.lbo.laplacian.eigenpairs; });
  const auto set = o.set;
  o.set = [set](CanonicalFormOptions& c, const OptionValue& v) {  // spectral-mds's are its --basis
    set(c, v);
    c.diffusion.laplacian.eigenpairs = c.lbo.laplacian.eigenpairs;
  };
  return o;
}

MethodOption near_multiple_gap_option() {
  MethodOption o = number_option("near_multiple_gap", "report consecutive eigenvalues closer than this relative gap",
                                 laplace_beltrami_limits::kNearMultipleGap, {"lbo", "diffusion", "spectral_mds"},
                                 [](Ref c) -> double& { return c.lbo.laplacian.near_multiple_gap; });
  o.set = [](CanonicalFormOptions& c, const OptionValue& v) {
    for (LaplaceBeltramiOptions* l : laplacians(c)) l->near_multiple_gap = std::get<double>(v);
  };
  return o;
}

}  // namespace cshapes
