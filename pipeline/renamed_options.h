// The options renamed so that every command says one thing one way (docs/cli.md, "One name per meaning"):
// each old spelling is kept only to be refused, naming the new one. One table for the CLI and the Python
// module: the CLI refuses `--iters` (exit code 2, "--iters is now --smacof-max-iterations"), Python refuses
// the keyword `iters` (TypeError naming `smacof_max_iterations`).
//
//   {"method options", "iters", "smacof_max_iterations"}
//
// The names are Python's (snake_case); the CLI's flags are the same in kebab-case ("--" + option_flag).
#pragma once

#include <string>
#include <vector>

namespace cshapes {

struct RenamedOption {
  // Where the old name was read: "method options" (the canonical-form methods' options: `canon`, `distmat`,
  // the experiments; Python's canonical_form(), coulomb(), smacof()), or a command as the CLI names it
  // ("align", "bench smacof"; the CLI refuses the old flag there).
  std::string scope;
  std::string old_name;  // snake_case
  std::string new_name;  // snake_case
  // Also a keyword of Python (false: the CLI's only): a function that reads the new name refuses the old
  // one naming it (icp(), shape_distance() and distance_matrix() read align's options, experiment_paper()
  // the paper's).
  bool python = true;
};

// Every renamed option, in the order of the scopes.
const std::vector<RenamedOption>& renamed_options();
// The renamed options of one scope.
std::vector<RenamedOption> renamed_options_in(const std::string& scope);

}  // namespace cshapes
