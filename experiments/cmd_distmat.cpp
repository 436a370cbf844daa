// cshapes distmat DIR|manifest.csv -o D.csv --method M: canonical forms of a whole dataset (cached), ICP
// between every pair, the paper's distance (maximum distance between matched points) as a named CSV matrix
// that `cshapes evaluate` reads. Every option of the methods (`cshapes canon`'s groups) applies here too.
#include <filesystem>
#include <iostream>

#include "eval/distance_csv.h"
#include "experiments/command.h"
#include "pipeline/dataset_distances.h"

namespace cshapes::cli {
namespace {

struct DistmatArgs {
  std::string data, output, method = "coulomb", cache, metric = "hausdorff";
  bool largest_component = false, strict = false, json = false;
} args;

int run() {
  // The command line first: nothing is read or computed before it passes.
  check_canon_method_options({args.method}, false);  // the same options serve a loop over methods: warn
  require_output_path(args.output, {"csv"});
  DatasetDistanceOptions o;
  o.data = args.data;
  o.canon.method = args.method;
  o.canon.geodesics.method = GeodesicMethod::Heat;  // ours: 9× CGAL's speed, about 1% from exact (README)
  configure_canonical_form(o.canon);                // every method option given on the command line
  o.canon.strict = args.strict;
  o.cache_dir = args.cache.empty()
                    ? (std::filesystem::path(args.output).parent_path() / ".cshapes-cache").string()
                    : args.cache;
  o.progress = progress_printer();
  o.note = note;
  const DatasetDistances result = dataset_distances(o);
  const PairwiseDistanceResult& pd = result.distances;
  const Eigen::MatrixXd& D = args.metric == "hausdorff" ? pd.hausdorff
                             : args.metric == "chamfer" ? pd.chamfer
                                                        : pd.rmse;
  write_distance_csv(args.output, result.names, D);
  if (args.json)
    std::cout << nlohmann::json{{"output", args.output},         {"shapes", result.names.size()},
                                {"method", args.method},         {"metric", args.metric},
                                {"pairs_computed", pd.computed}, {"pairs_cached", pd.cached},
                                {"cache", o.cache_dir},          {"skipped", result.skipped}}
                     .dump(2)
              << std::endl;
  note("wrote " + args.output);
  return 0;
}

const bool registered = register_command(
    {{"distmat"},
     "Distance matrix of a dataset: canonical forms (cached), ICP between all pairs, the paper's distance",
     [](CLI::App& app) {
       app.add_option("DATA", args.data,
                      "folder of meshes (class = name without trailing digits) or manifest.csv")
           ->required();
       app.add_option("-o,--output", args.output, "distance matrix CSV (header: shape names)")->required();
       app.add_option("--method", args.method,
                      "coulomb, cmds or smacof (options: the groups below, as in canon)")
           ->capture_default_str()
           ->check(one_of({"coulomb", "cmds", "smacof"}));
       app.add_option("--metric", args.metric, "hausdorff (the paper's), chamfer or rmse")
           ->capture_default_str()
           ->check(one_of({"hausdorff", "chamfer", "rmse"}));
       app.add_option("--cache", args.cache, "cache folder (default: .cshapes-cache beside the output)");
       app.add_flag("--largest-component", args.largest_component,
                    "keep each input's largest component (the default repair; kept for old scripts)");
       app.add_flag("--strict", args.strict,
                    "refuse a mesh the method would have to repair instead of repairing it");
       app.add_flag("--json", args.json, "print a JSON summary");
       add_canon_method_options(app);
     },
     run});

}  // namespace
}  // namespace cshapes::cli
