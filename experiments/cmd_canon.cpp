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
  bool strict = false;
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
  const Mesh input = read_mesh(args.input);
  // The method's requirements (pipeline/canonical_forms.h), repaired unless --strict; a point cloud (no faces)
  // passes unchanged: the method builds its own neighbourhood graph (and refuses a disconnected one).
  CanonicalFormOptions requirements;
  requirements.method = method->name;
  requirements.name = args.input;
  requirements.strict = args.strict;
  RepairedMesh repaired = repair_for_canonical_form(input, requirements);
  const bool dropped_some = valid_input_vertices(repaired.vertex_map, input.num_vertices()).minCoeff() == 0;
  CSHAPES_REQUIRE(!dropped_some || file_extension(args.output) == "ply", args.output, ": the repair dropped ",
                  "vertices (", repaired.text, "); write .ply, which keeps the input's vertex count with NaN rows ",
                  "and a per-vertex 'valid' flag, or pass --strict to refuse the mesh");
  if (repaired.changed()) note(repaired.text);
  job.mesh = std::move(repaired.mesh);
  job.vertex_map = repaired.vertex_map;

  CanonOutput out = method->run(job);
  CSHAPES_REQUIRE(out.X.rows() == job.mesh.num_vertices() && out.X.allFinite(), "method ", method->name,
                  " returned an invalid canonical form (wrong size or non-finite coordinates)");
  // Back to the input's vertex count and order, with the input's faces: dropped vertices are NaN rows with
  // valid = 0 (PLY); a split vertex takes its first copy's position.
  Mesh result{to_input_vertices(out.X, job.vertex_map, input.num_vertices()), input.F};
  WriteOptions wo;
  for (const VertexScalar& s : out.scalars)
    wo.scalars.push_back({s.name, to_input_vertices(s.values, job.vertex_map, input.num_vertices(), 0.0)});
  if (dropped_some) wo.scalars.push_back({"valid", valid_input_vertices(job.vertex_map, input.num_vertices())});
  write_mesh(args.output, result, wo);
  nlohmann::json repairs = nlohmann::json::array();
  for (const RepairAction& a : repaired.actions) repairs.push_back({{"what", a.what}, {"count", a.count}});
  out.summary["repairs"] = repairs;
  out.summary["repair"] = repaired.text;
  out.summary["input_vertices"] = input.num_vertices();
  out.summary["kept_input_vertices"] =
      static_cast<Index>(valid_input_vertices(job.vertex_map, input.num_vertices()).sum());
  out.summary["repaired_vertices"] = job.mesh.num_vertices();
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
                    "keep the largest connected component (the default repair; kept for old scripts)");
       app.add_flag("--strict", args.strict,
                    "refuse a mesh the method would have to repair (non-manifold for MDS, several components, "
                    "duplicate faces, ...) instead of repairing it");
       app.add_flag("--json", args.json, "print a JSON summary on stdout");
       add_canon_method_options(app);
     },
     run});

}  // namespace
}  // namespace cshapes::cli
