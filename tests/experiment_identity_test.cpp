// Defaults in the library: `cshapes experiment paper` and paper_experiment called from C++ with the
// library's default options write the same files, byte for byte, on a small generated dataset (the Python
// module's side of the same check is tests/python/test_experiment_identity.py). Before the experiments'
// defaults moved into the library, the CLI chose heat geodesics and C++ got fast marching: the MDS forms,
// distances and metrics differed.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "cshapes/experiments/paper_experiment.h"
#include "test_support.h"

namespace cshapes {
namespace experiment_identity_test {

namespace fs = std::filesystem;

// Every file under root but report.md (it states the run's time) and the caches, by relative path, with the
// output folder's own path (which labels.csv names for the shapes glued here) written as OUT.
std::map<std::string, std::string> outputs(const std::string& root) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (!entry.is_regular_file()) continue;
    const std::string relative = fs::relative(entry.path(), root).string();
    if (relative == "report.md" || relative.rfind("cache/", 0) == 0) continue;
    std::ifstream in(entry.path(), std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    std::string content = text.str();
    for (size_t at = content.find(root); at != std::string::npos; at = content.find(root, at))
      content.replace(at, root.size(), "OUT");
    files[relative] = content;
  }
  return files;
}

TEST(ExperimentDefaults, CliAndCppRunsOfThePaperExperimentWriteTheSameFiles) {
  const std::string dir = test::scratch_dir("paper-identity");
  const std::string manifest = test::generated_dataset(dir, 2, 3, 400);
  const test::CliResult cli = test::run_cli("-q experiment paper --data '" + manifest + "' --out '" + dir +
                                            "/cli' --no-table1 --no-figure-data");
  ASSERT_EQ(cli.exit_code, 0) << cli.err;

  PaperExperimentOptions o;  // the library's defaults, as a C++ caller gets them
  o.data = manifest;
  o.out = dir + "/cpp";
  o.table1 = false;
  o.figures = false;
  paper_experiment(o);

  const std::map<std::string, std::string> a = outputs(dir + "/cli"), b = outputs(dir + "/cpp");
  ASSERT_GT(a.size(), 10u);
  EXPECT_TRUE(a.count("metrics.json") && a.count("distances/smacof.csv") && a.count("canon/cmds/biped0.ply"));
  for (const auto& [file, content] : a) {
    ASSERT_TRUE(b.count(file)) << file << " is written by the CLI only";
    EXPECT_TRUE(content == b.at(file)) << file << " differs between the CLI and C++";
  }
  EXPECT_EQ(a.size(), b.size());
}

}  // namespace experiment_identity_test
}  // namespace cshapes
