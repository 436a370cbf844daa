// cshapes remesh MESH -o OUT --vertices N [--subdivide K] [--json]: isotropic remeshing to N vertices (coarser
// or finer), then K 1-to-4 midpoint subdivisions if asked (a mesh of about 4^K·N vertices on the remesh's
// surface: how the million-vertex benchmark input is made, where remeshing itself would take long),
// reporting the Hausdorff distance to the input and the triangle angles.
#include <cmath>
#include <cstdio>
#include <iostream>

#include "cshapes/support/distance_matrix.h"
#include "cshapes/support/format.h"
#include "cshapes/mesh/io.h"
#include "cshapes/mesh/remesh.h"
#include "cshapes/mesh/subdivide.h"
#include "cli/command.h"

namespace cshapes::cli {
namespace cmd_remesh {
namespace {

struct RemeshArgs {
  std::string input, output;
  long vertices = 0;
  double tolerance = 0.01;
  int iterations = 3;
  int subdivide = 0;
  bool protect_border = false;
  double feature_angle = 60;
  bool json = false;
} args;

int run() {
  // The command line first, the estimate of the memory needed next: nothing is read before both pass.
  if (!(args.tolerance > 0 && args.tolerance < 0.5))
    usage_fail("--vertex-tolerance: expected a number in (0, 0.5), got ", args.tolerance);
  require_mesh_output_path(args.output);
  require_output_not_input(args.output, {args.input}, "-o");
  require_memory(remesh_memory_bytes(args.vertices), "--vertices " + std::to_string(args.vertices));
  const long subdivided = args.vertices << (2 * args.subdivide);  // about: 4^K times the vertices
  if (args.subdivide > 0)
    require_memory(remesh_memory_bytes(subdivided), "--vertices " + std::to_string(args.vertices) +
                                                        " --subdivide " + std::to_string(args.subdivide));
  Mesh mesh = read_mesh(args.input);
  RemeshOptions o;
  o.target_vertices = args.vertices;
  o.tolerance = args.tolerance;
  o.relaxation_iterations = args.iterations;
  o.protect_border = args.protect_border;
  o.feature_angle_deg = args.feature_angle;
  o.progress = progress_printer();
  RemeshResult r = remesh(mesh, o);
  const Index remeshed_vertices = r.mesh.num_vertices();
  for (int k = 0; k < args.subdivide; ++k) r.mesh = midpoint_subdivide(r.mesh);
  write_mesh(args.output, r.mesh);
  MeshInfo before = mesh_info(mesh), after = mesh_info(r.mesh);
  double hausdorff = hausdorff_distance(mesh, r.mesh);
  AngleStats angles_in = angle_stats(mesh), angles_out = angle_stats(r.mesh);
  nlohmann::json j = {{"input", args.input},
                      {"output", args.output},
                      {"target_vertices", args.vertices},
                      {"subdivisions", args.subdivide},
                      {"input_vertices", before.vertices},
                      {"vertices", after.vertices},
                      {"faces", after.faces},
                      {"remeshed_vertices", remeshed_vertices},
                      {"relative_count_error", (static_cast<double>(remeshed_vertices) - args.vertices) /
                                                   static_cast<double>(args.vertices)},
                      {"euler_characteristic_in", before.euler_characteristic},
                      {"euler_characteristic", after.euler_characteristic},
                      {"boundary_edges_in", before.boundary_edges},
                      {"boundary_edges", after.boundary_edges},
                      {"components", after.components},
                      {"hausdorff", hausdorff},
                      {"bbox_diagonal", before.bbox_diagonal},
                      {"hausdorff_over_diagonal", hausdorff / before.bbox_diagonal},
                      {"min_angle_in_deg", angles_in.min_angle},
                      {"min_angle_deg", angles_out.min_angle},
                      {"mean_min_angle_deg", angles_out.mean_min_angle},
                      {"target_edge_length", r.target_edge_length},
                      {"attempts", r.attempts},
                      {"collapsed_edges", r.collapsed_edges},
                      {"feature_angle_deg", r.feature_lines ? r.feature_angle_deg : 0.0}};
  if (args.json) {
    std::cout << j.dump(2) << std::endl;
    return 0;
  }
  std::printf("%s -> %s\n", args.input.c_str(), args.output.c_str());
  // Three significant figures; lengths in the input's units with their share of its bounding-box diagonal
  // (as align and info print them). --json has every digit.
  const double diagonal = before.bbox_diagonal;
  const auto share = [&](double x) { return diagonal > 0 ? 100 * x / diagonal : std::nan(""); };
  std::printf("  vertices        %ld -> %ld (target %ld, %+.3g%%)\n", static_cast<long>(before.vertices),
              static_cast<long>(remeshed_vertices), args.vertices,
              100 * j["relative_count_error"].get<double>());
  if (args.subdivide > 0)
    std::printf("  subdivided      %s -> %ld vertices\n", counted(args.subdivide, "time").c_str(),
                static_cast<long>(after.vertices));
  std::printf("  euler char.     %ld -> %ld, %s, %s\n", before.euler_characteristic,
              after.euler_characteristic, counted(after.components, "component").c_str(),
              counted(after.boundary_edges, "boundary edge").c_str());
  std::printf("  hausdorff       %.3g (%.3g%% of the bbox diagonal %.3g)\n", hausdorff, share(hausdorff),
              diagonal);
  std::printf("  min angle       %.3g deg (input %.3g deg), mean smallest angle %.3g deg\n",
              angles_out.min_angle, angles_in.min_angle, angles_out.mean_min_angle);
  std::printf(
      "  edge length     %.3g (%.3g%% of the bbox diagonal) after %s, %s collapsed\n",
      r.target_edge_length, share(r.target_edge_length), counted(r.attempts, "attempt").c_str(),
      counted(r.collapsed_edges, "edge").c_str());
  if (r.feature_lines)
    std::printf("  feature lines   edges sharper than %.0f deg kept\n", r.feature_angle_deg);
  return 0;
}

const bool registered = register_command(
    {{"remesh"},
     "Remesh to N vertices (isotropic remeshing + edge collapse); reports Hausdorff distance and angles",
     [](CLI::App& app) {
       app.add_option("MESH", args.input, "input mesh")->required();
       app.add_option("-o,--output", args.output, "output mesh (format by extension)")->required();
       app.add_option("--vertices", args.vertices, "vertex count wanted")
           ->required()
           ->check(integer_at_least(4));
       app.add_option("--vertex-tolerance", args.tolerance, "accepted relative deviation from --vertices")
           ->capture_default_str()
           ->check(number_above(0));
       app.add_option("--iterations", args.iterations, "isotropic remeshing iterations per attempt")
           ->capture_default_str()
           ->check(integer_in(1, 1000));
       app.add_option("--feature-angle", args.feature_angle,
                      "dihedral angle (degrees) above which an edge is kept as a feature line; 0: none")
           ->capture_default_str()
           ->check(number_in(0, 180));
       app.add_option("--subdivide", args.subdivide,
                      "then this many 1-to-4 midpoint subdivisions (about 4^K times the vertices, on the "
                      "remesh's surface)")
           ->capture_default_str()
           ->check(integer_in(0, 6));
       app.add_flag("--protect-border", args.protect_border, "keep border edges as they are");
       app.add_flag("--json", args.json, "print the summary as JSON");
     },
     run});

}  // namespace
}  // namespace cmd_remesh
}  // namespace cshapes::cli
