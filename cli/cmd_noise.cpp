// cshapes noise MESH -o OUT --glue K: topological noise by gluing almost-touching spots (see
// data/topological_noise.h); writes the glued vertex pairs as JSON for red marking in renderings.
#include <algorithm>
#include <cstdio>
#include <iostream>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/support/format.h"
#include "cshapes/mesh/io.h"
#include "cshapes/data/topological_noise.h"
#include "cli/command.h"
#include "cshapes/pipeline/mesh_report.h"

namespace cshapes::cli {
namespace cmd_noise {
namespace {

struct NoiseArgs {
  std::string input, output, pairs_json, geodesic_method = "graph";
  int glue = 1;
  int relax = 0;
  std::uint64_t seed = 0;
  double max_gap = 0, gap_edges = 6, min_ratio = 5, min_fraction = 0.1, separation = 0.15;
  bool json = false;
} args;

int run() {
  require_mesh_output_path(args.output);
  if (!args.pairs_json.empty()) require_output_path(args.pairs_json, {"json"});
  require_output_not_input(args.output, {args.input}, "-o");
  require_output_not_input(args.pairs_json, {args.input}, "--pairs-json");
  Mesh mesh = read_mesh(args.input);
  TopologicalNoiseOptions o;
  o.glue_count = args.glue;
  o.seed = args.seed;
  o.max_gap = args.max_gap;
  o.gap_edge_lengths = args.gap_edges;
  o.min_ratio = args.min_ratio;
  o.min_geodesic_fraction = args.min_fraction;
  o.min_separation_fraction = args.separation;
  o.geodesic.method = parse_geodesic_method(args.geodesic_method);
  o.relax_steps = args.relax;
  TopologicalNoiseResult r = glue_topological_noise(mesh, o);
  if (r.relax_steps_used > 0)
    note("relaxed " + counted(r.relax_steps_used, "time") + ": gap " + significant(r.max_gap) + " (" +
         significant(r.max_gap / r.mean_edge_length) + " × the mean edge length), min ratio " +
         significant(r.min_ratio));
  write_mesh(args.output, r.mesh);
  nlohmann::json j = topological_noise_json(r);
  j["input"] = args.input;
  j["output"] = args.output;
  j["min_ratio"] = r.min_ratio;
  if (!args.pairs_json.empty())
    write_file_atomically(args.pairs_json, [&](std::ostream& out) { out << j.dump(2) << '\n'; });
  MeshInfo before = mesh_info(mesh), after = mesh_info(r.mesh);
  if (args.json) {
    j["euler_characteristic_in"] = before.euler_characteristic;
    j["euler_characteristic"] = after.euler_characteristic;
    j["components"] = after.components;
    j["genus"] = after.genus;
    j["candidates"] = r.candidates;
    j["geodesic_checks"] = r.geodesic_checks;
    std::cout << j.dump(2) << std::endl;
    return 0;
  }
  std::printf("%s -> %s: %s, euler characteristic %ld -> %ld, genus %ld -> %ld, %s\n", args.input.c_str(),
              args.output.c_str(), counted(static_cast<long long>(r.pairs.size()), "glue").c_str(),
              before.euler_characteristic, after.euler_characteristic, before.genus, after.genus,
              counted(after.components, "component").c_str());
  // Three significant figures; lengths in the mesh's units with a reference (× the mean edge length, % of the
  // geodesic diameter). --json has every digit.
  std::printf(
      "  max gap %.3g (%.3g × the mean edge length %.3g), min ratio %.3g, geodesic diameter %.3g, %ld "
      "candidate pairs, %d geodesic checks\n",
      r.max_gap, r.max_gap / r.mean_edge_length, r.mean_edge_length, o.min_ratio, r.geodesic_diameter,
      static_cast<long>(r.candidates), r.geodesic_checks);
  for (const GluedPair& p : r.pairs)
    std::printf(
        "  glued %d - %d: euclidean %.3g (%.3g × the mean edge length), geodesic %.3g (ratio %.3g, %.3g%% of "
        "the diameter)\n",
        p.a, p.b, p.euclidean, p.euclidean / r.mean_edge_length, p.geodesic, p.geodesic / p.euclidean,
        100 * p.geodesic / r.geodesic_diameter);
  return 0;
}

const bool registered = register_command(
    {{"noise"},
     "Topological noise: glue K almost-touching spots (small Euclidean, large geodesic distance) by short "
     "tubes",
     [](CLI::App& app) {
       app.add_option("MESH", args.input, "input mesh (one component, manifold)")->required();
       app.add_option("-o,--output", args.output, "output mesh (same vertices, K handles more)")->required();
       add_declared(app, noise_options::kGlue, args.glue)->capture_default_str();
       add_declared(app, noise_options::kSeed, args.seed)->capture_default_str();
       add_declared(app, noise_options::kMaxGap, args.max_gap);
       add_declared(app, noise_options::kGapEdges, args.gap_edges)->capture_default_str();
       add_declared(app, noise_options::kMinRatio, args.min_ratio)->capture_default_str();
       add_declared(app, noise_options::kMinFraction, args.min_fraction)->capture_default_str();
       add_declared(app, noise_options::kSeparation, args.separation)->capture_default_str();
       add_declared(app, noise_options::kRelax, args.relax)->capture_default_str();
       add_declared(app, noise_options::kGeodesics, args.geodesic_method)->capture_default_str();
       app.add_option("--pairs-json", args.pairs_json, "write the glued vertex pairs and tube rims as JSON");
       app.add_flag("--json", args.json, "print the summary as JSON");
     },
     run});

}  // namespace
}  // namespace cmd_noise
}  // namespace cshapes::cli
