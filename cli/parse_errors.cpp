// The command line's mistakes in the user's words: CLI11's parse errors on one line, with a hint (the option
// meant when one is unknown or mistyped) and the old spellings kept only to be refused naming the new ones
// (command.h: add_renamed, parse_error_with_hint).
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>
#include <sstream>

#include "cli/command.h"

namespace cshapes::cli {

namespace parse_errors {
namespace {
// Per command, each old spelling add_renamed kept and its new name: a misspelling of an old name is answered
// with the new one.
std::map<const CLI::App*, std::map<std::string, std::string>>& renamed_flags() {
  static std::map<const CLI::App*, std::map<std::string, std::string>> renamed;
  return renamed;
}
}  // namespace
}  // namespace parse_errors

void add_renamed(CLI::App& app, const std::string& old_name, const std::string& new_name, bool takes_value,
                 const std::string& why) {
  parse_errors::renamed_flags()[&app][old_name] = new_name;
  const std::string message = old_name + " is now " + new_name +
                              (why.empty() ? " (one name per meaning in every command)" : " (" + why + ")");
  CLI::Option* option =
      takes_value ? app.add_option_function<std::string>(
                        old_name, [message](const std::string&) { throw CLI::ValidationError(message); })
                  : app.add_flag_callback(old_name, [message] { throw CLI::ValidationError(message); });
  option->group("");  // not in --help
}

namespace parse_errors {
namespace {

// CLI11's message, on one line, with its conversion failures in the wording of our validators.
std::string parse_error_message(const CLI::ParseError& error) {
  std::string message = error.what();
  for (char& c : message)
    if (c == '\n') c = ' ';
  const std::string value_prefix = "The value ", value_middle = " is not an allowed value for ";
  const size_t middle = message.find(value_middle);
  if (message.rfind(value_prefix, 0) == 0 && middle != std::string::npos)
    return message.substr(middle + value_middle.size()) + ": " +
           in_quotes(message.substr(value_prefix.size(), middle - value_prefix.size())) +
           " is not a valid value (not a number, or out of range)";
  const std::string convert_prefix = "Could not convert: ";
  const size_t equals = message.find(" = ");
  if (message.rfind(convert_prefix, 0) == 0 && equals != std::string::npos)
    return message.substr(convert_prefix.size(), equals - convert_prefix.size()) + ": " +
           in_quotes(message.substr(equals + 3)) + " is not a valid value";
  return message;
}

// The edit distance of two names (insertions, deletions, substitutions and swaps of neighbours, each 1).
size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
  for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (size_t i = 1; i <= a.size(); ++i)
    for (size_t j = 1; j <= b.size(); ++j) {
      d[i][j] =
          std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

// The options a command takes, as the user may write them: its own, its option groups' and its parents'
// (given before or after the command). Each name ("--output", "-o") maps to how a hint writes the option
// ("-o/--output"); an old spelling (add_renamed) to its new name.
struct KnownOptions {
  std::map<std::string, std::string> shown;    // the options in the help
  std::map<std::string, std::string> renamed;  // old spelling -> new name
  bool knows(const std::string& name) const { return shown.count(name) || renamed.count(name); }
};
void collect_options(const CLI::App& app, KnownOptions& known) {
  for (const CLI::Option* option : app.get_options()) {
    if (option->get_group().empty()) continue;  // an old spelling: below, with its new name
    std::string written;
    for (const std::string& s : option->get_snames()) written += "-" + s + "/";
    for (const std::string& l : option->get_lnames()) written += "--" + l + "/";
    if (written.empty()) continue;  // a positional argument
    written.pop_back();
    for (const std::string& s : option->get_snames()) known.shown["-" + s] = written;
    for (const std::string& l : option->get_lnames()) known.shown["--" + l] = written;
  }
  if (const auto at = renamed_flags().find(&app); at != renamed_flags().end())
    for (const auto& [old_name, new_name] : at->second) known.renamed[old_name] = new_name;
  for (const CLI::App* group : app.get_subcommands([](const CLI::App* a) { return a->get_name().empty(); }))
    collect_options(*group, known);
}

// The first option on the command line that `command` (its path, "bench smacof") does not take, and the
// option its user most likely meant ("" when none is close): the nearest name by edit distance, or the one
// it begins (--out for --output).
struct UnknownOption {
  std::string written, meant;
};
std::optional<UnknownOption> unknown_option(CLI::App& app, const std::string& command, int argc,
                                            char** argv) {
  KnownOptions known;
  collect_options(app, known);
  CLI::App* level = &app;
  std::stringstream path(command);
  for (std::string part; path >> part;) {
    CLI::App* sub = nullptr;
    for (CLI::App* candidate : level->get_subcommands([](CLI::App*) { return true; }))
      if (candidate->get_name() == part) sub = candidate;
    if (!sub) break;
    level = sub;
    collect_options(*level, known);
  }
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word == "--") break;  // positional arguments follow
    if (word.size() < 2 || word[0] != '-') continue;
    char* end = nullptr;
    std::strtod(word.c_str(), &end);
    if (end && *end == '\0') continue;  // a negative number
    const bool long_name = word[1] == '-';
    const std::string name = long_name ? word.substr(0, word.find('=')) : word.substr(0, 2);  // -ofile: -o
    if (known.knows(name)) continue;
    // A file whose name starts with '-' (the caller says how to write it).
    std::error_code ec;
    if (std::filesystem::exists(word, ec) ||
        (long_name ? name : word).find_first_of("./") != std::string::npos)
      continue;
    UnknownOption unknown{name, ""};
    const std::string bare = name.substr(name.find_first_not_of('-'));
    // Close: up to a third of the name's letters changed (1 to 3), or the start of a name (--out, --output).
    // Ranked by the edits, a start after one edit (--method: --methods before --method-timeout).
    const size_t most = std::max<size_t>(1, std::min<size_t>(3, bare.size() / 3));
    size_t best = SIZE_MAX;
    auto consider = [&](const std::string& candidate, const std::string& written) {
      const std::string other = candidate.substr(candidate.find_first_not_of('-'));
      const size_t edits = edit_distance(bare, other);
      size_t rank = edits <= most ? 2 * edits : SIZE_MAX;
      if (bare.size() >= 3 && other.rfind(bare, 0) == 0) rank = std::min<size_t>(rank, 3);
      if (rank < best) {
        best = rank;
        unknown.meant = written;
      }
    };
    for (const auto& [candidate, written] : known.shown) consider(candidate, written);
    for (const auto& [old_name, new_name] : known.renamed) consider(old_name, new_name);
    return unknown;
  }
  return std::nullopt;
}

// A parse error of the command line with a hint: an unknown option is named first, with the option meant
// ("unknown option --methods; did you mean --method?"); a required option missing because the user wrote
// another name for it says which ("--output is required: --out is not an option of canon; use -o/--output").
}  // namespace
}  // namespace parse_errors

std::string parse_error_with_hint(const CLI::ParseError& error, CLI::App& app, const std::string& command,
                                  int argc, char** argv) {
  using namespace parse_errors;
  const std::string message = parse_error_message(error);
  const std::optional<UnknownOption> unknown = unknown_option(app, command, argc, argv);
  if (!unknown) return message;
  if (dynamic_cast<const CLI::RequiredError*>(&error) && !unknown->meant.empty()) {
    const std::string meant_long = unknown->meant.substr(unknown->meant.rfind('/') + 1);
    if (message.rfind(meant_long + " is required", 0) == 0)
      return message + ": " + unknown->written + " is not an option of " +
             (command.empty() ? "cshapes" : command) + "; use " + unknown->meant;
  }
  std::string text = "unknown option " + unknown->written;
  if (!unknown->meant.empty()) text += "; did you mean " + unknown->meant + "?";
  if (dynamic_cast<const CLI::ExtrasError*>(&error)) return text;
  return text + " (" + message + ")";
}

}  // namespace cshapes::cli
