// Method coulomb (pipeline/canonical_form_methods.h): the Coulomb canonical form, §2 of the paper
// (canon/coulomb.h), on the mesh's edges or a point cloud's kNN graph.
#include <nlohmann/json.hpp>

#include "cshapes/canon/coulomb.h"
#include "cshapes/canon/coulomb_multiresolution.h"
#include "cshapes/support/format.h"
#include "cshapes/support/error.h"
#include "cshapes/support/timing.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/form_quality_json.h"

namespace cshapes {

namespace {

CanonicalForm coulomb_compute(const Mesh& mesh, const CanonicalFormOptions& options, const GivenDistances&) {
  auto start = WallClock::now();
  const Edges E = constraint_edges(mesh, options.knn);
  if (mesh.is_point_cloud()) {
    // A point cloud's kNN graph stands in for the mesh's edges; its parts would drift apart if it fell apart.
    const Components components = connected_components(mesh.num_vertices(), E);
    CSHAPES_REQUIRE(components.count == 1, options.name, ": the ", options.knn.k,
                    "-nearest-neighbour graph has ", components.count,
                    " components; its parts would drift apart: raise --knn");
    say(options.note, options.name + ": point cloud, " + std::to_string(E.rows()) +
                          " kNN edges (k = " + std::to_string(options.knn.k) + ")");
  }
  CanonicalForm form;
  form.precompute_seconds = seconds_since(start);
  CoulombCanonOptions co = options.coulomb;
  if (!co.progress) co.progress = options.progress;
  // A mesh finer than options.coulomb.multiresolution.above_vertices goes through a coarse version of its
  // surface (canon/coulomb_multiresolution.h); point clouds and coarser meshes run the iteration directly.
  CoulombCanonResult r;
  std::string multiresolution;
  if (mesh.is_point_cloud()) {
    r = coulomb_canonical_form(mesh.V, E, co);
  } else {
    CoulombMultiresolutionResult mr = coulomb_multiresolution(mesh, co);
    if (mr.used) say(options.note, "coulomb: " + mr.note);
    multiresolution = mr.note;
    r = std::move(mr.result);
  }
  form.X = r.X;
  form.torn = r.torn_vertices;
  form.iterations = r.iterations;
  form.solve_seconds = r.seconds;
  form.seconds_per_iteration = r.iterations ? r.seconds / r.iterations : 0;
  form.history_columns = {"iteration", "energy",     "mean_violation", "max_violation", "step",
                          "max_move",  "torn_edges", "shape_change",   "momentum",      "seconds"};
  for (const CoulombIterationRecord& h : r.history)
    form.history_rows.push_back({double(h.iteration), h.energy, h.mean_violation, h.max_violation, h.step,
                                 h.max_move, double(h.torn_edges), h.shape_change, h.momentum, h.seconds});
  form.summary_json = nlohmann::json{{"vertices", mesh.num_vertices()},
                                     {"edges", E.rows()},
                                     {"torn_edges", r.torn_edges.rows()},
                                     {"iterations", r.iterations},
                                     {"multiresolution", multiresolution},
                                     {"converged", r.converged},
                                     {"stop_reason", r.stop_reason},
                                     {"energy", r.energy},
                                     {"mean_violation", r.violation.mean_relative},
                                     {"max_violation", r.violation.max_relative},
                                     {"median_length_ratio", r.violation.median_length_ratio},
                                     {"seconds", r.seconds},
                                     {"scheme", to_string(co.scheme)},
                                     {"start", r.start},
                                     {"flatten", co.flatten},
                                     {"step_rule", to_string(co.step_rule)},
                                     {"step_gradient", to_string(co.step_gradient)},
                                     {"projection", to_string(co.projection.norm)},
                                     {"projection_steps", co.projection.steps},
                                     {"form_quality", form_quality_json(r.quality)}}
                          .dump();
  say(options.note, "coulomb: started at " + r.start);
  say(options.note, "coulomb: " + std::to_string(r.iterations) + " iterations (" + r.stop_reason + ") in " +
                        significant(r.seconds) + " s; edge lengths off their rest lengths by " +
                        significant(100 * r.violation.mean_relative) + "% on average, " +
                        std::to_string(r.torn_edges.rows()) + " edges torn");
  say(options.note, "coulomb: form quality " + r.quality.description);
  return form;
}

}  // namespace

CanonicalFormMethod coulomb_method() {
  CanonicalFormMethod m;
  m.name = "coulomb";
  m.title = "Coulomb";
  m.requirements = MeshRequirements::edge_graph();
  m.repair_purpose = "Coulomb canonization (the largest component's edge graph)";
  m.uses_geodesic_matrix = false;
  m.options_not_read = {"geodesics",      "cmds",           "smacof", "smacof_init", "smacof_weights",
                        "distances_file", "lbo",            "diffusion", "spectral_mds", "mds_solver"};
  m.has_history = true;
  m.compute = coulomb_compute;
  return m;
}

}  // namespace cshapes
