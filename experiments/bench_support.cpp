#include "cshapes/experiments/bench_support.h"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/experiments/figures.h"

namespace cshapes {

Mesh bench_mesh(const std::string& path, int n, std::string& source) {
  if (!path.empty()) {
    source = path;
    return read_mesh(path);
  }
  CSHAPES_REQUIRE(n >= 16, "--vertices must be >= 16, got ", n);
  const int nv = std::max(4, static_cast<int>(std::lround(std::sqrt(n / 3.0))));
  const int nu = (n + nv - 1) / nv;
  source = "torus " + std::to_string(nu) + "x" + std::to_string(nv);
  return torus(nu, nv, 1.0, 0.3);
}

namespace fs = std::filesystem;

double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // Linux: kilobytes
}

double load_average() {
  std::ifstream in("/proc/loadavg");
  double one_minute = 0;
  in >> one_minute;
  return one_minute;
}

std::string shared_tosca5k_shape(const std::string& name) {
  std::string dir;
  if (const char* env = std::getenv("CSHAPES_DATA"); env && *env)
    dir = env;
  else
    dir = "../shared/data";
  const std::string path = dir + "/tosca5k/" + name + ".off";
  std::error_code ec;
  return fs::exists(path, ec) ? path : "";
}

namespace {

// A fresh folder under the system's temporary folder, removed with everything in it on destruction.
class ScratchFolder {
 public:
  ScratchFolder() {
    static std::atomic<int> counter{0};
    path_ = (fs::temp_directory_path() /
             ("cshapes-anchor-" + std::to_string(::getpid()) + "-" + std::to_string(counter++)))
                .string();
    std::error_code ec;
    fs::remove_all(path_, ec);
    if (!fs::create_directories(path_, ec) || ec)
      fail_write("cannot create the temporary folder ", path_, ": ", ec.message());
  }
  ~ScratchFolder() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

std::string last_nonempty_line(const std::string& file) {
  std::ifstream in(file);
  std::string last, line;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

}  // namespace

AnchorRun run_python_anchor(const AnchorScript& script) {
  AnchorRun run;
  const std::string python = script.python.empty() ? find_python(script.imports) : script.python;
  if (python.empty()) {
    run.skipped = "no Python that imports " + script.imports + " (for " + script.package +
                  ") found: looked at $CSHAPES_PYTHON, /usr/bin/python3, python3";
    return run;
  }
  const ScratchFolder folder;
  if (script.write_inputs) script.write_inputs(folder.path());
  const std::string source = folder.path() + "/anchor.py", errors = folder.path() + "/stderr";
  write_file_atomically(source, [&](std::ostream& out) { out << script.source; });
  std::string command = script.environment.empty() ? "" : script.environment + " ";
  command += shell_quote(python) + " " + shell_quote(source) + " " + shell_quote(folder.path());
  for (const std::string& argument : script.arguments) command += " " + shell_quote(argument);
  command += " 2>" + shell_quote(errors);
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) {
    run.skipped = "cannot start " + python;
    return run;
  }
  char buffer[4096];
  while (size_t got = fread(buffer, 1, sizeof buffer, pipe)) run.output.append(buffer, got);
  const int status = pclose(pipe);
  const int exit_status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.ran = exit_status == 0 && !run.output.empty();
  if (!run.ran) {
    run.skipped = python + " with " + script.package + " failed (exit status " + std::to_string(exit_status) +
                  "): " + last_nonempty_line(errors);
    run.output.clear();
  }
  return run;
}

}  // namespace cshapes
