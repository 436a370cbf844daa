// No output may be an input: every command that writes files refuses, before any work, an output path that
// is one of the files it reads, however it is spelt ("./X", a symbolic link, a hard link), and leaves the
// input as it was (cli/command.h: require_output_not_input).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/data/synthetic.h"
#include "tests/test_support.h"

namespace cshapes {
namespace output_not_input_cli_test {

namespace fs = std::filesystem;

constexpr int kUsage = 2;  // README's exit codes: an output path that cannot be written is a usage error

std::string q(const std::string& path) {
  return "'" + path + "'";
}

// The command was refused with one error line naming the input, and `input` still holds `bytes`.
void expect_input_kept(const test::CliResult& r, const std::string& command, const std::string& input,
                       const std::string& bytes) {
  EXPECT_GE(r.exit_code, 0) << "killed by a signal: " << r.err;
  EXPECT_EQ(r.exit_code, kUsage) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(r.err.rfind("cshapes " + command + ": error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("is the input"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(input), std::string::npos) << r.err;
  EXPECT_EQ(read_file(input), bytes) << input << " was changed by: " << command;
}

struct MeshFiles {
  std::string dir, a, b, a_link, a_hard, a_dotted;
  std::string a_bytes, b_bytes;
};
MeshFiles mesh_files() {
  MeshFiles m;
  m.dir = test::scratch_dir("output-not-input");
  m.a = m.dir + "/a.off";
  m.b = m.dir + "/b.off";
  write_mesh(m.a, icosphere(1));
  write_mesh(m.b, icosphere(1, 2.0));
  m.a_link = m.dir + "/a_link.off";
  fs::create_symlink("a.off", m.a_link);
  m.a_hard = m.dir + "/a_hard.off";
  fs::create_hard_link(m.a, m.a_hard);
  m.a_dotted = m.dir + "/./sub/../a.off";
  fs::create_directories(m.dir + "/sub");
  m.a_bytes = read_file(m.a);
  m.b_bytes = read_file(m.b);
  return m;
}

TEST(OutputNotInput, TheLibraryRuleNamesBothPathsAndPassesNewFiles) {
  const MeshFiles m = mesh_files();
  for (const std::string& output : {m.a, m.a_link, m.a_hard, m.a_dotted}) {
    SCOPED_TRACE(output);
    try {
      check_output_not_input(output, {m.b, m.a}, "-o");
      ADD_FAILURE() << "not refused";
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("-o " + output), std::string::npos) << message;
      EXPECT_NE(message.find("is the input " + m.a), std::string::npos) << message;
    }
  }
  EXPECT_NO_THROW(check_output_not_input(m.dir + "/new.off", {m.a, m.b}));  // does not exist yet
  EXPECT_NO_THROW(check_output_not_input(m.b, {m.a, ""}));                  // exists, but no input
  fs::remove_all(m.dir);
}

TEST(OutputNotInput, MeshCommandsRefuseToOverwriteTheirInput) {
  const MeshFiles m = mesh_files();
  for (const std::string& output : {m.a, m.a_link, m.a_hard, m.a_dotted}) {
    SCOPED_TRACE(output);
    expect_input_kept(test::run_cli("-q canon " + q(m.a) + " -o " + q(output) + " --method cmds"), "canon",
                      m.a, m.a_bytes);
    expect_input_kept(test::run_cli("-q remesh " + q(m.a) + " -o " + q(output) + " --vertices 60"), "remesh",
                      m.a, m.a_bytes);
    expect_input_kept(test::run_cli("-q align " + q(m.a) + " " + q(m.b) + " -o " + q(output)), "align", m.a,
                      m.a_bytes);
    expect_input_kept(test::run_cli("-q convert " + q(m.a) + " " + q(output)), "convert", m.a, m.a_bytes);
    expect_input_kept(test::run_cli("-q noise " + q(m.a) + " -o " + q(output) + " --glue 1"), "noise", m.a,
                      m.a_bytes);
    expect_input_kept(test::run_cli("-q show " + q(m.a) + " " + q(m.b) + " -o " + q(output)), "show", m.a,
                      m.a_bytes);
  }
  // align's target is an input too.
  expect_input_kept(test::run_cli("-q align " + q(m.a) + " " + q(m.b) + " -o " + q(m.b)), "align", m.b,
                    m.b_bytes);
  fs::remove_all(m.dir);
}

TEST(OutputNotInput, DistmatRefusesTheManifestAndTheReference) {
  const std::string dir = test::scratch_dir("output-not-input-distmat");
  const std::string manifest = test::generated_dataset(dir + "/data", 2, 2, 300);
  const std::string bytes = read_file(manifest);
  // The folder is read through its manifest: writing the matrix over it would leave no dataset.
  expect_input_kept(test::run_cli("-q distmat " + q(dir + "/data") + " -o " + q(manifest)), "distmat",
                    manifest, bytes);
  expect_input_kept(test::run_cli("-q distmat " + q(manifest) + " -o " + q(dir + "/data/./manifest.csv")),
                    "distmat", manifest, bytes);
  const std::string reference = dir + "/reference.csv";
  test::write_text(reference, "x\n");
  expect_input_kept(test::run_cli("-q distmat " + q(manifest) + " --two-stage-k 1 --reference " +
                                  q(reference) + " -o " + q(reference)),
                    "distmat", reference, "x\n");
  fs::remove_all(dir);
}

// An experiment writes many files into --out (report.md, matrices, classes.cla, caches): the dataset's own
// folder is refused as --out, whether --data names the folder or its manifest.
TEST(OutputNotInput, ExperimentsRefuseTheDatasetsFolderAsOutput) {
  const std::string dir = test::scratch_dir("output-not-input-experiments");
  const std::string manifest = test::generated_dataset(dir + "/data", 2, 2, 300);
  const std::string bytes = read_file(manifest);
  for (const std::string& data : {dir + "/data", manifest}) {
    for (const char* experiment : {"retrieval", "paper", "noise", "pose"}) {
      SCOPED_TRACE(std::string(experiment) + " " + data);
      const test::CliResult r = test::run_cli(std::string("-q experiment ") + experiment + " --data " + q(data) +
                                              " --out " + q(dir + "/./data"));
      EXPECT_EQ(r.exit_code, kUsage) << r.err;
      EXPECT_NE(r.err.find("is the folder of the dataset"), std::string::npos) << r.err;
      EXPECT_EQ(read_file(manifest), bytes);
    }
  }
  fs::remove_all(dir);
}

TEST(OutputNotInput, EvaluateRefusesToReplaceItsMatrixOrLabels) {
  const std::string dir = test::scratch_dir("output-not-input-evaluate");
  const std::string matrix = dir + "/out/matrix.csv";
  const std::string text = "a0,a1,b0,b1\n0,1,2,2\n1,0,2,2\n2,2,0,1\n2,2,1,0\n";
  test::write_text(matrix, text);
  expect_input_kept(test::run_cli("-q evaluate " + q(matrix) + " --out " + q(dir + "/out") + " --no-draw"),
                    "evaluate", matrix, text);
  const std::string labels = dir + "/out/pr.csv";
  test::write_text(labels, "a0,a\na1,a\nb0,b\nb1,b\n");
  const std::string other = dir + "/m.csv";
  test::write_text(other, text);
  expect_input_kept(test::run_cli("-q evaluate " + q(other) + " --labels " + q(labels) + " --out " +
                                  q(dir + "/out") + " --no-draw"),
                    "evaluate", labels, "a0,a\na1,a\nb0,b\nb1,b\n");
  // A matrix outside the output folder is fine.
  test::CliResult ok =
      test::run_cli("-q evaluate " + q(other) + " --out " + q(dir + "/fresh") + " --no-draw --min-class-size 2");
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  fs::remove_all(dir);
}

}  // namespace output_not_input_cli_test
}  // namespace cshapes
