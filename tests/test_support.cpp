#include "tests/test_support.h"

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace cshapes::test {

namespace fs = std::filesystem;

std::string data_dir() {
  if (const char* env = std::getenv("CSHAPES_DATA"); env && *env && fs::is_directory(env)) return env;
  fs::path p = fs::path(CSHAPES_SOURCE_DIR) / ".." / "shared" / "data";
  if (fs::is_directory(p)) return fs::canonical(p).string();
  return "";
}

std::string tosca5k(const std::string& name) { return data_dir() + "/tosca5k/" + name + ".off"; }

std::string scratch_dir(const std::string& tag) {
  static std::atomic<int> counter{0};
  fs::path p = fs::temp_directory_path() /
               ("cshapes-test-" + tag + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
  fs::remove_all(p);
  fs::create_directories(p);
  return p.string();
}

namespace {
std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
}  // namespace

CliResult run_cli(const std::string& arguments) {
  std::string dir = scratch_dir("cli");
  std::string out = dir + "/stdout", err = dir + "/stderr";
  std::string command = std::string("'") + CSHAPES_CLI + "' " + arguments + " >'" + out + "' 2>'" + err + "'";
  int status = std::system(command.c_str());
  CliResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  fs::remove_all(dir);
  return r;
}

double mean_relative_error(const Eigen::VectorXd& d, const Eigen::VectorXd& exact, double min_distance) {
  double sum = 0;
  int count = 0;
  for (Eigen::Index i = 0; i < d.size(); ++i)
    if (exact[i] > min_distance) {
      sum += std::abs(d[i] - exact[i]) / exact[i];
      ++count;
    }
  EXPECT_GT(count, 0);
  return count ? sum / count : 0.0;
}

void write_text(const std::string& path, const std::string& text) {
  fs::path p(path);
  if (p.has_parent_path()) fs::create_directories(p.parent_path());
  std::ofstream(path) << text;
}

}  // namespace cshapes::test
