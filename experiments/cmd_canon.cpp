// cshapes canon MESH -o OUT --method M: a canonical form by any registered method (see command.h).
#include <iostream>
#include <sstream>

#include "core/error.h"
#include "core/io.h"
#include "experiments/command.h"

namespace cshapes::cli {
namespace {

struct CanonArgs {
  std::string input, output, history, method = "coulomb";
  bool largest_component = false;
  bool json = false;
} args;

int run() {
  const CanonMethod* method = nullptr;
  std::string known;
  for (const CanonMethod& m : canon_methods()) {
    if (m.name == args.method) method = &m;
    known += (known.empty() ? "" : ", ") + m.name;
  }
  if (!method) usage_fail("--method: expected one of ", known, ", got '", args.method, "'");
  // Everything the command line decides is checked before any work.
  check_canon_method_options({method->name}, true);
  if (method->validate) method->validate();
  require_mesh_output_path(args.output);
  if (!args.history.empty()) require_output_path(args.history, {"csv"});

  CanonJob job;
  job.input_path = args.input;
  job.history_path = args.history;
  Mesh mesh = read_mesh(args.input);
  if (mesh.is_point_cloud()) {
    // No faces: the method builds its own neighbourhood graph (and refuses a disconnected one).
    job.vertex_map.resize(mesh.num_vertices());
    for (Index i = 0; i < mesh.num_vertices(); ++i) job.vertex_map[i] = static_cast<int>(i);
    job.mesh = std::move(mesh);
  } else {
    std::string dropped;
    Submesh sub = require_connected(mesh, args.input, args.largest_component, &dropped);
    if (!dropped.empty()) note(dropped);
    job.mesh = std::move(sub.mesh);
    job.vertex_map = std::move(sub.vertex_map);
  }

  CanonOutput out = method->run(job);
  CSHAPES_REQUIRE(out.X.rows() == job.mesh.num_vertices() && out.X.allFinite(), "method ", method->name,
                  " returned an invalid canonical form (wrong size or non-finite coordinates)");
  Mesh result{out.X, job.mesh.F};
  WriteOptions wo;
  wo.scalars = out.scalars;
  write_mesh(args.output, result, wo);
  if (!args.history.empty() && !out.history_columns.empty())
    write_csv(args.history, out.history_columns, out.history_rows);
  out.summary["method"] = method->name;
  out.summary["input"] = args.input;
  out.summary["output"] = args.output;
  if (args.json) std::cout << out.summary.dump(2) << std::endl;
  note("wrote " + args.output);
  return 0;
}

const bool registered = register_command(
    {{"canon"},
     "Compute a canonical form (Coulomb shape, classical MDS or SMACOF), written with the input's faces "
     "and vertex order",
     [](CLI::App& app) {
       app.add_option("MESH", args.input, "input mesh")->required();
       app.add_option("-o,--output", args.output, "output mesh (.ply keeps per-vertex flags such as 'torn')")
           ->required();
       std::string names;
       for (const CanonMethod& m : canon_methods()) names += "\n  " + m.name + ": " + m.summary;
       app.add_option("--method", args.method, "canonization method:" + names)->capture_default_str();
       app.add_option("--history", args.history, "write the per-iteration history as CSV");
       app.add_flag("--largest-component", args.largest_component,
                    "keep the largest connected component instead of refusing a disconnected mesh");
       app.add_flag("--json", args.json, "print a JSON summary on stdout");
       add_canon_method_options(app);
     },
     run});

}  // namespace
}  // namespace cshapes::cli
