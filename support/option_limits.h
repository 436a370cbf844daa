// One source for each limit of a user option. The library checks its options against it (check_limit, in
// each validate), the CLI's help shows it and its parser applies it (cli/command.h: within), and
// the Python module checks each keyword against it (python/kwargs.h) — so the help, the CLI's refusal,
// the Python refusal and the library's own check can never disagree. A limit is named as the user types
// the option on the command line (without "--"); the Python keyword names it in snake_case.
//
//   inline constexpr Limit kCoulombMaxIterations{"coulomb-max-iterations", 0, 1e8, Limit::Integer};
//   check_limit(kCoulombMaxIterations, o.max_iterations, "coulomb");
//     → Error "coulomb: coulomb-max-iterations must be an integer in 0..100000000, got -5"
#pragma once

#include <limits>
#include <string>
#include <vector>

namespace cshapes {

inline constexpr double kNoLimit = std::numeric_limits<double>::infinity();

struct Limit {
  enum Kind { Integer, Number };
  const char* option;  // the CLI's name without "--" (kebab-case)
  double minimum;
  double maximum = std::numeric_limits<double>::infinity();
  Kind kind = Number;
  bool minimum_open = false;  // (minimum, ...: the minimum itself is refused
  bool maximum_open = false;  // ..., maximum): the maximum itself is refused

  bool holds(double value) const;
  // "an integer in 0..100000000", "an integer >= 1", "a number > 0", "a number in [0, 0.99]",
  // "a number >= 1" (what the messages say after "expected" or "must be").
  std::string describe() const;
  // The CLI help's short form: "0..100000000", ">= 1", "> 0", "in [0, 0.99]".
  std::string brief() const;
};

constexpr Limit integer_limit(const char* option, double minimum,
                              double maximum = std::numeric_limits<double>::infinity()) {
  return Limit{option, minimum, maximum, Limit::Integer};
}
constexpr Limit number_limit(const char* option, double minimum,
                             double maximum = std::numeric_limits<double>::infinity(),
                             bool minimum_open = false, bool maximum_open = false) {
  return Limit{option, minimum, maximum, Limit::Number, minimum_open, maximum_open};
}

// Throws Error "<context>: <option> must be <describe>, got <value>" when value is outside (or NaN).
void check_limit(const Limit& limit, double value, const std::string& context);

// A list option names each item once (`--methods lbo,lbo` and `--poses kid07,kid07` counted twice): throws
// Error "<context>: '<item>' is listed twice" at the first item repeated.
void check_distinct(const std::vector<std::string>& items, const std::string& context);

// A number as the messages print it: shortest form that reads back the same (0.99, 1e-12, 100000000).
std::string format_limit_number(double value);

}  // namespace cshapes
