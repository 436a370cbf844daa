// cshapes: the command-line entry point. All logic lives in the libraries; commands are registered by
// experiments/cmd_*.cpp (see command.h).
#include <omp.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>

#include "core/atomic_file.h"
#include "core/error.h"
#include "experiments/command.h"

namespace cshapes::cli {

namespace {
struct Registry {
  std::vector<Command> commands;
  std::vector<CanonMethod> canon;
};
Registry& registry() {
  static Registry r;
  return r;
}
bool g_quiet = false;
int g_threads = 0;
}  // namespace

bool register_command(Command command) {
  registry().commands.push_back(std::move(command));
  return true;
}
bool register_canon_method(CanonMethod method) {
  registry().canon.push_back(std::move(method));
  return true;
}
const std::vector<CanonMethod>& canon_methods() { return registry().canon; }

void add_canon_method_options(CLI::App& app) {
  for (const CanonMethod& m : canon_methods()) {
    CLI::Option_group* group = app.add_option_group(m.name + " options");
    if (m.add_options) m.add_options(*group);
  }
}

void configure_canonical_form(CanonicalFormOptions& options) {
  for (const CanonMethod& m : canon_methods())
    if (m.configure) m.configure(options);
}

bool quiet() { return g_quiet; }
int threads() { return g_threads; }

void note(const std::string& line) {
  if (!g_quiet) std::cerr << line << std::endl;
}

ProgressFn progress_printer() {
  if (g_quiet) return {};
  struct State {
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now(), last{};
    std::string stage;
  };
  auto state = std::make_shared<State>();
  return [state](const std::string& stage, double done, double total) {
    auto now = std::chrono::steady_clock::now();
    if (stage != state->stage) {
      state->stage = stage;
      state->start = now;
    }
    bool finished = done >= total;
    if (!finished && now - state->last < std::chrono::milliseconds(250)) return;
    state->last = now;
    double elapsed = std::chrono::duration<double>(now - state->start).count();
    double fraction = total > 0 ? done / total : 1.0;
    std::fprintf(stderr, "\r[%s] %5.1f%%", stage.c_str(), 100.0 * fraction);
    if (fraction > 0.01 && !finished) std::fprintf(stderr, " (about %.0f s left)   ", elapsed * (1 / fraction - 1));
    if (finished) std::fprintf(stderr, " in %.2f s            \n", elapsed);
    std::fflush(stderr);
  };
}

void write_csv(const std::string& path, const std::vector<std::string>& columns,
               const std::vector<std::vector<double>>& rows) {
  write_file_atomically(path, [&](std::ostream& out) {
    for (size_t c = 0; c < columns.size(); ++c) out << (c ? "," : "") << columns[c];
    out << '\n';
    out.precision(10);
    for (const auto& row : rows) {
      for (size_t c = 0; c < row.size(); ++c) out << (c ? "," : "") << row[c];
      out << '\n';
    }
  });
}

}  // namespace cshapes::cli

int main(int argc, char** argv) {
  using namespace cshapes::cli;
  CLI::App app{"cshapes " CSHAPES_VERSION
               ": deformation-invariant canonical forms (Coulomb shapes, classical MDS, SMACOF), ICP matching "
               "and shape-retrieval evaluation"};
  app.require_subcommand(1);
  app.fallthrough();
  app.set_version_flag("--version", CSHAPES_VERSION);
  app.add_option("--threads", cshapes::cli::g_threads, "OpenMP threads (default: all cores)")->check(CLI::NonNegativeNumber);
  app.add_flag("-q,--quiet", cshapes::cli::g_quiet, "no progress or notes on stderr");

  // Build the command tree from the registered paths.
  std::map<CLI::App*, const Command*> leaf;
  for (const Command& cmd : registry().commands) {
    CLI::App* parent = &app;
    for (size_t k = 0; k < cmd.path.size(); ++k) {
      CLI::App* sub = nullptr;
      for (CLI::App* existing : parent->get_subcommands([](CLI::App*) { return true; }))
        if (existing->get_name() == cmd.path[k]) sub = existing;
      if (!sub) {
        sub = parent->add_subcommand(cmd.path[k], k + 1 == cmd.path.size() ? cmd.summary : "");
        sub->fallthrough();
      }
      if (k + 1 < cmd.path.size()) sub->require_subcommand(1);
      parent = sub;
    }
    parent->description(cmd.summary);
    if (cmd.add_options) cmd.add_options(*parent);
    leaf[parent] = &cmd;
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // One line, like every other error (CLI11 would add a second "Run with --help" line).
    std::string message = e.what();
    for (char& c : message)
      if (c == '\n') c = ' ';
    std::cerr << "cshapes: error: " << message << " (see --help)\n";
    return e.get_exit_code() ? e.get_exit_code() : 2;
  }
  if (g_threads > 0) omp_set_num_threads(g_threads);

  CLI::App* selected = &app;
  while (!selected->get_subcommands().empty()) selected = selected->get_subcommands().front();
  auto it = leaf.find(selected);
  if (it == leaf.end()) {
    std::cerr << "cshapes: no command given; see cshapes --help\n";
    return 2;
  }
  try {
    return it->second->run();
  } catch (const cshapes::Error& e) {
    std::cerr << "cshapes " << selected->get_name() << ": error: " << e.what() << '\n';
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "cshapes " << selected->get_name() << ": error: out of memory\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "cshapes " << selected->get_name() << ": error: " << e.what() << '\n';
    return 1;
  }
}
