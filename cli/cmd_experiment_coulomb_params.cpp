// cshapes experiment coulomb-params --data DIR --out DIR [--shapes cat0,michael0] [--configs a,b] [--bridges
// K]: the parameter study behind the Coulomb defaults (experiments/coulomb_params.h). Writes
// OUT/coulomb_params.csv and OUT/coulomb_params.md (also printed; --json: the rows as JSON).
#include <iostream>

#include "cli/command.h"
#include "cshapes/canon/coulomb.h"
#include "cshapes/experiments/coulomb_params.h"

namespace cshapes::cli {
namespace cmd_experiment_coulomb_params {
namespace {

struct StudyArgs {
  std::string data, out;
  std::string shapes = "cat0,michael0";
  std::string partners =
      "cat1,michael1";  // another pose of each shape's class, for the pose-invariance column
  std::string configs = "all";
  int bridges = 8;
  int max_iterations = 600;
  bool json = false;
} args;

int run() {
  CoulombParamsOptions o;
  o.data = args.data;
  o.shapes = list_option("--shapes", args.shapes);
  o.partners = list_option("--partners", args.partners);
  if (args.configs != "all") o.configs = list_option("--configs", args.configs);
  o.bridges = args.bridges;
  o.max_iterations = args.max_iterations;
  o.note = note;
  const std::vector<CoulombParamsRow> rows = run_coulomb_params(o);
  const std::string table = write_coulomb_params(args.out, rows);
  if (args.json)
    std::cout << coulomb_params_json(rows).dump(2) << std::endl;
  else
    std::cout << table;
  return 0;
}
const bool registered = register_command(
    {{"experiment", "coulomb-params"},
     "Parameter study of the Coulomb canonization on clean and glued shapes (violation, energy, robustness)",
     [](CLI::App& app) {
       app.add_option("--data", args.data, "folder of OFF shapes (e.g. ../shared/data/tosca5k)")->required();
       app.add_option("--out", args.out, "output folder for coulomb_params.csv/.md")->required();
       app.add_option("--shapes", args.shapes, "comma-separated shape names")->capture_default_str();
       app.add_option("--configs", args.configs, "comma-separated configuration names, or all")
           ->capture_default_str();
       app.add_option("--partners", args.partners,
                      "comma-separated other pose per shape (same class, corres/*.vts), '' for none")
           ->capture_default_str();
       app.add_option("--bridges", args.bridges, "bridge edges glued per shape")->capture_default_str();
       app.add_option("--coulomb-max-iterations", args.max_iterations,
                      "maximum outer iterations of each run (canon's --coulomb-max-iterations)")
           ->capture_default_str()
           ->check(within(coulomb_limits::kMaxIterations));
       app.add_flag("--json", args.json, "print the rows as JSON (full precision) instead of the table");
     },
     run});

}  // namespace
}  // namespace cmd_experiment_coulomb_params
}  // namespace cshapes::cli
