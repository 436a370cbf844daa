// cshapes geodesics MESH -o D.bin --method heat|heat-cgal|fmm|exact|graph: all-pairs geodesic distances
// (binary format in support/distance_matrix.h), or with --source i one row as CSV (-o NAME.csv or stdout).
#include <climits>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cli/command.h"
#include "cshapes/support/error.h"
#include "cshapes/support/timing.h"
#include "cshapes/pipeline/mesh_geodesics.h"

namespace cshapes::cli {
namespace cmd_geodesics {
namespace {

struct GeodesicsArgs {
  std::string input, output, method = "heat", heat_mode = "idt";
  int source = -1;
  bool csv = false;
  bool strict = false;
  bool json = false;
  CLI::Option* heat_mode_option = nullptr;
} args;

int run() {
  GeodesicOptions options;
  options.method = parse_geodesic_method(args.method);
  options.heat_mode = parse_cgal_heat_mode(args.heat_mode);
  // The command line is checked before any work.
  const bool heat = options.method == GeodesicMethod::Heat || options.method == GeodesicMethod::HeatCgal;
  if (args.heat_mode_option->count() > 0 && !heat)
    usage_fail("--heat-mode applies to --method heat or heat-cgal only");
  // The output's form follows -o: NAME.csv (or stdout) one row of --source, NAME.bin all pairs.
  const bool to_stdout = args.output.empty() || args.output == "-";
  const std::string extension = to_stdout ? "" : std::filesystem::path(args.output).extension().string();
  if (extension == ".csv" || to_stdout) args.csv = true;
  if (args.csv && args.source < 0)
    usage_fail(to_stdout ? std::string("all-pairs distances need -o NAME.bin") : "-o " + args.output,
               ": one row of distances as CSV needs --source i (all pairs are written to -o NAME.bin)");
  if (args.source >= 0 && extension == ".bin")
    usage_fail(
        "--source i writes one row as CSV: give -o NAME.csv (or no -o for stdout); -o D.bin takes all "
        "pairs");
  if (!to_stdout) {
    require_output_path(args.output, {args.csv ? "csv" : "bin"});
    require_output_not_input(args.output, {args.input}, "-o");
  }
  options.progress = progress_printer();
  Mesh input = read_mesh(args.input);
  // Repaired for geodesics unless --strict; the output is given at the input's vertices
  // (pipeline/mesh_geodesics.h).
  MeshGeodesicsOptions mo;
  mo.geodesics = options;
  mo.strict = args.strict;
  mo.name = args.input;
  const MeshGeodesics prepared = prepare_mesh_geodesics(input, mo);
  const RepairedMesh& sub = prepared.repaired;
  if (sub.changed())
    note(sub.text +
         "; distances are given at the input's vertices (NaN where a vertex was dropped, the "
         "nearest copy where one was split)");
  const WallClock::time_point start = WallClock::now();
  nlohmann::json summary = {{"input", args.input},
                            {"vertices", input.num_vertices()},
                            {"repaired_vertices", sub.mesh.num_vertices()},
                            {"method", to_string(options.method)},
                            {"output", args.output.empty() ? "-" : args.output}};
  if (options.method == GeodesicMethod::Heat || options.method == GeodesicMethod::HeatCgal)
    summary["heat_mode"] = to_string(options.heat_mode);
  if (!prepared.warning.empty()) {
    warn(prepared.warning);
    summary["warning"] = prepared.warning;
  }

  if (args.source >= 0) {
    const Eigen::VectorXd d = geodesic_rows(input, prepared, {args.source}, mo).row(0).transpose();
    std::vector<std::vector<double>> rows;
    rows.reserve(d.size());
    for (Index v = 0; v < d.size(); ++v) rows.push_back({static_cast<double>(v), d[v]});
    if (args.output.empty() || args.output == "-") {
      std::printf("vertex,distance\n");
      for (const auto& row : rows) std::printf("%d,%.10g\n", static_cast<int>(row[0]), row[1]);
    } else {
      write_csv(args.output, {"vertex", "distance"}, rows);
    }
    summary["source"] = args.source;
  } else {
    const DistanceMatrix D = geodesic_all_pairs(input, prepared, mo);
    summary["max_distance"] = D.array().isNaN().select(0.0f, D.array()).maxCoeff();  // NaN: dropped
    write_distance_matrix(args.output, D);
  }
  summary["seconds"] = seconds_since(start);
  if (args.json) std::cout << summary.dump(2) << std::endl;
  if (!args.output.empty() && args.output != "-") note("wrote " + args.output);
  return 0;
}

const bool registered = register_command(
    {{"geodesics"},
     "Geodesic distances on a mesh: all pairs as a binary n×n float32 matrix, or one row as CSV",
     [](CLI::App& app) {
       app.add_option("MESH", args.input, "input triangle mesh")->required();
       app.add_option("-o,--output", args.output,
                      "output: D.bin (CSHDIST1 header, n, then n×n float32 row-major), or CSV with --source; "
                      "'-' or omitted with --source: stdout");
       add_declared(app, geodesic_options::kMethod, args.method)->capture_default_str();
       args.heat_mode_option =
           add_declared(app, geodesic_options::kHeatMode, args.heat_mode)->capture_default_str();
       app.add_option(
              "--source", args.source,
              "one source vertex (0-based, input numbering): one row of distances as CSV, to -o NAME.csv "
              "or stdout; none (the default): all pairs")
           ->default_str("none")
           ->check(integer_in(0, INT_MAX));
       app.add_flag("--csv", args.csv,
                    "CSV (vertex,distance) for the row of --source; implied by -o NAME.csv or no -o");
       add_declared_flag(app, kStrictGeodesicsOption, args.strict);
       app.add_flag("--json", args.json, "print a JSON summary on stdout");
     },
     run});

}  // namespace
}  // namespace cmd_geodesics
}  // namespace cshapes::cli
