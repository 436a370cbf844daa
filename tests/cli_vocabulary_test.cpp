// One name per meaning in every command (cli/command.h): `--out DIR` for an output folder, `-o, --output FILE`
// for an output file, `--no-draw` for "do not draw the figures", `--json` for JSON on stdout. Read from every
// command's --help, so a new command or option that says one of these things another way fails here; the old
// spellings are refused with a hint naming the new one.
#include <gtest/gtest.h>

#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.h"

namespace cshapes {
namespace cli_vocabulary_test {

std::string help_of(const std::string& command) {
  const test::CliResult r = test::run_cli(command + " --help");
  EXPECT_EQ(r.exit_code, 0) << command << ": " << r.err;
  return r.out;
}

// The names listed under "Subcommands:" in a help text.
std::vector<std::string> subcommands_in(const std::string& help) {
  std::vector<std::string> names;
  std::istringstream in(help);
  bool listing = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("Subcommands:", 0) == 0) {
      listing = true;
      continue;
    }
    static const std::regex entry(R"(^  ([a-z0-9-]+)\s{2,}.*)");
    std::smatch m;
    if (listing && std::regex_match(line, m, entry)) names.push_back(m[1]);
  }
  return names;
}

// Every command that runs something ("canon", "experiment paper", "bench coulomb", …).
std::vector<std::string> leaf_commands() {
  std::vector<std::string> leaves, pending = subcommands_in(help_of(""));
  while (!pending.empty()) {
    const std::string command = pending.back();
    pending.pop_back();
    const std::vector<std::string> below = subcommands_in(help_of(command));
    if (below.empty()) leaves.push_back(command);
    for (const std::string& b : below) pending.push_back(command + " " + b);
  }
  return leaves;
}

struct Option {
  std::string names;        // "-o,--output"
  std::string description;  // its help text, continuation lines joined
};

std::vector<Option> options_of(const std::string& help) {
  std::vector<Option> options;
  std::istringstream in(help);
  static const std::regex start(R"(^\s{2,6}((?:-[a-zA-Z],)?--[a-z0-9-]+)\S*\s*(.*))");
  static const std::regex continuation(R"(^\s{20,}(\S.*))");
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (std::regex_match(line, m, start))
      options.push_back({m[1], m[2]});
    else if (!options.empty() && std::regex_match(line, m, continuation))
      options.back().description += " " + m[1].str();
  }
  return options;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(CliVocabulary, EveryCommandSaysOneThingOneWay) {
  const std::vector<std::string> commands = leaf_commands();
  ASSERT_GT(commands.size(), 20u);  // the whole tree was read
  std::map<std::string, int> checked;
  for (const std::string& command : commands) {
    for (const Option& o : options_of(help_of(command))) {
      const std::string where = "cshapes " + command + " " + o.names + ": " + o.description;
      for (const char* old : {"--no-figure", "--no-figures", "--output-dir", "--outdir", "--json-out"})
        EXPECT_FALSE(o.names == old || o.names.find(std::string(",") + old) != std::string::npos) << where;
      if (contains(o.description, "do not draw")) {
        EXPECT_EQ(o.names, "--no-draw") << where;
        ++checked["--no-draw"];
      }
      const bool folder = contains(o.description, "folder") || contains(o.description, "directory");
      if (o.names == "--out") {
        EXPECT_TRUE(folder) << "--out is an output folder: " << where;
        ++checked["--out"];
      }
      if (o.names == "-o,--output") {
        EXPECT_FALSE(contains(o.description, "output folder") || contains(o.description, "output directory"))
            << "-o is an output file, --out a folder: " << where;
        ++checked["-o"];
      }
      if (contains(o.description, "output folder") || contains(o.description, "output directory")) {
        EXPECT_EQ(o.names, "--out") << where;
      }
      if (contains(o.description, "JSON") && (contains(o.description, "print") || contains(o.description, "stdout")))
        if (o.names != "--out" && o.names != "-o,--output") {
          EXPECT_EQ(o.names, "--json") << where;
          ++checked["--json"];
        }
    }
  }
  // Each rule met real options (the parser read the help as it is laid out).
  for (const char* name : {"--no-draw", "--out", "-o", "--json"}) EXPECT_GT(checked[name], 2) << name;
}

TEST(CliVocabulary, OldSpellingsAreRefusedWithTheNewName) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"evaluate m.csv -o e", "-o is now --out"},
      {"evaluate m.csv --output e", "--output is now --out"},
      {"generate dataset -o d", "-o is now --out"},
      {"generate articulated --output d", "--output is now --out"},
      {"experiment retrieval --data d --out o --no-figures", "--no-figures is now --no-draw"},
      {"experiment noise --data d --out o --no-figure", "--no-figure is now --no-draw"},
      {"experiment paper --data d --out o --no-figures", "--no-figures is now --no-figure-data"},
      {"stress --out s.jsonl", "--out is now -o/--output"},
  };
  for (const auto& [arguments, hint] : cases) {
    const test::CliResult r = test::run_cli(arguments);
    EXPECT_EQ(r.exit_code, 2) << arguments << ": " << r.err;
    EXPECT_TRUE(contains(r.err, hint)) << arguments << ": " << r.err;
  }
}

}  // namespace cli_vocabulary_test
}  // namespace cshapes
