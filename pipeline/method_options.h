// The options of the canonical-form methods, each declared once, in its method's file, as a MethodOption: its
// name, type, limit or choices, help, the CanonicalFormOptions fields it sets, and how it reads and writes
// them. Everything else is derived from these declarations: the CLI's option groups (`cshapes canon --help`),
// Python's keywords and their checks (canonical_form(), coulomb()), the type stub (scripts/make_stub.py), the
// refusal of an option the method does not read (naming the methods that read it), and the docs' option
// tables. The name is Python's keyword, snake_case ("step_factor"); the CLI's flag is the same in kebab-case
// ("--step-factor") unless `flag` names another.
//
//   MethodOption o = number_option("step_factor", "the factor of the step rule (paper: 0.1)",
//                                  coulomb_limits::kStepFactor, {"coulomb"},
//                                  [](CanonicalFormOptions& c) -> double& { return c.coulomb.step_factor; });
//
// An option read by several methods (--geodesics by cmds, smacof and spectral-mds) is one declaration, listed
// by each: options are the same option when their names are. A method registered outside the library keeps
// its values in CanonicalFormOptions::extra (option_in_extra), so it needs no field of its own.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "cshapes/support/option_limits.h"

namespace cshapes {

struct CanonicalFormOptions;

// An option's value: a flag, an integer, a number, or a text (a choice's name, a path).
using OptionValue = std::variant<bool, long long, double, std::string>;

struct MethodOption {
  enum class Type { Integer, Number, Choice, Path };
  std::string name;  // Python's keyword, snake_case
  std::string flag;  // the CLI's option, "--" + kebab-case name unless set
  Type type = Type::Number;
  std::string help;                  // one line: --help, docstrings, the stub, the docs
  std::optional<Limit> limit;        // Integer, Number: the library's limit (support/option_limits.h)
  std::vector<std::string> choices;  // Choice: the names, in order
  // The top-level CanonicalFormOptions fields (for_each_field's names) it sets: the fields a method that
  // lists this option reads (its cache key covers them).
  std::vector<std::string> fields;
  std::function<OptionValue(const CanonicalFormOptions&)> get;  // its value; the default: get of {}
  std::function<void(CanonicalFormOptions&, const OptionValue&)> set;  // a value already checked
  // Read only when another option (by name) has one of `values` (a choice), or is not 0 (values empty):
  // given otherwise, it is refused by name ("--fixed-step applies to --step-rule fixed only"; with a phrase:
  // "--tear-after applies only when tearing (--tear-fraction > 0)").
  struct Condition {
    std::string option;
    std::vector<std::string> values;
    std::string phrase;
  };
  std::optional<Condition> applies_when;
  bool python = true;  // also a keyword of canonical_form() (false: a file only `cshapes canon` reads)
  // One of the single settings a preset covers: the CLI's help lists it under --help-all only.
  bool advanced = false;
};

// How a front end names options in messages, and what it was given.
struct OptionFace {
  bool cli = false;          // "--step-rule fixed" (CLI) or "step_rule='fixed'" (Python)
  bool single_mesh = true;   // one mesh (`cshapes canon`, Python): options that need one are allowed
  std::function<bool(const std::string& name)> given;  // by MethodOption::name
  std::string name(const MethodOption& option) const;   // "--step-factor" or "step_factor"
  std::string value(const MethodOption& option, const std::string& text) const;  // "fixed" or "'fixed'"
};

// "--" + name in kebab-case: the CLI flag of an option declared without one.
std::string option_flag(const std::string& name);
// The option's flag (its own, or option_flag of its name).
std::string cli_flag(const MethodOption& option);
// A value as its option's text: integers exactly, numbers in their shortest round-trip form, texts as they
// are (the CLI's default shown in --help, the stub's default).
std::string option_text(const OptionValue& value);
// The CLI's text for the option's type (already checked by its validator: limit or choices).
OptionValue parse_option_text(const MethodOption& option, const std::string& text);
// The option's default: its value in CanonicalFormOptions{}.
OptionValue option_default(const MethodOption& option);
// Throws cshapes::Error (worded for `face`) when the option is given but its
// applies_when does not hold in `options`.
void check_applies_when(const MethodOption& option, const std::vector<const MethodOption*>& all,
                        const CanonicalFormOptions& options, const OptionFace& face);

// An option with its name, type, help and fields; the rest (flag, limit, choices, get, set, applies_when) set
// after.
MethodOption option_of(std::string name, MethodOption::Type type, std::string help,
                       std::vector<std::string> fields = {});

// Builders for options bound to a field: `ref` returns the field in the options given.
template <class T>
using FieldRef = std::function<T&(CanonicalFormOptions&)>;
namespace detail {
template <class T>
struct Given {  // a parameter whose type the call names (integer_option<int>), not deduced from a lambda
  using type = T;
};
}  // namespace detail
template <class Int>
MethodOption integer_option(std::string name, std::string help, const Limit& limit,
                            std::vector<std::string> fields, typename detail::Given<FieldRef<Int>>::type ref) {
  MethodOption o = option_of(std::move(name), MethodOption::Type::Integer, std::move(help), std::move(fields));
  o.limit = limit;
  o.get = [ref](const CanonicalFormOptions& c) {
    return OptionValue(static_cast<long long>(ref(const_cast<CanonicalFormOptions&>(c))));
  };
  o.set = [ref](CanonicalFormOptions& c, const OptionValue& v) {
    ref(c) = static_cast<Int>(std::get<long long>(v));
  };
  return o;
}
MethodOption number_option(std::string name, std::string help, const Limit& limit,
                           std::vector<std::string> fields, FieldRef<double> ref);
// An enum option: names in order, to_string and parse as the enum's own functions.
template <class Enum>
MethodOption choice_option(std::string name, std::string help, std::vector<std::string> choices,
                           std::vector<std::string> fields, typename detail::Given<FieldRef<Enum>>::type ref,
                           std::string (*to_text)(Enum), Enum (*parse)(const std::string&)) {
  MethodOption o = option_of(std::move(name), MethodOption::Type::Choice, std::move(help), std::move(fields));
  o.choices = std::move(choices);
  o.get = [ref, to_text](const CanonicalFormOptions& c) {
    return OptionValue(to_text(ref(const_cast<CanonicalFormOptions&>(c))));
  };
  o.set = [ref, parse](CanonicalFormOptions& c, const OptionValue& v) {
    ref(c) = parse(std::get<std::string>(v));
  };
  return o;
}
// An option whose value is kept in CanonicalFormOptions::extra under its name (a method registered outside
// the library): `fallback` is its default.
MethodOption option_in_extra(MethodOption option, OptionValue fallback);
// A value of CanonicalFormOptions::extra as its option's type (its default when not set): what a method
// registered outside the library reads.
double extra_number(const CanonicalFormOptions& options, const MethodOption& option);
long long extra_integer(const CanonicalFormOptions& options, const MethodOption& option);
std::string extra_text(const CanonicalFormOptions& options, const MethodOption& option);

}  // namespace cshapes
