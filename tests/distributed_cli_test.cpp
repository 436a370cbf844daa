// `mpirun -np R cshapes distmat|experiment paper` (pipeline/distributed.h): the outputs of 2 and 3 ranks are
// byte-identical to one process's, and a killed run resumed with another rank count recomputes nothing it had
// stored. Skipped when the build has no MPI. Ranks are oversubscribed and root is allowed, as CI runs as root
// on small machines; each rank runs one thread.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "cshapes/support/atomic_file.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/distributed.h"
#include "test_support.h"

namespace cshapes {
namespace distributed_cli_test {

namespace fs = std::filesystem;

#define CSHAPES_REQUIRE_MPI()                                                                 \
  do {                                                                                        \
    if (!built_with_mpi() || mpi_launcher().empty()) GTEST_SKIP() << "this build has no MPI"; \
  } while (0)

// Ten generated shapes of 400 vertices (2 classes × 4 poses + 1 noisy each): seconds per run.
std::string small_dataset(const std::string& tag) {
  const std::string dir = test::scratch_dir(tag);
  test::CliResult r = test::run_cli("-q generate dataset --out '" + dir +
                                    "/data' --classes 2 --poses 4 --noisy 1 "
                                    "--vertices 400");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return dir;
}

// Runs the CLI under the MPI launcher with `ranks` processes, or directly when ranks is 0.
test::CliResult run_ranks(int ranks, const std::string& arguments) {
  if (ranks == 0) return test::run_cli("--threads 1 " + arguments);
  const std::string dir = test::scratch_dir("mpirun");
  const std::string out = dir + "/stdout", err = dir + "/stderr";
  const std::string command = "OMPI_MCA_rmaps_base_oversubscribe=1 '" + mpi_launcher() +
                              "' --allow-run-as-root --oversubscribe -np " + std::to_string(ranks) + " '" +
                              CSHAPES_CLI + "' --threads 1 " + arguments + " >'" + out + "' 2>'" + err + "'";
  const int status = std::system(command.c_str());
  test::CliResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_file(out);
  r.err = read_file(err);
  fs::remove_all(dir);
  return r;
}

nlohmann::json run_json(int ranks, const std::string& arguments) {
  test::CliResult r = run_ranks(ranks, arguments + " --json");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return nlohmann::json::parse(r.out.empty() ? "{}" : r.out);
}

TEST(DistributedCli, DistmatOfTwoAndThreeRanksEqualsOneProcess) {
  CSHAPES_REQUIRE_MPI();
  const std::string dir = small_dataset("mpi-distmat");
  std::string reference;
  for (int ranks : {0, 2, 3}) {
    const std::string out = dir + "/r" + std::to_string(ranks);
    fs::create_directories(out);  // an output file's folder must exist
    const nlohmann::json j = run_json(ranks, "-q distmat '" + dir + "/data' -o '" + out + "/d.csv'");
    EXPECT_EQ(j["ranks"], std::max(ranks, 1));
    EXPECT_EQ(j["forms_computed"], 10);  // each form once, over all ranks
    EXPECT_EQ(j["forms_cached"], 0);
    EXPECT_EQ(j["pairs_computed"], 45);
    EXPECT_EQ(j["pairs_cached"], 0);
    const std::string csv = read_file(out + "/d.csv");
    if (ranks == 0)
      reference = csv;
    else
      EXPECT_EQ(csv, reference) << ranks << " ranks";
    // Only rank 0 writes outputs: the output folder holds the CSV, its labels and the cache.
    std::vector<std::string> files;
    for (const auto& e : fs::directory_iterator(out)) files.push_back(e.path().filename().string());
    std::sort(files.begin(), files.end());
    EXPECT_EQ(files, (std::vector<std::string>{".cshapes-cache", "d.csv", "d.labels.csv"}));
  }
}

TEST(DistributedCli, KilledRunResumesWithAnotherRankCountWithoutRecomputing) {
  CSHAPES_REQUIRE_MPI();
  const std::string dir = small_dataset("mpi-resume");
  const std::string data = "'" + dir + "/data'", cache = " --cache '" + dir + "/cache'";
  const nlohmann::json one = run_json(0, "-q distmat " + data + " -o '" + dir + "/one.csv'");
  // Two ranks, each stopped after 5 computed pairs (the hook stores them first): 10 pairs stored.
  test::CliResult killed =
      run_ranks(2, "-q distmat " + data + cache + " -o '" + dir + "/killed.csv' --test-fail-after-pairs 5");
  EXPECT_NE(killed.exit_code, 0);
  EXPECT_NE(killed.err.find("test hook"), std::string::npos) << killed.err;
  EXPECT_FALSE(fs::exists(dir + "/killed.csv"));
  // Resumed with three ranks: the 10 forms and the 10 stored pairs are read, only the other 35 computed.
  const nlohmann::json resumed = run_json(3, "-q distmat " + data + cache + " -o '" + dir + "/resumed.csv'");
  EXPECT_EQ(resumed["forms_computed"], 0);
  EXPECT_EQ(resumed["forms_cached"], 10);
  EXPECT_EQ(resumed["pairs_cached"], 10);
  EXPECT_EQ(resumed["pairs_computed"], 35);
  EXPECT_EQ(read_file(dir + "/resumed.csv"), read_file(dir + "/one.csv"));
  // Once more with two ranks: everything cached.
  const nlohmann::json again = run_json(2, "-q distmat " + data + cache + " -o '" + dir + "/again.csv'");
  EXPECT_EQ(again["pairs_cached"], 45);
  EXPECT_EQ(again["pairs_computed"], 0);
  EXPECT_EQ(read_file(dir + "/again.csv"), read_file(dir + "/one.csv"));
}

TEST(DistributedCli, TwoStageOfTwoRanksEqualsOneProcessAndReportsRecall) {
  CSHAPES_REQUIRE_MPI();
  const std::string dir = small_dataset("mpi-two-stage");
  const std::string data = "'" + dir + "/data'";
  run_json(0, "-q distmat " + data + " -o '" + dir + "/exact.csv'");
  const std::string two_stage = " --two-stage-k 3 --reference '" + dir + "/exact.csv'";
  fs::create_directories(dir + "/a");  // an output file's folder must exist
  fs::create_directories(dir + "/b");
  const nlohmann::json a = run_json(0, "-q distmat " + data + two_stage + " -o '" + dir + "/a/d.csv'");
  const nlohmann::json b = run_json(2, "-q distmat " + data + two_stage + " -o '" + dir + "/b/d.csv'");
  EXPECT_EQ(read_file(dir + "/a/d.csv"), read_file(dir + "/b/d.csv"));
  for (const nlohmann::json& j : {a, b}) {
    EXPECT_EQ(j["two_stage"]["k"], 3);
    const long aligned = j["two_stage"]["pairs_aligned"];
    EXPECT_GE(aligned, 15);  // at least 10 × 3 / 2 distinct pairs
    EXPECT_LT(aligned, 45);
    EXPECT_EQ(j["pairs_computed"], aligned);
    const double recall = j["two_stage"]["recall_at_k"];
    EXPECT_GE(recall, 0.0);
    EXPECT_LE(recall, 1.0);
  }
  EXPECT_EQ(a["two_stage"]["recall_at_k"], b["two_stage"]["recall_at_k"]);
}

TEST(DistributedCli, PaperExperimentOfTwoAndThreeRanksEqualsOneProcess) {
  CSHAPES_REQUIRE_MPI();
  const std::string dir = small_dataset("mpi-paper");
  auto outputs = [](const std::string& out) {
    std::vector<std::string> files;
    for (const auto& e : fs::recursive_directory_iterator(out)) {
      const std::string rel = fs::relative(e.path(), out).string();
      if (e.is_regular_file() && rel.rfind("cache/", 0) != 0) files.push_back(rel);
    }
    std::sort(files.begin(), files.end());
    return files;
  };
  std::vector<std::string> reference_files;
  for (int ranks : {0, 2, 3}) {
    const std::string out = dir + "/out" + std::to_string(ranks);
    const nlohmann::json j = run_json(
        ranks, "-q experiment paper --data '" + dir + "/data' --out '" + out + "' --no-table1 --no-figure-data");
    EXPECT_EQ(j["canonical_forms_cached"], 0);
    EXPECT_EQ(j["pairs_cached"], 0);
    if (ranks == 0) {
      reference_files = outputs(out);
      continue;
    }
    EXPECT_EQ(outputs(out), reference_files);
    // Every output but the report (which holds timings) is the one process's, byte for byte.
    for (const std::string& f : reference_files)
      if (f != "report.md") {
        EXPECT_EQ(read_file(out + "/" + f), read_file(dir + "/out0/" + f)) << f;
      }
    const int methods = static_cast<int>(canonical_form_method_registry().size());  // the default: all
    EXPECT_EQ(j["canonical_forms_computed"], 12 * methods);  // 12 shapes (10 + 2 noise references)
    EXPECT_EQ(j["pairs_computed"], 45 * methods);
  }
}

// experiment retrieval with --resample under 2 ranks: the remeshes, forms and pairs split over the ranks, the
// files those of one process (retrieval.json, report.md and figures aside: they hold timings).
TEST(DistributedCli, RetrievalExperimentOfTwoRanksEqualsOneProcess) {
  CSHAPES_REQUIRE_MPI();
  const std::string dir = small_dataset("mpi-retrieval");
  for (int ranks : {0, 2}) {
    const std::string out = dir + "/out" + std::to_string(ranks);
    test::CliResult r = run_ranks(ranks, "-q experiment retrieval --data '" + dir + "/data' --out '" + out +
                                             "' --methods coulomb,cmds --resample 300 --no-draw");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  for (const char* f : {"classes.cla", "resampled/manifest.csv", "resampled/biped0.off", "coulomb/hausdorff.csv",
                        "coulomb/classes.cla", "cmds/rmse.matrix", "cmds/chamfer.txt", "cmds/hausdorff/queries.csv"})
    EXPECT_EQ(read_file(dir + "/out0/" + f), read_file(dir + "/out2/" + f)) << f;
}

}  // namespace distributed_cli_test
}  // namespace cshapes
