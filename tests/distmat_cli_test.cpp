// `cshapes distmat` and `cshapes experiment paper` take every option of the canonization methods, with
// `cshapes canon`'s names: the options reach the computation (they change the cache key and the result), and
// options only `canon` can honour are refused by name.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "cshapes/data/synthetic.h"
#include "cshapes/eval/distance_csv.h"
#include "cshapes/mesh/io.h"
#include "cshapes/support/atomic_file.h"
#include "test_support.h"

namespace cshapes {
namespace distmat_cli_test {

// Two spheres and two tori of different sizes: a dataset small enough for a CLI test.
std::string tiny_dataset() {
  const std::string dir = test::scratch_dir("distmat_cli");
  write_mesh(dir + "/data/sphere0.off", icosphere(2, 1.0));
  write_mesh(dir + "/data/sphere1.off", icosphere(2, 1.2));
  write_mesh(dir + "/data/torus0.off", torus(16, 8, 1.0, 0.3));
  write_mesh(dir + "/data/torus1.off", torus(16, 8, 1.1, 0.35));
  return dir;
}

nlohmann::json run_json(const std::string& arguments) {
  test::CliResult r = test::run_cli(arguments + " --json");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return nlohmann::json::parse(r.out.empty() ? "{}" : r.out);
}

TEST(DistmatCli, MethodOptionsReachTheComputation) {
  const std::string dir = tiny_dataset();
  const std::string base = "-q distmat '" + dir + "/data' --cache '" + dir +
                           "/cache' --method coulomb "
                           "--coulomb-max-iterations 40 --tear-fraction 0";
  nlohmann::json a = run_json(base + " -o '" + dir + "/a.csv'");
  EXPECT_EQ(a["pairs_computed"], 6);
  // The same options again: everything cached.
  nlohmann::json same = run_json(base + " -o '" + dir + "/same.csv'");
  EXPECT_EQ(same["pairs_computed"], 0);
  EXPECT_EQ(same["pairs_cached"], 6);
  // A different k: new canonical forms, so new pairs, and a different matrix.
  nlohmann::json b = run_json(base + " --projection-steps 1 -o '" + dir + "/b.csv'");
  EXPECT_EQ(b["pairs_computed"], 6);

  const NamedDistances da = read_distance_csv(dir + "/a.csv");
  const NamedDistances ds = read_distance_csv(dir + "/same.csv");
  const NamedDistances db = read_distance_csv(dir + "/b.csv");
  ASSERT_EQ(da.names.size(), 4u);
  EXPECT_EQ((da.D - ds.D).norm(), 0.0);
  EXPECT_GT((da.D - db.D).norm(), 1e-6 * da.D.norm());
}

TEST(DistmatCli, MdsOptionsAndCanonOnlyOptions) {
  const std::string dir = tiny_dataset();
  const std::string base = "-q distmat '" + dir + "/data' --cache '" + dir + "/cache' ";
  nlohmann::json plain = run_json(base + "--method smacof --geodesics graph -o '" + dir + "/p.csv'");
  EXPECT_EQ(plain["pairs_computed"], 6);
  nlohmann::json accelerated =
      run_json(base + "--method smacof --geodesics graph --accelerate rre -o '" + dir + "/r.csv'");
  EXPECT_EQ(accelerated["pairs_computed"], 6);  // another option, other forms

  // What only `canon` can do is refused in one line naming the option, with no output file.
  for (const std::string& extra : {std::string("--distances x.bin"), std::string("--weights area"),
                                   std::string("--init mesh"), std::string("--scheme nonsense")}) {
    const std::string out = dir + "/refused.csv";
    test::CliResult r = test::run_cli(base + "--method smacof " + extra + " -o '" + out + "'");
    EXPECT_NE(r.exit_code, 0) << extra;
    const std::string option = extra.substr(0, extra.find(' ')), value = extra.substr(extra.find(' ') + 1);
    EXPECT_TRUE(r.err.find(option) != std::string::npos || r.err.find("'" + value + "'") != std::string::npos)
        << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(std::filesystem::exists(out)) << extra;
  }
}

TEST(DistmatCli, ACacheOnAFullDiskStopsWithThePathAndTheReason) {
  // Issue 22: on a nearly full disk, shapes were "skipped" and a smaller matrix written with exit 0. Here a
  // real full disk: a 12 KB tmpfs (root only; skipped where mounting is not allowed).
  if (::geteuid() != 0) GTEST_SKIP() << "mounting a tmpfs needs root";
  const std::string dir = tiny_dataset();
  const std::string mount_point = dir + "/small-disk";
  std::filesystem::create_directories(mount_point);
  if (std::system(("mount -t tmpfs -o size=12k tmpfs '" + mount_point + "' 2>/dev/null").c_str()) != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here";
  const std::string out = dir + "/full.csv";
  test::CliResult r = test::run_cli("-q distmat '" + dir + "/data' --cache '" + mount_point +
                                    "/cache' --method cmds --geodesics graph -o '" + out + "'");
  std::system(("umount '" + mount_point + "'").c_str());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find(mount_point + "/cache/"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("skipped"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(DistmatCli, ACacheFolderThatIsAFileIsRefusedFirst) {
  const std::string dir = tiny_dataset();
  test::write_text(dir + "/cache-file", "x");
  const std::string out = dir + "/out.csv";
  test::CliResult r = test::run_cli("distmat '" + dir + "/data' --cache '" + dir +
                                    "/cache-file' --method cmds -o '" + out + "'");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find(dir + "/cache-file"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("not a folder"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("sphere0"), std::string::npos) << r.err;  // before any shape
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(DistmatCli, AnErrorAfterProgressStartsALineOfItsOwn) {
  // Issue 22: without -q an error was glued to the progress line ("\r[coulomb] 0.0%cshapes canon: error:
  // ...").
  const std::string dir = tiny_dataset();
  test::CliResult r = test::run_cli("distmat '" + dir + "/data' --cache '" + dir +
                                    "/cache' --method cmds --geodesics graph --test-fail-after-pairs 1 -o '" +
                                    dir + "/out.csv'");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  ASSERT_NE(r.err.find("[distances, "), std::string::npos) << r.err;  // a progress line, naming the method
  const size_t at = r.err.find("cshapes distmat: error: ");
  ASSERT_NE(at, std::string::npos) << r.err;
  EXPECT_TRUE(at == 0 || r.err[at - 1] == '\n') << r.err;
}

// Issue 57: distmat wrote no classes, so `evaluate D.csv` on a manifest whose file names carry none (s0 …)
// took them all for one class and said mAP 1.000. The labels file beside the matrix carries them.
TEST(DistmatCli, WritesTheClassesBesideTheMatrixWhereEvaluateFindsThem) {
  const std::string dir = tiny_dataset();
  std::filesystem::create_directories(dir + "/named/sub");
  const char* files[] = {"sphere0", "sphere1", "torus0", "torus1"};
  for (int k = 0; k < 4; ++k)
    std::filesystem::copy_file(dir + "/data/" + files[k] + ".off",
                               dir + "/named/s" + std::to_string(k) + ".off");
  test::write_text(dir + "/named/manifest.csv",
                   "file,class\ns0.off,sphere\ns1.off,sphere\ns2.off,torus\ns3.off,torus\n");
  const nlohmann::json summary = run_json("-q distmat '" + dir + "/named/manifest.csv' --cache '" + dir +
                                          "/cache' --method cmds --geodesics graph -o '" + dir + "/D.csv'");
  EXPECT_EQ(summary["labels"], dir + "/D.labels.csv");
  // Above the classes, what the matrix is (issue 60): evaluate's figures are titled with it.
  EXPECT_EQ(read_file(dir + "/D.labels.csv"),
            "# method: classical MDS\n# distance: Hausdorff\n# data: named\n"
            "name,class\ns0,sphere\ns1,sphere\ns2,torus\ns3,torus\n");
  test::CliResult r = test::run_cli("-q evaluate '" + dir + "/D.csv' --out '" + dir +
                                    "/eval' --json --no-draw --min-class-size 2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json m = nlohmann::json::parse(r.out);
  EXPECT_EQ(m["classes_from"], dir + "/D.labels.csv");
  EXPECT_EQ(m["classes"].size(), 2u);
  EXPECT_EQ(m["title"], "classical MDS, Hausdorff distance, named: 4 shapes, 2 classes");
  // Two files of one shape name: refused before any work, both files named (no matrix, no labels).
  std::filesystem::copy_file(dir + "/data/torus0.off", dir + "/named/sub/s0.off");
  test::write_text(dir + "/named/twice.csv", "file,class\ns0.off,sphere\ns1.off,sphere\nsub/s0.off,torus\n");
  r = test::run_cli("distmat '" + dir + "/named/twice.csv' --cache '" + dir +
                    "/cache' --method cmds --geodesics graph -o '" + dir + "/twice.csv'");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find(dir + "/named/s0.off and " + dir + "/named/sub/s0.off are both shape 's0'"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/twice.csv"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/twice.labels.csv"));
}

}  // namespace distmat_cli_test
}  // namespace cshapes
