// One declaration per user option that both skins take outside the canonical-form methods (those are
// pipeline/method_options.h's MethodOption): `cshapes align --trim` and icp(trim=...), `--resample` and every
// experiment's resample=, ... Declared once, in the room that owns the option (matching/icp.h for ICP's,
// data/topological_noise.h for the glues', experiments/ for the experiments'), it holds the CLI's flag, the
// Python keyword, one help text written for people and the library's limit or choices. The CLI adds the
// option with the declaration's help (cli/command.h: add_declared); Python's docstrings render the same text
// (cshapes.option_declarations(), python/_api.py), with the limit in words ("a number in [0, 0.9]").
//
//   inline const OptionDeclaration kIcpTrim{
//       "trim", "--trim", "the fraction of the worst pairs dropped per direction at each step (trimmed ICP)",
//       icp_limits::kTrim};
//
// A help text that names another option writes its Python keyword in braces, "{gap_edges}": the CLI shows
// "--gap-edges", Python "gap_edges" (option_help). The text is a phrase without a final full stop, as the
// CLI's help lines are; Python capitalises it and ends it. A flag that says the opposite of its keyword
// (`--no-draw` for draw=True) is declared `negated`, its help saying what the keyword does ("draw noise.png
// ..."): the CLI shows "do not draw noise.png ...".
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cshapes/support/option_limits.h"

namespace cshapes {

struct OptionDeclaration {
  std::string keyword;               // Python's keyword, snake_case
  std::string flag;                  // the CLI's flag, "--" + kebab-case (or another spelling)
  std::string help;                  // one text for both skins; other options as "{keyword}"
  std::optional<Limit> limit;        // the library's limit of a number (support/option_limits.h), if any
  std::vector<std::string> choices;  // a choice's names, in order (empty: not a choice)
  bool negated = false;              // the CLI's flag turns off what the keyword (true) turns on

  OptionDeclaration(std::string keyword_, std::string flag_, std::string help_,
                    std::optional<Limit> limit_ = std::nullopt, std::vector<std::string> choices_ = {})
      : keyword(std::move(keyword_)),
        flag(std::move(flag_)),
        help(std::move(help_)),
        limit(limit_),
        choices(std::move(choices_)) {}
};

enum class OptionSkin { Cli, Python };

// A flag that turns off what its keyword turns on: negated_option("draw", "--no-draw", "draw noise.png").
OptionDeclaration negated_option(std::string keyword, std::string flag, std::string help);

// The declaration's help for one skin: every "{keyword}" written as that skin spells an option ("--gap-edges"
// or "gap_edges"); a negated flag's on the CLI after "do not ".
std::string option_help(const OptionDeclaration& option, OptionSkin skin);
// The CLI's spelling of a keyword: "--" + its kebab-case ("gap_edges" -> "--gap-edges").
std::string keyword_flag(const std::string& keyword);

}  // namespace cshapes
