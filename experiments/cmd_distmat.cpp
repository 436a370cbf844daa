// cshapes distmat DIR|manifest.csv -o D.csv --method M: canonical forms of a whole dataset (cached), ICP
// between every pair, the paper's distance (maximum distance between matched points) as a named CSV matrix
// that `cshapes evaluate` reads. Every option of the methods (`cshapes canon`'s groups) applies here too.
#include <filesystem>
#include <iostream>

#include "core/dataset.h"
#include "core/error.h"
#include "pipeline/canonical_forms.h"
#include "eval/distance_csv.h"
#include "eval/pairwise_distances.h"
#include "experiments/command.h"

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
  CanonicalFormOptions co;
  co.method = args.method;
  co.geodesics.method = GeodesicMethod::Heat;  // ours: 9× CGAL's speed, about 1% from exact (README)
  configure_canonical_form(co);                // every method option given on the command line
  Dataset data = read_dataset(args.data);
  co.strict = args.strict;
  const std::string cache_dir =
      args.cache.empty() ? (std::filesystem::path(args.output).parent_path() / ".cshapes-cache").string()
                         : args.cache;
  DiskCache cache((std::filesystem::path(cache_dir) / "forms").string());

  std::vector<Points> forms;
  std::vector<std::string> keys, names, skipped;
  for (size_t i = 0; i < data.entries.size(); ++i) {
    const DatasetEntry& e = data.entries[i];
    // Each shape is repaired for the method (a note says what), or refused with --strict; one that cannot
    // be used at all (unreadable, too few vertices) is skipped with its reason, the others go on.
    co.name = e.path;
    bool cached = false;
    CanonicalForm form;
    Mesh mesh;
    try {
      mesh = read_mesh(e.path);
      form = cached_canonical_form(cache, mesh, co, &cached);
    } catch (const Error& error) {
      if (args.strict) throw;
      note(std::string("skipped: ") + error.what());
      skipped.push_back(e.path);
      continue;
    }
    if (!form.repair_text.empty()) note(form.repair_text);
    forms.push_back(form.X);
    keys.push_back(canonical_form_cache_key(mesh, co));
    names.push_back(e.name);
    note("[" + std::to_string(i + 1) + "/" + std::to_string(data.entries.size()) + "] " + e.name +
         (cached ? " (cached)" : ""));
  }
  CSHAPES_REQUIRE(forms.size() >= 2, args.data, ": ", forms.size(), " usable shapes (", skipped.size(),
                  " skipped), a distance matrix needs at least 2");
  PairwiseDistanceOptions po;
  po.cache_dir = (std::filesystem::path(cache_dir) / "pairs").string();
  po.progress = progress_printer();
  PairwiseDistanceResult pd = pairwise_distances(forms, keys, po);
  const Eigen::MatrixXd& D = args.metric == "hausdorff" ? pd.hausdorff
                             : args.metric == "chamfer" ? pd.chamfer
                                                        : pd.rmse;
  write_distance_csv(args.output, names, D);
  if (args.json)
    std::cout << nlohmann::json{{"output", args.output},   {"shapes", names.size()},       {"method", args.method},
                                {"metric", args.metric},   {"pairs_computed", pd.computed}, {"pairs_cached", pd.cached},
                                {"cache", cache_dir},      {"skipped", skipped}}
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
