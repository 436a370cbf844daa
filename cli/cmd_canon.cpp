// cshapes canon MESH -o OUT --method M: a canonical form by any registered method (see command.h), computed
// by the drivers library (pipeline/canonical_forms.h) as `distmat` and `experiment paper` compute theirs.
#include <iostream>
#include <nlohmann/json.hpp>

#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cli/command.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/canonical_forms.h"
#include "cshapes/pipeline/mesh_report.h"

namespace cshapes::cli {
namespace cmd_canon {
namespace {

struct CanonArgs {
  std::string input, output, history, method = "coulomb";
  bool strict = false;
  bool json = false;
} args;

int run() {
  // Everything the command line decides is checked before any work.
  check_options_read_by(args.method, !args.history.empty());  // first: it names the options' own readers
  CanonicalFormOptions options;
  options.method = args.method;
  configure_canonical_form(options, true);
  options.name = args.input;
  options.strict = args.strict;
  options.progress = progress_printer();
  options.note = note;
  require_mesh_output_path(args.output);
  if (!args.history.empty()) require_output_path(args.history, {"csv"});
  const std::vector<std::string> inputs{args.input, options.distances_file};
  require_output_not_input(args.output, inputs, "-o");
  require_output_not_input(args.history, inputs, "--history");

  // Rows a canonical form marks invalid (NaN, valid = 0) are not read: said, as the form has fewer rows.
  const MeshFile file = read_mesh_file(args.input);
  warn_invalid_vertices_dropped(file, args.input);
  const Mesh& input = file.mesh;
  if (option_given("--knn") && input.num_faces() > 0)
    usage_fail("--knn applies to point clouds (no faces) only; ", args.input, " has ", input.num_faces(),
               " faces");
  // The method's requirements, repaired unless --strict; a point cloud (no faces) passes unchanged: the
  // method builds its own neighbourhood graph (and refuses a disconnected one).
  const RepairedMesh repaired = repair_for_canonical_form(input, options);
  const bool dropped_some = valid_input_vertices(repaired.vertex_map, input.num_vertices()).minCoeff() == 0;
  CSHAPES_REQUIRE(!dropped_some || file_extension(args.output) == "ply", args.output, ": the repair dropped ",
                  "vertices (", repaired.text,
                  "); write .ply, which keeps the input's vertex count with NaN rows ",
                  "and a per-vertex 'valid' flag, or pass --strict to refuse the mesh");
  if (repaired.changed()) note(repaired.text);

  const CanonicalForm form = canonical_form(input, options);
  // The input's vertex count and order, with the input's faces: dropped vertices are NaN rows with
  // valid = 0 (PLY); a split vertex takes its first copy's position.
  WriteOptions wo;
  if (form.torn.size()) wo.scalars.push_back({"torn", form.torn});
  if (dropped_some) wo.scalars.push_back({"valid", form.valid});
  wo.comments.push_back("method " + args.method);  // what made it: `cshapes show` titles the form by it (PLY)
  write_mesh(args.output, Mesh{form.X, input.F}, wo);
  if (!args.history.empty() && !form.history_columns.empty())
    write_csv(args.history, form.history_columns, form.history_rows);

  nlohmann::json summary = canonical_form_summary(form, args.method);
  summary["repaired_vertices"] = repaired.mesh.num_vertices();
  summary["input"] = args.input;
  summary["output"] = args.output;
  if (args.json) std::cout << summary.dump(2) << std::endl;
  note("wrote " + args.output);
  return 0;
}

const bool registered = register_command(
    {{"canon"},
     "Compute a canonical form (" + method_titles(" or ") + "), written with the input's faces and vertex order",
     [](CLI::App& app) {
       app.add_option("MESH", args.input, "input mesh")->required();
       app.add_option("-o,--output", args.output, "output mesh (.ply keeps per-vertex flags such as 'torn')")
           ->required();
       std::string names;
       std::vector<std::string> known;
       for (const CanonicalFormMethod& m : canonical_form_method_registry()) {
         names += "\n  " + m.name + ": " + m.summary;
         known.push_back(m.name);
       }
       app.add_option("--method", args.method, "canonization method:" + names)
           ->capture_default_str()
           ->check(one_of(known));
       app.add_option("--history", args.history, "write the per-iteration history as CSV");
       add_declared_flag(app, kStrictFormOption, args.strict);
       app.add_flag("--json", args.json, "print a JSON summary on stdout");
       add_canon_method_options(app);
     },
     run});

}  // namespace
}  // namespace cmd_canon
}  // namespace cshapes::cli
