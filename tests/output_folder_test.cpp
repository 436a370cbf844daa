// support/output_folder.h and issue 57's rules through the CLI: an output never replaces what a user had, a
// failed run leaves the previous complete set, a rerun leaves nothing of the previous run it no longer writes;
// a dataset is its folder; messages name the cause. Each CLI case once exited 0 (or blamed the wrong thing)
// on the code before the issue.
#include "cshapes/support/output_folder.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <limits>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/data/dataset.h"
#include "cshapes/data/synthetic.h"
#include "tests/test_support.h"

namespace cshapes {
namespace output_folder_test {

namespace fs = std::filesystem;

constexpr int kBadData = 1, kUsage = 2;

std::string q(const std::string& path) {
  return "'" + path + "'";
}

std::string text_of(const std::string& path) {
  return read_file(path);
}

// ---- the library: OutputRun ----

TEST(OutputRun, ANewFolderIsClaimedAndItsFilesRecorded) {
  const std::string dir = test::scratch_dir("output-run-new") + "/out";
  {
    OutputRun run(dir, "test");
    test::write_text(dir + "/a.txt", "a");
    test::write_text(dir + "/sub/b.txt", "b");
    run.commit();
  }
  const std::string record = text_of(dir + "/" + kOutputRecordName);
  EXPECT_NE(record.find("command test"), std::string::npos) << record;
  EXPECT_NE(record.find("file a.txt"), std::string::npos) << record;
  EXPECT_NE(record.find("file sub/b.txt"), std::string::npos) << record;
  EXPECT_NE(record.find("state complete"), std::string::npos) << record;
}

TEST(OutputRun, AFolderHoldingAUsersFileIsRefusedUnlessForced) {
  const std::string dir = test::scratch_dir("output-run-user");
  test::write_text(dir + "/mine.off", "user data");
  try {
    OutputRun run(dir, "test");
    FAIL() << "a folder holding a user's file was claimed";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("mine.off"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--force"), std::string::npos) << e.what();
  }
  {
    OutputRun run(dir, "test", {}, true);
    test::write_text(dir + "/new.txt", "new");
    run.commit();
  }
  EXPECT_EQ(text_of(dir + "/mine.off"), "user data");
  // The user's file stays the user's: a second run, not forced, takes the folder, and never removes it.
  {
    OutputRun run(dir, "test");
    run.commit();
  }
  EXPECT_EQ(text_of(dir + "/mine.off"), "user data");
  EXPECT_FALSE(fs::exists(dir + "/new.txt"));  // the previous run's output, not written again
}

TEST(OutputRun, AnotherCommandsFolderIsRefused) {
  const std::string dir = test::scratch_dir("output-run-other");
  {
    OutputRun run(dir, "generate dataset");
    test::write_text(dir + "/a.off", "a");
    run.commit();
  }
  try {
    OutputRun run(dir, "experiment retrieval", {"cache"});
    FAIL() << "another command's folder was claimed";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("generate dataset"), std::string::npos) << e.what();
  }
  EXPECT_EQ(text_of(dir + "/a.off"), "a");
}

TEST(OutputRun, AFailedRunLeavesThePreviousCompleteSet) {
  const std::string dir = test::scratch_dir("output-run-failed");
  {
    OutputRun run(dir, "test", {"cache"});
    test::write_text(dir + "/metrics.json", "old");
    test::write_text(dir + "/matrix.csv", "old matrix");
    test::write_text(dir + "/cache/entry", "cached");
    run.commit();
  }
  try {
    OutputRun run(dir, "test", {"cache"});
    test::write_text(dir + "/metrics.json", "new");  // half of the new set, then a failure
    test::write_text(dir + "/cache/entry2", "cached too");
    throw Error("disk full");
  } catch (const Error&) {
  }
  EXPECT_EQ(text_of(dir + "/metrics.json"), "old");
  EXPECT_EQ(text_of(dir + "/matrix.csv"), "old matrix");
  EXPECT_EQ(text_of(dir + "/cache/entry2"), "cached too");  // what was computed is kept
  EXPECT_FALSE(fs::exists(dir + "/.cshapes-previous"));
}

TEST(OutputRun, ARunKilledOutrightIsUndoneByTheNextClaim) {
  const std::string dir = test::scratch_dir("output-run-killed");
  {
    OutputRun run(dir, "test");
    test::write_text(dir + "/report.md", "complete");
    run.commit();
  }
  // What kill -9 leaves: the record of a running process that no longer exists, the previous set aside and
  // a partial new one.
  fs::create_directories(dir + "/.cshapes-previous");
  fs::rename(dir + "/report.md", dir + "/.cshapes-previous/report.md");
  test::write_text(dir + "/partial.csv", "half");
  test::write_text(dir + "/" + kOutputRecordName,
                   "cshapes output folder 1\ncommand test\nstate running\npid 999999999\nhost " +
                       [] {
                         char name[256] = {};
                         gethostname(name, sizeof name - 1);
                         return std::string(name);
                       }() +
                       "\nfile report.md\n");
  {
    OutputRun run(dir, "test");
    EXPECT_FALSE(fs::exists(dir + "/partial.csv"));
    EXPECT_FALSE(fs::exists(dir + "/report.md"));  // moved aside again for the new run
    test::write_text(dir + "/report.md", "rerun");
    run.commit();
  }
  EXPECT_EQ(text_of(dir + "/report.md"), "rerun");
  EXPECT_FALSE(fs::exists(dir + "/partial.csv"));
}

TEST(OutputRun, PublishingStagedFilesNeverReplacesUnlessForced) {
  const std::string dir = test::scratch_dir("output-run-publish");
  test::write_text(dir + "/hand_glued.off", "user's");
  std::string staging = make_staging_folder(dir);
  test::write_text(staging + "/hand_glued.off", "generated");
  test::write_text(staging + "/other.off", "generated");
  EXPECT_THROW(publish_staged_files(staging, dir, false), Error);
  EXPECT_EQ(text_of(dir + "/hand_glued.off"), "user's");
  EXPECT_FALSE(fs::exists(dir + "/other.off"));  // nothing moved
  EXPECT_FALSE(fs::exists(staging));
  staging = make_staging_folder(dir);
  test::write_text(staging + "/hand_glued.off", "generated");
  publish_staged_files(staging, dir, true);
  EXPECT_EQ(text_of(dir + "/hand_glued.off"), "generated");
}

// ---- the CLI: issue 57's cases ----

TEST(OutputFolderCli, GenerateNeverReplacesAUsersFiles) {
  // Was: `generate dataset --out mydata` replaced mydata/biped0.off and manifest.csv; `generate hand --out h`
  // replaced h/hand_glued.off; `generate swissroll` replaced ./swissroll.off; all with exit 0.
  const std::string dir = test::scratch_dir("output-generate");
  test::write_text(dir + "/mydata/biped0.off", "mine");
  test::CliResult r = test::run_cli("-q generate dataset --out " + q(dir + "/mydata") +
                                    " --classes 1 --poses 2 --noisy 0 --vertices 300");
  EXPECT_EQ(r.exit_code, kBadData) << r.err;
  EXPECT_NE(r.err.find("biped0.off"), std::string::npos) << r.err;
  EXPECT_EQ(text_of(dir + "/mydata/biped0.off"), "mine");
  EXPECT_FALSE(fs::exists(dir + "/mydata/manifest.csv"));

  test::write_text(dir + "/h/hand_glued.off", "mine");
  r = test::run_cli("-q generate hand --out " + q(dir + "/h"));
  EXPECT_EQ(r.exit_code, kBadData) << r.err;
  EXPECT_NE(r.err.find("hand_glued.off"), std::string::npos) << r.err;
  EXPECT_EQ(text_of(dir + "/h/hand_glued.off"), "mine");
  EXPECT_FALSE(fs::exists(dir + "/h/hand_separated.off"));  // all or nothing
  r = test::run_cli("-q generate hand --out " + q(dir + "/h") + " --force");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(text_of(dir + "/h/hand_glued.off"), "mine");

  test::write_text(dir + "/swissroll.off", "mine");
  r = test::run_cli("-q generate swissroll -o " + q(dir + "/swissroll.off"));
  EXPECT_EQ(r.exit_code, kBadData) << r.err;
  EXPECT_EQ(text_of(dir + "/swissroll.off"), "mine");
  // A rerun of generate dataset into its own folder replaces the previous dataset whole.
  r = test::run_cli("-q generate dataset --out " + q(dir + "/d") + " --classes 2 --poses 2 --noisy 0 --vertices 300");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir + "/d/quadruped1.off"));
  r = test::run_cli("-q generate dataset --out " + q(dir + "/d") + " --classes 1 --poses 2 --noisy 0 --vertices 300");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/d/quadruped1.off")) << "the previous dataset's shape stayed";
}

TEST(OutputFolderCli, EvaluateRerunLeavesNothingOfThePreviousRun) {
  // Was: `evaluate --no-draw` after a drawing run left the previous pr.png and matrix.png beside new numbers.
  const std::string dir = test::scratch_dir("output-evaluate");
  test::write_text(dir + "/D.csv",
                   ",a0,a1,a2,b0,b1,b2\na0,0,1,1,4,4,4\na1,1,0,1,4,4,4\na2,1,1,0,4,4,4\nb0,4,4,4,0,1,1\n"
                   "b1,4,4,4,1,0,1\nb2,4,4,4,1,1,0\n");
  const std::string out = dir + "/eval";
  test::CliResult r = test::run_cli("-q evaluate " + q(dir + "/D.csv") + " --out " + q(out) + " --no-draw");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  test::write_text(out + "/pr.png", "a figure of an earlier run");  // as a drawing run leaves it
  std::string record = text_of(out + "/" + kOutputRecordName);
  record += "file pr.png\n";
  test::write_text(out + "/" + kOutputRecordName, record);
  r = test::run_cli("-q evaluate " + q(dir + "/D.csv") + " --out " + q(out) + " --no-draw");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(fs::exists(out + "/pr.png"));
  EXPECT_TRUE(fs::exists(out + "/metrics.json"));
  // A folder holding a user's file is refused, the file untouched.
  test::write_text(dir + "/notes/mine.txt", "mine");
  r = test::run_cli("-q evaluate " + q(dir + "/D.csv") + " --out " + q(dir + "/notes") + " --no-draw");
  EXPECT_EQ(r.exit_code, kBadData) << r.err;
  EXPECT_NE(r.err.find("mine.txt"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/notes/metrics.json"));
}

TEST(OutputFolderCli, AnExperimentRefusesADatasetsFolderAsItsOutput) {
  // Was (Python): experiment_retrieval(cla, out) with out the dataset's folder rewrote its .cla.
  const std::string dir = test::scratch_dir("output-experiment");
  test::run_cli("-q generate dataset --out " + q(dir + "/data") + " --classes 2 --poses 3 --noisy 0 --vertices 300");
  const std::string manifest_before = text_of(dir + "/data/manifest.csv");
  const test::CliResult r = test::run_cli("-q experiment retrieval --data " + q(dir + "/data/manifest.csv") +
                                          " --out " + q(dir + "/data/sub/..") + " --methods lbo --no-draw");
  EXPECT_NE(r.exit_code, 0) << r.err;
  EXPECT_EQ(text_of(dir + "/data/manifest.csv"), manifest_before);
  EXPECT_FALSE(fs::exists(dir + "/data/classes.cla"));
}

TEST(DatasetFolder, ManifestEntriesOutsideTheFolderAreRefusedWithoutPrintingThem) {
  // Was: '../../../../etc/passwd', an absolute path and a link to /etc/passwd were read, and the reader's
  // warning printed the file's first line.
  const std::string dir = test::scratch_dir("dataset-outside");
  test::generated_dataset(dir + "/data", 1, 3, 300);
  test::write_text(dir + "/secret.off", "root:x:0:0:root:/root:/bin/bash\n");
  fs::create_symlink(dir + "/secret.off", dir + "/data/link.off");
  for (const std::string& entry : {std::string("../secret.off"), dir + "/secret.off", std::string("link.off")}) {
    SCOPED_TRACE(entry);
    test::write_text(dir + "/data/manifest.csv", "file,class\n" + entry + ",x\n");
    try {
      read_dataset(dir + "/data/manifest.csv");
      FAIL() << "read";
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("outside the dataset's folder"), std::string::npos) << m;
      EXPECT_NE(m.find("manifest.csv:2"), std::string::npos) << m;
      EXPECT_EQ(m.find("root:x"), std::string::npos) << m;
    }
    EXPECT_NO_THROW(read_dataset(dir + "/data/manifest.csv", true));
    const test::CliResult r = test::run_cli("-q dataset " + q(dir + "/data/manifest.csv"));
    EXPECT_EQ(r.exit_code, kBadData);
    EXPECT_EQ(r.err.find("root:x"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("--allow-outside"), std::string::npos) << r.err;
  }
}

TEST(DatasetFolder, ANegativePoseIsRefusedNamingTheLine) {
  // Was: a negative pose number was replaced by the shape's rank without a word.
  const std::string dir = test::scratch_dir("dataset-negative-pose");
  write_mesh(dir + "/a.off", icosphere(1));
  write_mesh(dir + "/b.off", icosphere(2));
  test::write_text(dir + "/manifest.csv", "file,class,pose\na.off,x,0\nb.off,x,-3\n");
  try {
    read_dataset(dir + "/manifest.csv");
    FAIL() << "read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("manifest.csv:3: 'pose' must be 0 or more, got -3"), std::string::npos)
        << e.what();
  }
}

TEST(CauseMessages, CanonSaysWhenItDropsInvalidRows) {
  // Was: canon of a PLY with a valid = 0 row wrote one vertex fewer without a word (info and convert warned).
  const std::string dir = test::scratch_dir("messages-valid");
  const Mesh sphere = icosphere(2);
  WriteOptions options;
  Eigen::VectorXd valid = Eigen::VectorXd::Ones(sphere.num_vertices());
  valid[5] = 0;
  Mesh marked = sphere;
  marked.V.row(5).setConstant(std::numeric_limits<double>::quiet_NaN());
  options.scalars.push_back({"valid", valid});
  write_mesh(dir + "/in.ply", marked, options);
  const test::CliResult r =
      test::run_cli("canon " + q(dir + "/in.ply") + " -o " + q(dir + "/out.ply") + " --method lbo");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("1 invalid vertices"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("in.ply"), std::string::npos) << r.err;
}

// ---- messages that name the cause ----

TEST(CauseMessages, PlyHeaderClaimingMoreVerticesNamesTheCounts) {
  // Was: "face 306: unexpected end of file" (ASCII) and "face 0 has 0 vertex indices" (binary).
  const std::string dir = test::scratch_dir("messages-ply-counts");
  const Mesh sphere = icosphere(2);  // 162 vertices, 320 faces
  for (const bool binary : {false, true}) {
    SCOPED_TRACE(binary);
    const std::string good = dir + (binary ? "/b.ply" : "/a.ply");
    WriteOptions options;
    options.binary = binary;
    write_mesh(good, sphere, options);
    std::string bytes = text_of(good);
    const size_t at = bytes.find("element vertex 162");
    ASSERT_NE(at, std::string::npos);
    bytes.replace(at, 18, "element vertex 170");
    const std::string bad = dir + (binary ? "/bad_b.ply" : "/bad_a.ply");
    test::write_text(bad, bytes);
    try {
      read_mesh(bad);
      FAIL() << "read";
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("170 vertex"), std::string::npos) << m;
      EXPECT_NE(m.find("claims"), std::string::npos) << m;
    }
  }
}

TEST(CauseMessages, AHugeFaceCountIsNamedWithoutOverflow) {
  // The fuzzer's find (tests/regressions): a binary PLY claiming 4e11 faces; the size check converted the
  // bytes they need (5.6e19) to an integer that cannot hold them.
  try {
    read_mesh(std::string(CSHAPES_SOURCE_DIR) + "/tests/regressions/ply_face_count_overflows_size_check.ply");
    FAIL() << "read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("the header claims"), std::string::npos) << e.what();
  }
}

TEST(CauseMessages, TwoPropertiesOfOneNameBlameTheInput) {
  // Was: `convert dup_x.ply out.ply` blamed the output.
  const std::string dir = test::scratch_dir("messages-dup-x");
  test::write_text(dir + "/dup_x.ply",
                   "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float x\nproperty float "
                   "y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                   "0 0 0 0\n1 1 0 0\n0 0 1 0\n3 0 1 2\n");
  const test::CliResult r = test::run_cli("-q convert " + q(dir + "/dup_x.ply") + " " + q(dir + "/out.ply"));
  EXPECT_EQ(r.exit_code, kBadData) << r.err;
  EXPECT_NE(r.err.find("dup_x.ply"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("appears twice"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/out.ply"));
}

TEST(CauseMessages, ANulByteInAFieldDoesNotCutTheMessage) {
  const std::string dir = test::scratch_dir("messages-nul");
  test::write_text(dir + "/D.csv", std::string(",a0,a1\na0,0,1\na1,x\0y,0\n", 23));
  const test::CliResult r = test::run_cli("-q evaluate " + q(dir + "/D.csv") + " --out " + q(dir + "/e"));
  EXPECT_EQ(r.exit_code, kBadData) << r.err;
  EXPECT_NE(r.err.find("x\\x00y"), std::string::npos) << r.err;
}

TEST(CauseMessages, OneShapeClassesSayAQueryNeedsAnotherShape) {
  // Was: `evaluate --min-class-size 1` on one-shape classes said "no class has at least 1 shapes".
  const std::string dir = test::scratch_dir("messages-min-class");
  test::write_text(dir + "/D.csv", ",a0,b0,c0\na0,0,1,2\nb0,1,0,1\nc0,2,1,0\n");
  const test::CliResult r =
      test::run_cli("-q evaluate " + q(dir + "/D.csv") + " --out " + q(dir + "/e") + " --min-class-size 1");
  EXPECT_EQ(r.exit_code, kBadData) << r.err;
  EXPECT_EQ(r.err.find("at least 1 shapes"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("no class has 2 shapes or more"), std::string::npos) << r.err;
}

TEST(CauseMessages, ClassesOfTwoSayHowToTakeThem) {
  // Was: "no class has 3 shapes or more", with no word on why 3 or how to evaluate classes of two.
  const std::string dir = test::scratch_dir("messages-classes-of-two");
  test::write_text(dir + "/D.csv", ",a0,a1,b0,b1\na0,0,1,2,3\na1,1,0,3,2\nb0,2,3,0,1\nb1,3,2,1,0\n");
  test::CliResult r = test::run_cli("-q evaluate " + q(dir + "/D.csv") + " --out " + q(dir + "/e") + " --no-draw");
  EXPECT_EQ(r.exit_code, kBadData) << r.err;
  EXPECT_NE(r.err.find("`--min-class-size 2`"), std::string::npos) << r.err;
  r = test::run_cli("-q evaluate " + q(dir + "/D.csv") + " --out " + q(dir + "/e") +
                    " --no-draw --min-class-size 2");
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST(CauseMessages, AFileNamedLikeAnOptionGetsAHint) {
  // Was: `info -weird.off` said "MESH is required".
  const std::string dir = test::scratch_dir("messages-dash");
  write_mesh(dir + "/-weird.off", icosphere(1));
  const test::CliResult r = test::run_cli("-q info -weird.off");
  EXPECT_EQ(r.exit_code, kUsage) << r.err;
  EXPECT_NE(r.err.find("./-weird.off"), std::string::npos) << r.err;
}

TEST(CauseMessages, TwoConesJoinedAtATipAreANonManifoldVertex) {
  // Was: "non-manifold edge or inconsistent orientation".
  const std::string dir = test::scratch_dir("messages-cones");
  // Two closed cones (tetrahedra) sharing vertex 0 only.
  Mesh m;
  m.V.resize(7, 3);
  m.V << 0, 0, 0, 1, 0, 1, -1, 1, 1, -1, -1, 1, 1, 0, -1, -1, 1, -1, -1, -1, -1;
  m.F.resize(8, 3);
  m.F << 0, 2, 1, 0, 3, 2, 0, 1, 3, 1, 2, 3, 0, 4, 5, 0, 5, 6, 0, 6, 4, 4, 6, 5;
  write_mesh(dir + "/cones.off", m);
  const test::CliResult r = test::run_cli("-q remesh " + q(dir + "/cones.off") + " -o " + q(dir + "/r.off") +
                                          " --vertices 100");
  EXPECT_EQ(r.exit_code, kBadData) << r.err;
  EXPECT_NE(r.err.find("non-manifold vertex"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("inconsistent orientation"), std::string::npos) << r.err;
}

}  // namespace output_folder_test
}  // namespace cshapes
