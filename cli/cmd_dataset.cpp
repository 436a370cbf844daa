// cshapes dataset PATH [--json]: lists what the dataset reader (data/dataset.h) makes of a folder or a
// manifest.csv — the shapes, their classes, poses and noise flags — as every multi-shape command will see
// them.
#include <cstdio>
#include <iostream>

#include "cshapes/data/dataset.h"
#include "cli/command.h"
#include "cshapes/pipeline/shape_failures.h"

namespace cshapes::cli {
namespace cmd_dataset {
namespace {

struct DatasetListArgs {
  std::string path;
  bool json = false, allow_outside = false;
} args;

int run() {
  Dataset d = read_dataset(args.path, args.allow_outside);
  const std::vector<ShapeFailure> left_out = left_out_records(d.left_out);
  for (const std::string& line : same_content_notes(d)) warn(line);
  const std::vector<int> labels = d.labels();
  if (args.json) {
    nlohmann::json entries = nlohmann::json::array();
    for (size_t k = 0; k < d.entries.size(); ++k) {
      const DatasetEntry& e = d.entries[k];
      entries.push_back({{"file", e.path},
                         {"name", e.name},
                         {"class", e.class_name},
                         {"label", labels[k]},
                         {"pose", e.pose},
                         {"noisy", e.noisy}});
    }
    std::cout << nlohmann::json{{"source", d.source},
                                {"classes", d.classes},
                                {"shapes", entries},
                                {"left_out", shape_failures_json(left_out)}}
                     .dump(2)
              << std::endl;
    return exit_code_for(left_out);
  }
  std::printf("%s: %zu shapes, %zu classes\n", d.source.c_str(), d.entries.size(), d.classes.size());
  for (const DatasetEntry& e : d.entries)
    std::printf("  %-12s pose %-3d %s %s\n", e.class_name.c_str(), e.pose, e.noisy ? "noisy" : "     ",
                e.path.c_str());
  // Folder entries that are no shape: said, and the exit code of a partial result (as every command).
  return exit_code_for(left_out);
}

const bool registered =
    register_command({{"dataset"},
                      "List a dataset (folder of meshes, class = name without trailing digits, or "
                      "manifest.csv) as commands read it",
                      [](CLI::App& app) {
                        app.add_option("PATH", args.path, "folder of meshes, or manifest.csv")->required();
                        app.add_flag("--json", args.json, "print JSON");
                        add_allow_outside_flag(app, args.allow_outside);
                      },
                      run});

}  // namespace
}  // namespace cmd_dataset
}  // namespace cshapes::cli
