#include "cshapes/experiments/figures.h"

#include <dlfcn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cshapes/support/atomic_file.h"
#include "cshapes/pipeline/canonical_form_methods.h"

namespace cshapes {

namespace fs = std::filesystem;

namespace {

// The file of the binary (executable or shared object) this function was linked into.
fs::path this_binary() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&this_binary), &info) && info.dli_fname) {
    std::error_code ec;
    fs::path p = fs::canonical(info.dli_fname, ec);
    if (!ec) return p;
  }
  std::error_code ec;
  fs::path self = fs::canonical("/proc/self/exe", ec);
  return ec ? fs::path() : self;
}

}  // namespace

std::string plot_scripts_directory() {
  if (const char* env = std::getenv("CSHAPES_PLOTS"); env && *env) return env;
  const fs::path binary = this_binary();
  if (binary.empty()) return "";
  // build/cshapes, PREFIX/bin/cshapes, build/python/cshapes/_cshapes.so, site-packages/cshapes/_cshapes.so
  const fs::path dir = binary.parent_path();
  for (const fs::path& candidate : {dir / "share/cshapes/plots", dir.parent_path() / "share/cshapes/plots",
                                    dir.parent_path().parent_path() / "share/cshapes/plots", dir / "plots"}) {
    std::error_code ec;
    if (fs::is_directory(candidate, ec)) return candidate.string();
  }
  return "";
}

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string find_python(const std::string& imports) {
  std::vector<std::string> candidates;
  if (const char* env = std::getenv("CSHAPES_PYTHON"); env && *env) candidates.push_back(env);
  candidates.push_back("/usr/bin/python3");
  candidates.push_back("python3");
  for (const std::string& c : candidates) {
    if (c.find('/') != std::string::npos && !fs::exists(c)) continue;
    const std::string command =
        shell_quote(c) + " -c " + shell_quote("import " + imports) + " >/dev/null 2>&1";
    if (std::system(command.c_str()) == 0) return c;
  }
  return "";
}

void write_method_titles(const std::string& folder, const std::vector<std::string>& methods) {
  nlohmann::ordered_json titles = nlohmann::ordered_json::object();
  if (methods.empty()) {
    for (const CanonicalFormMethod& method : canonical_form_method_registry()) titles[method.name] = method.title;
    // Methods from outside after the library's: each its own colour (figure_style.py's EXTRA_COLOURS, in order).
    for (const CanonicalFormMethod* method : outside_canonical_form_methods())
      titles[method->name] = method->title;
  }
  for (const std::string& m : methods) titles[m] = canonical_form_method_title(m);
  write_file_atomically((fs::path(folder) / "methods.json").string(),
                        [&](std::ostream& out) { out << titles.dump(2) << "\n"; });
}

namespace {

// The path of a figure script in plot_scripts_directory(); "" when it is not there.
std::string figure_script_path(const std::string& script) {
  const std::string dir = plot_scripts_directory();
  if (dir.empty()) return "";
  const fs::path path = fs::path(dir) / script;
  std::error_code ec;
  return fs::exists(path, ec) ? path.string() : "";
}

// The last non-empty line of a text file; "" when there is none.
std::string last_line_of(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line))
    if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  return last;
}

// What a script said when it failed, as its own words: the last line of a Python traceback without the
// exception's class ("ValueError: x.obj: ..." -> "x.obj: ..."), a sys.exit message as it is.
std::string said_without_exception_class(const std::string& line) {
  const size_t colon = line.find(": ");
  if (colon == std::string::npos || colon == 0) return line;
  const std::string name = line.substr(0, colon);
  const bool identifier =
      name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.") ==
      std::string::npos;
  const bool exception =
      name.size() > 5 && (name.compare(name.size() - 5, 5, "Error") == 0 ||
                          (name.size() > 9 && name.compare(name.size() - 9, 9, "Exception") == 0));
  return identifier && exception ? line.substr(colon + 2) : line;
}

// Why `system` reported a failure, in words: "exited with status 2", "was killed by signal 9".
std::string status_text(int status) {
  if (status == -1) return "could not be started";
  if (WIFEXITED(status)) return "exited with status " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return "was killed by signal " + std::to_string(WTERMSIG(status));
  return "failed";
}

}  // namespace

FigureRun run_figure_script(const std::string& script, const std::vector<std::string>& args,
                            const std::string& expected, const ProgressFn& progress) {
  FigureRun run;
  const std::string path = figure_script_path(script);
  if (path.empty()) {
    run.problem = "the figure script " + script +
                  " was not found (looked beside the binary in share/cshapes/plots; set $CSHAPES_PLOTS)";
    return run;
  }
  std::string by_hand = "python3 " + path;
  for (const std::string& a : args) by_hand += " " + shell_quote(a);
  const std::string python = find_python("matplotlib, numpy");
  if (python.empty()) {
    run.problem =
        "no Python with matplotlib and numpy found ($CSHAPES_PYTHON, /usr/bin/python3, python3); run `" +
        by_hand + "` once it is installed (Debian: python3-matplotlib)";
    return run;
  }
  std::error_code ec;
  fs::remove(expected, ec);
  static std::atomic<long> counter{0};
  const fs::path errors = fs::temp_directory_path(ec) / ("cshapes-figure-" + std::to_string(::getpid()) +
                                                         "-" + std::to_string(counter++) + ".err");
  // With progress, the script is asked for its "progress K N" lines (CSHAPES_FIGURE_PROGRESS=1).
  std::string command = std::string(progress ? "CSHAPES_FIGURE_PROGRESS=1 " : "") + shell_quote(python) + " " +
                        shell_quote(path);
  for (const std::string& a : args) command += " " + shell_quote(a);
  command += (progress ? "" : " >/dev/null") + std::string(" 2>") + shell_quote(errors.string());
  int status = -1;
  if (!progress) {
    status = std::system(command.c_str());
  } else if (FILE* pipe = ::popen(command.c_str(), "r")) {
    // The script's "progress K N" lines, as it finishes each figure.
    char line[512];
    while (std::fgets(line, sizeof line, pipe)) {
      double done = 0, total = 0;
      if (std::sscanf(line, "progress %lf %lf", &done, &total) == 2 && total > 0) progress("figures", done, total);
    }
    status = ::pclose(pipe);
  }
  run.drawn = status == 0 && fs::exists(expected, ec);
  if (!run.drawn) {
    // The script's own last words when it said any; else how it ended. Either way, the command to see it all.
    const std::string said = said_without_exception_class(last_line_of(errors.string()));
    const std::string how =
        status == 0 ? "wrote no " + fs::path(expected).filename().string() : status_text(status);
    run.problem = script + ": " + (said.empty() || status == 0 ? how : said) + " (`" + python + " " + path +
                  "` " + (said.empty() || status == 0 ? "" : how + "; ") +
                  "run it by hand to see all it printed)";
  }
  fs::remove(errors, ec);
  return run;
}

FigureRun draw_figure(const std::string& script, const std::vector<std::string>& args,
                      const std::string& figure, FigureFormat format, const std::vector<std::string>& methods,
                      const ProgressFn& progress) {
  const fs::path path(figure);
  if (!figure_script_path(script).empty()) write_method_titles(path.parent_path().string(), methods);
  std::vector<std::string> with_format = args;
  with_format.push_back("--format=" + to_string(format));
  return run_figure_script(script, with_format,
                           (path.parent_path() / figure_file_name(path.filename().string(), format)).string(),
                           progress);
}

std::string figure_markdown(const std::string& caption, const std::string& file) {
  const bool pdf = fs::path(file).extension() == ".pdf";
  return pdf ? "[" + caption + " (PDF)](" + file + ")" : "![" + caption + "](" + file + ")";
}

}  // namespace cshapes
