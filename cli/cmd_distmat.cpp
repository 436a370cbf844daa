// cshapes distmat DIR|manifest.csv -o D.csv --method M: canonical forms of a whole dataset (cached), ICP
// between every pair, the paper's distance (maximum distance between matched points) as a named CSV matrix
// and the shapes' classes beside it (D.labels.csv, with the method, distance and data in its comment lines),
// which `cshapes evaluate` reads. Every option of the methods (`cshapes canon`'s groups) applies here too.
// Under `mpirun -np R` the work is split over the ranks (pipeline/dataset_distances.h); rank 0 alone prints
// and writes the outputs. --two-stage-k K aligns only each shape's K descriptor-nearest candidates.
#include <filesystem>
#include <iostream>

#include "cli/command.h"
#include "cshapes/pipeline/outside_methods.h"
#include "cshapes/data/dataset.h"
#include "cshapes/eval/distance_csv.h"
#include "cshapes/matching/shape_distance.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/dataset_distances.h"
#include "cshapes/pipeline/distributed.h"

namespace cshapes::cli {
namespace cmd_distmat {
namespace {

struct DistmatArgs {
  std::string data, output, method = "coulomb", cache, metric = "hausdorff", reference;
  bool strict = false, json = false, allow_outside = false;
  int two_stage_k = 0;
  Index resample = 0;          // --resample N: remesh every shape to about N vertices first
  long fail_after_pairs = -1;  // test hook (hidden option): fail after this many pairs on each rank
} args;

int run() {
  // The command line first: nothing is read or computed before it passes.
  const Communicator& comm = world_communicator();
  const bool root = comm.is_root();
  args.method = method_option(args.method);  // a method from outside is registered under its name here
  check_options_read_by(args.method);        // every rank: each must stop
  require_output_path(args.output, {"csv"});
  std::vector<std::string> inputs = dataset_description_files(args.data);
  inputs.push_back(args.reference);
  require_output_not_input(args.output, inputs, "-o");
  // The classes beside the matrix: `evaluate D.csv` reads them, whatever the file names say.
  const std::string labels = labels_path_for(args.output);
  require_output_not_input(labels, inputs, "-o");
  if (!args.reference.empty() && args.two_stage_k == 0)
    throw UsageError("--reference: applies to the two-stage mode only (--two-stage-k)");
  DatasetDistanceOptions o;
  o.data = args.data;
  o.allow_outside = args.allow_outside;
  o.canon.method = args.method;
  configure_canonical_form(o.canon);                // every method option given on the command line
  o.canon.strict = args.strict;
  o.cache_dir = args.cache.empty()
                    ? (std::filesystem::path(args.output).parent_path() / ".cshapes-cache").string()
                    : args.cache;
  set_outside_method_logs((std::filesystem::path(o.cache_dir) / kMethodLogsFolder).string());
  if (root) {  // one voice: the other ranks work silently
    o.progress = progress_printer();
    o.note = note;
  }
  o.communicator = &comm;
  o.two_stage_k = args.two_stage_k;
  o.pairs.fail_after_computed = args.fail_after_pairs;
  o.reference = args.reference;
  o.resample.vertices = args.resample;
  const DatasetDistances result = dataset_distances(o);
  if (!root) return 0;
  const PairwiseDistanceResult& pd = result.distances;
  const Eigen::MatrixXd& D = args.metric == "hausdorff" ? pd.hausdorff
                             : args.metric == "chamfer" ? pd.chamfer
                                                        : pd.rmse;
  write_distance_csv(args.output, result.names, D);
  // What the matrix is, for the titles of `evaluate`'s figures (eval/distance_csv.h).
  const MatrixDescription description{canonical_form_method_title(args.method),
                                      shape_distance_title(args.metric), dataset_name(args.data)};
  write_labels_csv(labels, result.names, result.classes, description);
  if (args.json) {
    nlohmann::json summary{{"output", args.output},
                           {"labels", labels},
                           {"shapes", result.names.size()},
                           {"method", args.method},
                           {"metric", args.metric},
                           {"pairs", pd.pairs},
                           {"pairs_computed", pd.computed},
                           {"pairs_cached", pd.cached},
                           {"forms_computed", result.forms_computed},
                           {"forms_cached", result.forms_cached},
                           {"ranks", comm.size()},
                           {"seconds", pd.seconds},
                           {"cache", o.cache_dir},
                           {"skipped", result.skipped},
                           {"failures", shape_failures_json(result.failures)}};
    if (args.resample > 0)
      summary["resample"] = {{"vertices", args.resample},
                             {"folder", result.resampling.folder},
                             {"remeshes_computed", result.resampling.computed},
                             {"remeshes_cached", result.resampling.cached}};
    if (result.two_stage.k > 0) {
      summary["two_stage"] = {{"k", result.two_stage.k}, {"pairs_aligned", result.two_stage.pairs_aligned}};
      if (result.two_stage.recall >= 0) {
        summary["two_stage"]["recall_at_k"] = result.two_stage.recall;
        summary["two_stage"]["reference"] = args.reference;
      }
    }
    std::cout << summary.dump(2) << std::endl;
  }
  note("wrote " + args.output + " and " + labels);
  return exit_code_for(result.failures);
}

const bool registered = register_command(
    {{"distmat"},
     "Distance matrix of a dataset: canonical forms (cached), ICP between all pairs, the paper's distance",
     [](CLI::App& app) {
       app.add_option("DATA", args.data, option_help(kDataOption, OptionSkin::Cli))->required();
       add_allow_outside_flag(app, args.allow_outside);
       app.add_option("-o,--output", args.output,
                      "distance matrix CSV (header: shape names); the shapes' classes go beside it, D.csv -> "
                      "D.labels.csv, where evaluate finds them (with the method, distance and data, which "
                      "evaluate's figures name)")
           ->required();
       app.add_option("--method", args.method,
                      "one of " + canonical_form_method_list() +
                          " (options: the groups below, as in canon), or a method from outside: "
                          "NAME=cmd:'COMMAND with {mesh} and {form}' or NAME=forms:DIR")
           ->capture_default_str();
       add_outside_method_options(app);
       add_declared(app, kMetricOption, args.metric)->capture_default_str();
       app.add_option("--cache", args.cache, "cache folder (default: .cshapes-cache beside the output)");
       app.add_flag(
           "--strict", args.strict,
           "stop at the first shape that fails (exit code 1) instead of leaving it out (exit code 3), "
           "with no geodesic fallback; and refuse a mesh the method would have to repair");
       app.footer(kPartialResultHelp);
       app.add_flag("--json", args.json, "print a JSON summary");
       add_declared(app, kTwoStageKOption, args.two_stage_k)
           ->capture_default_str()
           ->check(integer_at_least(0));
       app.add_option("--reference", args.reference,
                      "two-stage: the exact distance CSV of the same data, to report recall@K in --json");
       add_resample_option(app, args.resample);
       // Hidden (no group): simulates a run killed after N computed pairs per rank, for the resume tests.
       app.add_option("--test-fail-after-pairs", args.fail_after_pairs)->group("");
       add_canon_method_options(app);
     },
     run});

}  // namespace
}  // namespace cmd_distmat
}  // namespace cshapes::cli
