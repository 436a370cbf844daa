// cshapes align A B [--json] [--no-reflections] [-o aligned.ply]: rigid ICP alignment of A onto B and the
// shape distances after it (matching/icp.h, matching/shape_distance.h).
#include <cmath>
#include <cstdio>
#include <iostream>

#include "cli/command.h"
#include "cshapes/support/format.h"
#include "cshapes/mesh/io.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/matching/icp.h"
#include "cshapes/matching/shape_distance.h"

namespace cshapes::cli {
namespace cmd_align {
namespace {

struct AlignArgs {
  std::string source, target, output;
  bool json = false;
  bool no_reflections = false;
  bool one_way = false;
  bool axis_swaps = false;
  double trim = 0;
  double tolerance = IcpOptions{}.relative_tolerance;
} args;

nlohmann::json matrix_json(const Eigen::MatrixXd& M) {
  nlohmann::json rows = nlohmann::json::array();
  for (Index i = 0; i < M.rows(); ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (Index j = 0; j < M.cols(); ++j) row.push_back(M(i, j));
    rows.push_back(row);
  }
  return rows;
}

int run() {
  if (!args.output.empty()) {
    require_mesh_output_path(args.output);
    require_output_not_input(args.output, {args.source, args.target}, "-o");
  }
  // Canonical forms keep their input's faces, which need not pass mesh validation: only points matter here.
  ReadOptions lenient;
  lenient.validate = false;
  // Rows marked invalid (NaN, valid = 0: vertices a canonical form's repair dropped) are left out by the
  // reader: the alignment uses the valid vertices only.
  const MeshFile file_a = read_mesh_file(args.source, lenient), file_b = read_mesh_file(args.target, lenient);
  const Mesh& a = file_a.mesh;
  const Mesh& b = file_b.mesh;
  for (const MeshFile* f : {&file_a, &file_b})
    if (f->invalid_vertices > 0)
      warn((f == &file_a ? args.source : args.target) + ": " + std::to_string(f->invalid_vertices) +
           " invalid vertices (NaN rows, valid = 0) ignored; aligned on the " +
           std::to_string(f->mesh.num_vertices()) + " valid ones");
  // A set ICP cannot take at any size (fewer than 4 points, all on one line or at one point): named by its file.
  for (const MeshFile* f : {&file_a, &file_b})
    if (const std::string refusal = icp_points_refusal(f->mesh.V); !refusal.empty())
      fail(f == &file_a ? args.source : args.target, ": ", refusal);
  IcpOptions options;
  options.allow_reflections = !args.no_reflections;
  options.symmetric = !args.one_way;
  options.try_axis_swaps = args.axis_swaps;
  options.trim_fraction = args.trim;
  options.relative_tolerance = args.tolerance;
  IcpResult r;
  ShapeDistance d = aligned_shape_distance(a.V, b.V, options, &r);
  if (!args.output.empty()) {
    write_mesh(args.output, Mesh{r.transform.apply(a.V), a.F});
    note("wrote " + args.output);
  }
  nlohmann::json j;
  j["source"] = args.source;
  j["target"] = args.target;
  j["transform"] = matrix_json(r.transform.matrix());
  j["rotation"] = matrix_json(r.transform.rotation);
  j["translation"] = {r.transform.translation[0], r.transform.translation[1], r.transform.translation[2]};
  j["reflection"] = r.transform.is_reflection();
  j["hausdorff"] = d.hausdorff;
  j["chamfer"] = d.chamfer;
  j["rmse"] = d.rmse;
  j["directed_source_to_target"] = d.directed_ab;
  j["directed_target_to_source"] = d.directed_ba;
  // The same distances as a share of B's bounding-box diagonal: comparable across shapes of any size.
  const double diagonal = finite_bbox_diagonal(b.V);
  const auto share = [&](double x) { return diagonal > 0 ? 100 * x / diagonal : std::nan(""); };
  j["target_bbox_diagonal"] = diagonal;
  j["hausdorff_percent"] = share(d.hausdorff);
  j["chamfer_percent"] = share(d.chamfer);
  j["rmse_percent"] = share(d.rmse);
  j["icp_rmse"] = r.rmse;
  j["inlier_fraction"] = r.inlier_fraction;
  j["iterations"] = r.iterations;
  j["total_iterations"] = r.total_iterations;
  j["starts"] = r.start_transforms.size();
  j["best_start"] = r.best_start;
  j["converged"] = r.converged;
  if (file_a.invalid_vertices + file_b.invalid_vertices > 0)
    j["invalid_vertices"] = {{"source", file_a.invalid_vertices}, {"target", file_b.invalid_vertices}};
  j["stop_reason"] = r.stop_reason;
  j["seconds"] = r.seconds;
  if (args.json) {
    std::cout << j.dump(2) << std::endl;
    return 0;
  }
  const Eigen::Matrix4d M = r.transform.matrix();
  std::printf("%s -> %s\n", args.source.c_str(), args.target.c_str());
  // Three decimals of R and three significant figures elsewhere, for people; --json has every digit.
  std::printf("  transform x -> R x + t%s (every digit: --json)\n",
              r.transform.is_reflection() ? ", a reflection" : "");
  for (int i = 0; i < 3; ++i)
    std::printf("    %s %7.3f %7.3f %7.3f   %s %10.3g\n", i == 0 ? "R" : " ", M(i, 0), M(i, 1), M(i, 2),
                i == 0 ? "t" : " ", M(i, 3));
  std::printf("  distances after alignment, in A's units (%% of B's bounding-box diagonal, %.3g):\n",
              diagonal);
  for (const auto& [label, value] : {std::pair<const char*, double>{"hausdorff", d.hausdorff},
                                     {"chamfer", d.chamfer},
                                     {"rmse", d.rmse}})
    std::printf("    %-10s %-10.3g (%.3g%%)\n", label, value, share(value));
  // Why ICP stopped, in words with the threshold: "relative change" alone says neither what changed nor by how
  // little.
  const std::string why = r.stop_reason == "relative change"
                              ? "stopped when the RMSE changed by less than " + significant(args.tolerance) +
                                    " of itself"
                              : "stopped: " + r.stop_reason;
  std::printf("  icp: %s on all points (%d in all, %s), %s, %s\n", counted(r.iterations, "iteration").c_str(),
              r.total_iterations, counted(static_cast<long long>(r.start_transforms.size()), "start").c_str(),
              why.c_str(), duration_text(r.seconds).c_str());
  return 0;
}

const bool registered = register_command(
    {{"align"},
     "Rigidly align shape A onto shape B (ICP) and print the transform and the Hausdorff, Chamfer and RMS "
     "distances (in A's units and in % of B's bounding-box diagonal)",
     [](CLI::App& app) {
       app.add_option("A", args.source, "source mesh or point cloud (moved)")->required();
       app.add_option("B", args.target, "target mesh or point cloud")->required();
       app.add_option("-o,--output", args.output, "write A after alignment (with A's faces)");
       app.add_flag("--json", args.json, "print JSON");
       add_declared_flag(app, icp_options::kNoReflections, args.no_reflections);
       add_declared_flag(app, icp_options::kOneWay, args.one_way);
       add_declared_flag(app, icp_options::kAxisSwaps, args.axis_swaps);
       add_declared(app, icp_options::kTrim, args.trim);
       add_declared(app, icp_options::kTolerance, args.tolerance);
     },
     run});

}  // namespace
}  // namespace cmd_align
}  // namespace cshapes::cli
