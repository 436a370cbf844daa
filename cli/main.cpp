// cshapes: the command-line entry point. All logic lives in the libraries; commands are registered by
// experiments/cmd_*.cpp (see command.h).
#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "cli/command.h"
#include "cshapes/support/atomic_file.h"
#include "cshapes/support/build_info.h"
#include "cshapes/support/distance_matrix.h"
#include "cshapes/support/error.h"
#include "cshapes/support/format.h"
#include "cshapes/mesh/knn_graph.h"
#include "cshapes/mesh/remesh.h"
#include "cshapes/support/simd.h"
#include "cshapes/support/threads.h"
#include "cshapes/support/timing.h"
#include "cshapes/data/cache.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/distributed.h"
#include "cshapes/pipeline/method_options.h"
#include "cshapes/pipeline/outside_methods.h"
#include "cshapes/pipeline/renamed_options.h"
#include "cshapes/support/output_folder.h"
#include "cshapes/data/dataset.h"

namespace cshapes::cli {

namespace {
struct Registry {
  std::vector<Command> commands;
};
Registry& registry() {
  static Registry r;
  return r;
}
bool g_quiet = false;
int g_threads = 0;
std::string g_command = "";  // "canon", "bench coulomb": the command in messages
}  // namespace

bool register_command(Command command) {
  registry().commands.push_back(std::move(command));
  return true;
}

bool quiet() {
  return g_quiet;
}
int threads() {
  return g_threads;
}

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, ',');)
    if (!part.empty()) parts.push_back(part);
  return parts;
}

std::vector<std::string> list_option(const std::string& option, const std::string& text) {
  if (text.empty()) {
    if (option_given(option))
      usage_fail(option, ": empty list; give at least one item, or leave the option out for its default");
    return {};
  }
  std::vector<std::string> parts;
  size_t start = 0;
  while (true) {
    const size_t comma = text.find(',', start);
    const std::string item =
        text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (item.empty()) usage_fail(option, ": empty item in '", text, "'");
    parts.push_back(item);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return parts;
}

namespace {
CLI::App* g_selected = nullptr;  // the command that runs, after a successful parse
}  // namespace

bool option_given(const std::string& option) {
  if (!g_selected) return false;
  const CLI::Option* found = g_selected->get_option_no_throw(option);
  if (!found)
    for (CLI::App* group : g_selected->get_subcommands([](CLI::App* a) { return a->get_name().empty(); }))
      if ((found = group->get_option_no_throw(option))) break;
  return found && found->count() > 0;
}

namespace {
// Whether a progress line ("\r[coulomb]  42.0%") is on the screen unfinished: a message first ends it, so
// that it starts a line of its own.
std::atomic<bool> g_progress_open{false};
void end_progress_line() {
  if (g_progress_open.exchange(false)) std::cerr << '\n';
}
}  // namespace

void note(const std::string& line) {
  // A library's warning said on the note channel ("warning: …") is a warning: one prefix, shown with --quiet.
  static const std::string kWarning = "warning: ";
  if (line.rfind(kWarning, 0) == 0) return warn(line.substr(kWarning.size()));
  if (g_quiet) return;
  end_progress_line();
  std::cerr << line << std::endl;
}

void warn(const std::string& line) {
  end_progress_line();
  std::cerr << "cshapes" << (g_command.empty() ? "" : " ") << g_command << ": warning: " << line << std::endl;
}

const char* const kPartialResultHelp =
    "Exit codes: 0 success; 1 a failure of the data or the computation that ended the run; 2 the command "
    "line; 3 a partial result: the run finished, but a shape whose file could not be used or whose "
    "canonical form failed (by any method) was left out, named on stderr, in the report and the JSON "
    "(a heat geodesics failure falls back to fast marching and keeps the shape). --strict stops at the "
    "first failing shape instead (exit code 1).";

int exit_code_for(const std::vector<ShapeFailure>& failures) {
  for (const ShapeFailure& f : failures) warn(describe(f));
  const int left_out = count_left_out(failures);
  if (left_out == 0) return kExitOk;
  // A file the data could not use (stage "read": unreadable, or a folder entry that is no mesh) is counted
  // as a file, not as a shape: a FIFO in the folder never was one.
  std::vector<ShapeFailure> unusable_files;
  for (const ShapeFailure& f : failures)
    if (f.stage == "read") unusable_files.push_back(f);
  const int files = count_left_out(unusable_files), shapes = left_out - files;
  std::string what;
  if (files > 0) what = std::to_string(files) + (files == 1 ? " file" : " files");
  if (shapes > 0)
    what += (what.empty() ? "" : " and ") + std::to_string(shapes) + (shapes == 1 ? " shape" : " shapes");
  warn(what + (left_out == 1 ? " was" : " were") + " left out: a partial result (exit code " +
       std::to_string(kExitPartial) + ")");
  return kExitPartial;
}

void require_output_path(const std::string& path, const std::vector<std::string>& extensions) {
  try {
    check_output_path(path, extensions);
  } catch (const UsageError&) {
    throw;
  } catch (const Error& e) {
    throw UsageError(e.what());
  }
}
void require_mesh_output_path(const std::string& path) {
  require_output_path(path, {"off", "ply", "obj", "xyz"});  // what write_mesh writes (mesh/io.h)
}
void prepare_experiment(const std::vector<std::string>& methods, const std::string& out,
                        CanonicalFormOptions& canon) {
  check_canon_method_options(methods);
  require_output_directory(out);
  keep_outside_method_logs(out);
  configure_canonical_form(canon);  // every method option given, as in `cshapes canon`
}

void add_data_and_out_options(CLI::App& app, std::string& data, std::string& out, bool& force,
                              bool& allow_outside, const OptionDeclaration& data_option) {
  add_declared(app, data_option, data)->required();
  add_allow_outside_flag(app, allow_outside);
  add_declared(app, kOutFolderOption, out)->required();
  add_force_flag(app, force);
}

void warn_invalid_vertices_dropped(const MeshFile& file, const std::string& path) {
  if (file.invalid_vertices > 0)
    warn(std::to_string(file.invalid_vertices) + " invalid vertices (NaN rows, valid = 0) of " + path +
         " dropped, with the " + std::to_string(file.invalid_faces) + " faces on them");
}

void add_allow_outside_flag(CLI::App& app, bool& allow_outside) {
  add_declared_flag(app, kAllowOutsideOption, allow_outside);
}

void add_force_flag(CLI::App& app, bool& force) {
  add_declared_flag(app, kForceOption, force);
}

void add_no_draw_flag(CLI::App& app, bool& no_draw, const OptionDeclaration& draw) {
  add_declared_flag(app, draw, no_draw);
  add_renamed(app, "--no-figures", "--no-draw", false);
  add_renamed(app, "--no-figure", "--no-draw", false);
}

CLI::Option* add_figure_format_option(CLI::App& app, FigureFormat& format) {
  return app
      .add_option_function<std::string>(
          kFigureFormatOption.flag,
          [&format](const std::string& name) { format = parse_figure_format(name); },
          option_help(kFigureFormatOption, OptionSkin::Cli))
      ->check(one_of(kFigureFormatOption.choices))
      ->default_str(to_string(format));
}

CLI::Option* add_out_folder_option(CLI::App& app, std::string& folder, const std::string& help) {
  for (const char* old : {"-o", "--output"})
    add_renamed(app, old, "--out", true, "an output folder is --out in every command, -o a file");
  return app.add_option("--out", folder, help);
}

std::string method_titles(const std::string& last) {
  const std::vector<CanonicalFormMethod>& methods = canonical_form_method_registry();
  std::string text;
  for (size_t k = 0; k < methods.size(); ++k)
    text += (k == 0 ? "" : k + 1 == methods.size() ? last : ", ") + methods[k].title;
  return text;
}

void require_output_directory(const std::string& path) {
  try {
    check_output_directory(path);
  } catch (const UsageError&) {
    throw;
  } catch (const Error& e) {
    throw UsageError(e.what());
  }
}

ProgressFn progress_printer() {
  if (g_quiet) return {};
  // On a terminal: one line rewritten in place ("\r"), at most 4 times a second. Into a file or a pipe (a
  // log): plain lines, when a stage starts, every 10 s and when it ends, so a log holds no "\r" fragments.
  const bool terminal = isatty(fileno(stderr)) != 0;
  struct State {
    WallClock::time_point start = WallClock::now(), last{};
    std::string stage;
    bool ended = false;  // the stage's "100%" line is out: a second one is not printed
  };
  auto state = std::make_shared<State>();
  return [state, terminal](const std::string& stage, double done, double total) {
    if (stage.empty()) return;  // a poll (support/progress.h): nothing to report
    auto now = WallClock::now();
    bool first = false;
    const bool finished = done >= total;
    if (stage == state->stage && state->ended && finished) return;
    // A new stage, or the same stage run again (the next shape's form) after it ended.
    if (stage != state->stage || state->ended) {
      state->stage = stage;
      state->start = now;
      state->last = now;
      state->ended = false;
      first = true;
    }
    const auto interval = terminal ? std::chrono::milliseconds(250) : std::chrono::milliseconds(10000);
    if (!finished && !first && now - state->last < interval) return;
    state->last = now;
    const double elapsed = std::chrono::duration<double>(now - state->start).count();
    const double fraction = total > 0 ? done / total : 1.0;
    std::fprintf(stderr, "%s[%s] %5.1f%%", terminal ? "\r" : "", stage.c_str(), 100.0 * fraction);
    // An estimate only once it means something: after 3 s and 5% of the stage.
    if (const std::optional<double> left = seconds_left_estimate(elapsed, fraction))
      std::fprintf(stderr, " (about %.0f s left)%s", *left, terminal ? "   " : "");
    if (finished)
      std::fprintf(stderr, " in %s%s", seconds_text(elapsed).c_str(), terminal ? "            " : "");
    if (finished || !terminal) std::fprintf(stderr, "\n");
    std::fflush(stderr);
    g_progress_open = terminal && !finished;
    state->ended = finished;
  };
}

namespace {

void set_threads(int requested) {
  const bool given = requested > 0;
  // R ranks of an MPI run on one node share its cores: by default each takes its part.
  if (!given && !std::getenv("OMP_NUM_THREADS"))
    requested = std::max(1, omp_get_max_threads() / cshapes::ranks_on_this_node());
  // Long runs choose again before each form and block of pairs from this request, not from the count the
  // load allows now (support/threads.h).
  const int request =
      std::min(requested > 0 ? requested : omp_get_max_threads(), 4 * std::max(1, omp_get_num_procs()));
  omp_set_num_threads(threads_for_computation(requested, 3, [given](const std::string& line) {
    warn((given ? "--threads " : "OMP_NUM_THREADS=") + line);
  }));
  cshapes::set_thread_request(request);
}

// The command named on the command line ("canon", "bench coulomb"), found without the parser (which may
// have failed): the longest chain of command names among the arguments.
std::string command_in_arguments(CLI::App& app, int argc, char** argv) {
  CLI::App* level = &app;
  std::string path;
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word.empty() || word[0] == '-') continue;
    CLI::App* sub = nullptr;
    for (CLI::App* candidate : level->get_subcommands([](CLI::App*) { return true; }))
      if (candidate->get_name() == word) sub = candidate;
    if (!sub) {
      if (level != &app) break;
      continue;
    }
    path += (path.empty() ? "" : " ") + word;
    level = sub;
  }
  return path;
}

// Every numeric option refuses what is not a number in one wording ("--iterations: expected an integer, got
// 'abc'"), also those without a range check of their own (which run first and say the same).
void check_numeric_options(CLI::App& app) {
  for (CLI::Option* option : app.get_options()) {
    std::string type = option->get_type_name();
    type = type.substr(0, type.find(':'));
    if (type == "INT")
      option->check(integer_in(LLONG_MIN, LLONG_MAX).description(""));
    else if (type == "UINT")
      option->check(integer_at_least(0).description(""));
    else if (type == "FLOAT")
      option->check(number_in(-HUGE_VAL, HUGE_VAL).description(""));
  }
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) check_numeric_options(*sub);
}

// Every option's help shows its default: options that take a value and are not required get the value their
// variable holds before parsing ("=0.1"); a command need not call capture_default_str() itself.
void show_defaults(CLI::App& app) {
  for (CLI::Option* option : app.get_options())
    if (option->get_type_size() != 0 && !option->get_required() && option->get_default_str().empty())
      option->capture_default_str();
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) show_defaults(*sub);
}

// The one-line descriptions of the commands that only group others (`cshapes bench`, ...).
std::string group_description(const std::string& name) {
  static const std::map<std::string, std::string> groups = {
      {"bench",
       "Benchmarks: each measures a part of cshapes against a reference in the same run and prints JSON "
       "(docs/benchmarks.md)"},
      {"experiment",
       "Experiments: the paper's, the noise curve, TOPKIDS, pose invariance and the Coulomb parameter study, "
       "each writing data, figures and report.md into --out (cached: reruns resume)"},
      {"generate",
       "Shapes made here, deterministic for a seed: a swiss roll, articulated poses, the hand, a "
       "whole retrieval dataset"}};
  auto it = groups.find(name);
  return it == groups.end() ? std::string() : it->second;
}

// OpenMP threads that wait by spinning keep their cores busy between parallel loops, and on a loaded machine
// they take the core from the thread that has work (docs/cli.md, "Threads"); a wait that only sleeps costs
// each of the canonization's many short loops a wake-up. The measured middle: spin briefly, then sleep
// (GOMP_SPINCOUNT=1000; scripts/busy_canon.py, docs/cli.md "Threads"). libgomp reads its variables once, when
// it loads, before main: so unless the user chose (OMP_WAIT_POLICY or GOMP_SPINCOUNT), the process runs
// itself again with GOMP_SPINCOUNT set (once: the new process sees the variable). If exec fails, it goes on.
void bound_the_spin(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") || std::getenv("GOMP_SPINCOUNT")) return;
  if (::setenv("GOMP_SPINCOUNT", kGompSpinCount, 1) != 0) return;
  ::execv("/proc/self/exe", argv);
  ::unsetenv("GOMP_SPINCOUNT");
}

int report(const std::string& what, int code) {
  end_progress_line();
  std::cerr << "cshapes" << (g_command.empty() ? "" : " ") << g_command << ": error: " << what << '\n';
  return code;
}

// The command tree from the registered paths: a subcommand per path element, each registered command's
// options on its leaf. Returns the leaves' commands. The help lists them in the order of their paths, not in
// the order the files registered them (which the build decides).
std::map<CLI::App*, const Command*> build_command_tree(CLI::App& app) {
  std::vector<const Command*> sorted;
  for (const Command& cmd : registry().commands) sorted.push_back(&cmd);
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const Command* a, const Command* b) { return a->path < b->path; });
  std::map<CLI::App*, const Command*> leaf;
  for (const Command* command : sorted) {
    const Command& cmd = *command;
    CLI::App* parent = &app;
    for (size_t k = 0; k < cmd.path.size(); ++k) {
      CLI::App* sub = nullptr;
      for (CLI::App* existing : parent->get_subcommands([](CLI::App*) { return true; }))
        if (existing->get_name() == cmd.path[k]) sub = existing;
      if (!sub) {
        sub = parent->add_subcommand(cmd.path[k],
                                     k + 1 == cmd.path.size() ? cmd.summary : group_description(cmd.path[k]));
        sub->fallthrough();
      }
      if (k + 1 < cmd.path.size()) sub->require_subcommand(1);
      parent = sub;
    }
    parent->description(cmd.summary);
    if (cmd.add_options) cmd.add_options(*parent);
    // The command's old spellings (pipeline/renamed_options.h), refused naming the new ones.
    std::string scope;
    for (const std::string& part : cmd.path) scope += (scope.empty() ? "" : " ") + part;
    for (const RenamedOption& renamed : renamed_options_in(scope))
      add_renamed(*parent, option_flag(renamed.old_name), option_flag(renamed.new_name), true);
    leaf[parent] = &cmd;
  }
  return leaf;
}

// Runs the command; an error is one line on stderr and its exit code (usage 2, data 1).
int run_command(const Command& command) {
  int code = 0;
  try {
    return command.run();
  } catch (const UsageError& e) {
    code = report(e.what(), kExitUsage);
  } catch (const cshapes::Error& e) {
    code = report(e.what(), kExitDataError);
  } catch (const std::bad_alloc&) {
    code = report("out of memory", kExitDataError);
  } catch (const std::length_error& e) {  // a container asked for more elements than it can hold
    code = report(std::string("out of memory: a size beyond what can be allocated (") + e.what() + ")",
                  kExitDataError);
  } catch (const std::exception& e) {
    code = report(e.what(), kExitDataError);
  }
  // Under mpirun the other ranks may be waiting for this one in a collective call: end them all.
  cshapes::abort_all_ranks(code);
  return code;
}

}  // namespace

}  // namespace cshapes::cli

int main(int argc, char** argv) {
  using namespace cshapes::cli;
  bound_the_spin(argv);
  CLI::App app{std::string("cshapes ") + CSHAPES_VERSION + ": deformation-invariant canonical forms (" +
               method_titles() + "), ICP matching and shape-retrieval evaluation"};
  app.require_subcommand(1);
  app.fallthrough();
  app.set_version_flag("--version", [] {
    try {
      return cshapes::version_text();
    } catch (const std::exception& e) {  // CSHAPES_SIMD names an instruction set this CPU lacks
      return "cshapes " + cshapes::version() + "\nbuild: " + cshapes::build_description() +
             "\nkernels: " + e.what();
    }
  });
  app.add_option("--threads", g_threads,
                 "OpenMP threads, at most 4 per core (default: all cores, shared among the MPI ranks of a "
                 "node); fewer when other processes keep "
                 "cores busy at the start (set CSHAPES_EXACT_THREADS=1 to keep N)")
      ->check(integer_at_least(0));
  app.add_flag("-q,--quiet", g_quiet, "no progress or notes on stderr");
  // --help lists the presets, --help-all also the single settings they cover (advanced option groups).
  app.set_help_all_flag("--help-all", "Print this help message with every advanced option and exit");
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--help-all") show_advanced_method_options(true);

  const std::map<CLI::App*, const Command*> leaf = build_command_tree(app);
  check_numeric_options(app);
  show_defaults(app);

  g_command = command_in_arguments(app, argc, argv);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    if (g_command.empty())
      for (int i = 1; i < argc; ++i)
        if (argv[i][0] != '-' && !(i > 1 && std::string(argv[i - 1]) == "--threads"))
          return report("unknown command '" + std::string(argv[i]) + "' (see cshapes --help)", kExitUsage);
    // A file whose name starts with '-' is read as an option: name it, and say how to write it.
    std::string hint;
    for (int i = 1; i < argc && hint.empty(); ++i) {
      const std::string word = argv[i];
      if (word.size() < 2 || word[0] != '-' || word == "--") continue;
      char* end = nullptr;
      std::strtod(word.c_str(), &end);
      if (end && *end == '\0') continue;  // a negative number
      std::error_code ec;
      if (std::filesystem::exists(word, ec) || word.find_first_of("./") != std::string::npos)
        hint = "; '" + word + "' was read as an option: write a file whose name starts with '-' as ./" + word;
    }
    // One line, like every other error (CLI11 would add a second "Run with --help" line), and one exit code.
    return report(parse_error_with_hint(e, app, g_command, argc, argv) + hint + " (see cshapes " +
                      (g_command.empty() ? "" : g_command + " ") + "--help)",
                  kExitUsage);
  }

  CLI::App* selected = &app;
  g_command.clear();
  while (!selected->get_subcommands().empty()) {
    selected = selected->get_subcommands().front();
    g_command += (g_command.empty() ? "" : " ") + selected->get_name();
  }
  g_selected = selected;
  auto it = leaf.find(selected);
  if (it == leaf.end()) return report("no command given; see cshapes --help", kExitUsage);
  try {
    cshapes::simd_target();  // CSHAPES_SIMD checked before any work
  } catch (const cshapes::Error& e) {
    return report(e.what(), kExitUsage);
  }
  // A timing is read with the kernels that produced it (the JSON of every bench records them too).
  if (g_command.rfind("bench", 0) == 0) note("kernels: " + cshapes::simd_description());
  set_threads(g_threads);
  cshapes::set_cache_warning_sink(warn);  // a damaged cache entry is said, also under --quiet
  return run_command(*it->second);
}
