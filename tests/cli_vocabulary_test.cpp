// One name per meaning in every command (cli/command.h): `--out DIR` for an output folder, `-o, --output
// FILE` for an output file, `--no-draw` for "do not draw the figures", `--json` for JSON on stdout (on every
// command), an iteration cap `--<what>-max-iterations`, a tolerance `--<what>-tolerance`, a vertex count
// `--vertices`, a point count `--points`, timed runs `--repeats`, canonical-form methods `--methods`. Read
// from every command's --help-all, so a new command or option that says one of these things another way
// fails here, as does a default outside the range its help shows; the old spellings are refused with a hint
// naming the new one (pipeline/renamed_options.h), and an option mistyped is answered with the one meant.
#include <gtest/gtest.h>

#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.h"

namespace cshapes {
namespace cli_vocabulary_test {

// flag: --help (the command tree: --help-all at the top lists every command's options too) or --help-all (a
// command's options, the advanced ones included).
std::string help_of(const std::string& command, const std::string& flag = "--help") {
  const test::CliResult r = test::run_cli(command + " " + flag);
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

// The spellings retired for one name per meaning (each refused with the new one: OldSpellingsAre...).
const char* const kRetired[] = {"--iters",          "--max-iters",       "--max-iterations",  "--n",
                                "--tolerance",      "--landmarks",       "--start-landmarks", "--window",
                                "--timing-repeats", "--fig5-iterations", "--canon-methods"};

// The range a help shows after the type ("INT:0..100000000=300", "FLOAT:in [0, 0.5]=0.001",
// "FLOAT:>= 0=1e-05", "FLOAT:> 0=0.1", "INT:0 or 4..100000000=0"), its default, and whether the default lies
// inside. No range or no default shown: nothing to check.
struct ShownRange {
  bool shown = false;
  std::string range, fallback;
  bool holds = true;
};
ShownRange shown_range(const std::string& description) {
  static const std::string number = R"(-?\d+(?:\.\d+)?(?:e[+-]?\d+)?)";
  static const std::regex pattern("^(?:INT|UINT|FLOAT):((0 or )?(?:(" + number + R"()\.\.()" + number +
                                  R"()|in \[()" + number + "), (" + number + R"()\]|>= ()" + number +
                                  ")|> (" + number + R"()))=(\S+))");
  std::smatch m;
  ShownRange r;
  if (!std::regex_search(description, m, pattern)) return r;
  r.shown = true;
  r.range = m[1];
  r.fallback = m[9];
  char* end = nullptr;
  const double value = std::strtod(r.fallback.c_str(), &end);
  if (end == r.fallback.c_str() || *end != '\0') {
    r.holds = r.fallback == "none";  // a word for "not given" (geodesics --source), never a number outside
    return r;
  }
  if (m[2].matched && value == 0) return r;  // "0 or a..b"
  auto at = [&](int k) { return std::stod(m[k].str()); };
  if (m[3].matched) r.holds = value >= at(3) && value <= at(4);
  if (m[5].matched) r.holds = value >= at(5) && value <= at(6);
  if (m[7].matched) r.holds = value >= at(7);
  if (m[8].matched) r.holds = value > at(8);
  return r;
}

TEST(CliVocabulary, ShownRangesAreReadAsTheHelpWritesThem) {
  EXPECT_TRUE(shown_range("INT:0..100000000=300 maximum").holds);
  EXPECT_FALSE(shown_range("INT:0..2147483647=-1").holds);
  EXPECT_FALSE(shown_range("INT:16..100000000=0 a torus").holds);
  EXPECT_TRUE(shown_range("INT:0 or 4..100000000=0").holds);
  EXPECT_FALSE(shown_range("INT:0 or 4..100000000=2").holds);
  EXPECT_TRUE(shown_range("FLOAT:in [0, 0.5]=0.001 per iteration").holds);
  EXPECT_FALSE(shown_range("FLOAT:in [0.001, 100]=0").holds);
  EXPECT_TRUE(shown_range("FLOAT:>= 0=1e-05").holds);
  EXPECT_FALSE(shown_range("FLOAT:> 0=0 the factor").holds);
  EXPECT_FALSE(shown_range("FLOAT:> 0.25=0.25").holds);
  EXPECT_TRUE(shown_range("UINT:0..1e+15=1").holds);
  EXPECT_TRUE(shown_range("INT:0..2147483647=none").holds);
  EXPECT_FALSE(shown_range("TEXT:{a, b}=a").shown);
  EXPECT_FALSE(shown_range("INT=600 iteration cap").shown);
}

TEST(CliVocabulary, OneFlagPerMeaningAndDefaultsInsideTheirRanges) {
  const std::vector<std::string> commands = leaf_commands();
  ASSERT_GT(commands.size(), 20u);
  std::map<std::string, int> checked;
  for (const std::string& command : commands) {
    bool json = false;
    for (const Option& o : options_of(help_of(command, "--help-all"))) {
      const std::string name = o.names.substr(o.names.rfind(',') + 1);
      const std::string where = "cshapes " + command + " " + o.names + ": " + o.description;
      json = json || name == "--json";
      for (const char* old : kRetired) EXPECT_NE(name, old) << "a retired spelling: " << where;
      static const std::regex iters(R"(iters?$)");
      EXPECT_FALSE(std::regex_search(name, iters)) << "iterations are spelled out: " << where;
      // An iteration cap says what it caps: --coulomb-max-iterations, --smacof-max-iterations.
      static const std::regex cap(R"(\b(maximum|max\.?) (\w+ )?iterations\b|iteration cap)");
      if (std::regex_search(o.description, cap)) {
        EXPECT_TRUE(name.size() > 17 && name.rfind("-max-iterations") == name.size() - 15)
            << "an iteration cap is --<what>-max-iterations: " << where;
        ++checked["max-iterations"];
      }
      // A count of vertices is --...vertices, of points --...points (bench's --n meant either).
      static const std::regex count(
          R"(^U?INT\S*\s.*?\b(number of points|points of|points per|vertices of)\b)");
      std::smatch counted;
      if (std::regex_search(o.description, counted, count)) {
        const std::string noun = counted[1].str().find("vertices") == 0 ? "vertices" : "points";
        EXPECT_TRUE(name.size() > noun.size() && name.rfind(noun) == name.size() - noun.size())
            << "a count of " << noun << " is --" << noun << ": " << where;
        ++checked["counts"];
      }
      const ShownRange range = shown_range(o.description);
      if (range.shown) {
        EXPECT_TRUE(range.holds) << "the default " << range.fallback << " is outside " << range.range << ": "
                                 << where;
        ++checked["ranges"];
      }
    }
    // Every command prints its result as JSON with --json; stress's lines are JSON already.
    if (command != "stress") {
      EXPECT_TRUE(json) << "cshapes " << command << " has no --json";
    }
  }
  EXPECT_GT(checked["max-iterations"], 4);
  EXPECT_GT(checked["counts"], 4);
  EXPECT_GT(checked["ranges"], 100);
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
      // Issue 60: one flag per meaning (pipeline/renamed_options.h).
      {"canon m.off -o x.ply --iters 5", "--iters is now --smacof-max-iterations"},
      {"canon m.off -o x.ply --tolerance 1e-4", "--tolerance is now --smacof-tolerance"},
      {"canon m.off -o x.ply --window 4", "--window is now --smacof-window"},
      {"distmat d -o d.csv --landmarks 50", "--landmarks is now --mds-landmarks"},
      {"experiment retrieval --data d --out o --start-landmarks 20",
       "--start-landmarks is now --coulomb-start-landmarks"},
      {"align a.off b.off --tolerance 1e-4", "--tolerance is now --icp-tolerance"},
      {"remesh m.off -o r.off --vertices 100 --tolerance 0.1", "--tolerance is now --vertex-tolerance"},
      {"bench coulomb --n 300", "--n is now --points"},
      {"bench coulomb-iteration --n 300", "--n is now --vertices"},
      {"bench form --n 300", "--n is now --vertices"},
      {"bench geodesics --n 300", "--n is now --vertices"},
      {"bench icp --n 300", "--n is now --points"},
      {"bench smacof --n 300", "--n is now --points"},
      {"bench smacof --iters 5", "--iters is now --iterations"},
      {"bench smacof --max-iters 5", "--max-iters is now --smacof-max-iterations"},
      {"bench smacof --tolerance 1e-4", "--tolerance is now --smacof-tolerance"},
      {"experiment coulomb-params --data d --out o --max-iterations 5",
       "--max-iterations is now --coulomb-max-iterations"},
      {"experiment paper --data d --out o --timing-repeats 3", "--timing-repeats is now --table1-repeats"},
      {"experiment paper --data d --out o --fig5-iterations 30",
       "--fig5-iterations is now --fig5-max-iterations"},
      {"stress --canon-methods lbo", "--canon-methods is now --methods"},
      {"stress --methods heat --count 1", "'heat' is a geodesic method: give it to --geodesic-methods"},
  };
  for (const auto& [arguments, hint] : cases) {
    const test::CliResult r = test::run_cli(arguments);
    EXPECT_EQ(r.exit_code, 2) << arguments << ": " << r.err;
    EXPECT_TRUE(contains(r.err, hint)) << arguments << ": " << r.err;
  }
}

// CLI11's parse errors with a hint: the unknown option first, and the option meant (by edit distance, or the
// one it begins); a required option the user wrote another way says how to write it. Exit code 2.
TEST(CliVocabulary, ParseErrorsNameTheOptionMeant) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"distmat d -o d.csv --methods lbo", "unknown option --methods; did you mean --method?"},
      {"experiment retrieval --data d --out o --method lbo",
       "unknown option --method; did you mean --methods?"},
      {"canon m.off --out x.ply", "--output is required: --out is not an option of canon; use -o/--output"},
      {"canon m.off -o x.ply --coulomb-max-iteration 5", "did you mean --coulomb-max-iterations?"},
      {"canon m.off -o x.ply --tolerence 1e-4", "did you mean --smacof-tolerance?"},  // an old name, misspelt
      {"bench smacof --pionts 300", "did you mean --points?"},
      {"canon m.off -o x.ply --frobnicate 1", "unknown option --frobnicate"},
  };
  for (const auto& [arguments, hint] : cases) {
    const test::CliResult r = test::run_cli(arguments);
    EXPECT_EQ(r.exit_code, 2) << arguments << ": " << r.err;
    EXPECT_TRUE(contains(r.err, hint)) << arguments << ": " << r.err;
    EXPECT_FALSE(contains(r.err, "were not expected")) << arguments << ": " << r.err;
  }
}

}  // namespace cli_vocabulary_test
}  // namespace cshapes
