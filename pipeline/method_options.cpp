#include "cshapes/pipeline/method_options.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "cshapes/pipeline/canonical_forms.h"
#include "cshapes/support/error.h"

namespace cshapes {

std::string option_flag(const std::string& name) {
  std::string flag = "--" + name;
  std::replace(flag.begin(), flag.end(), '_', '-');
  return flag;
}

std::string cli_flag(const MethodOption& option) {
  return option.flag.empty() ? option_flag(option.name) : option.flag;
}

std::string OptionFace::name(const MethodOption& option) const {
  return cli ? cli_flag(option) : option.name;
}

std::string OptionFace::value(const MethodOption&, const std::string& text) const {
  return cli ? text : "'" + text + "'";
}

std::string option_text(const OptionValue& value) {
  if (const bool* b = std::get_if<bool>(&value)) return *b ? "true" : "false";
  if (const long long* i = std::get_if<long long>(&value)) return std::to_string(*i);
  if (const double* x = std::get_if<double>(&value)) return format_limit_number(*x);
  return std::get<std::string>(value);
}

OptionValue parse_option_text(const MethodOption& option, const std::string& text) {
  switch (option.type) {
    case MethodOption::Type::Integer: return OptionValue(std::stoll(text));
    case MethodOption::Type::Number: return OptionValue(std::strtod(text.c_str(), nullptr));
    case MethodOption::Type::Choice:
    case MethodOption::Type::Path: return OptionValue(text);
  }
  return OptionValue(text);
}

OptionValue option_default(const MethodOption& option) {
  return option.get(CanonicalFormOptions{});
}

namespace {

// Whether a condition's option has one of its values (or, with none listed, is not 0).
bool condition_holds(const MethodOption::Condition& condition, const OptionValue& value) {
  if (condition.values.empty()) {
    if (const long long* i = std::get_if<long long>(&value)) return *i != 0;
    if (const double* x = std::get_if<double>(&value)) return *x != 0;
    return !option_text(value).empty();
  }
  const std::string text = option_text(value);
  return std::find(condition.values.begin(), condition.values.end(), text) != condition.values.end();
}

}  // namespace

void check_applies_when(const MethodOption& option, const std::vector<const MethodOption*>& all,
                        const CanonicalFormOptions& options, const OptionFace& face) {
  if (!option.applies_when || !face.given(option.name)) return;
  const MethodOption::Condition& condition = *option.applies_when;
  const auto other = std::find_if(all.begin(), all.end(),
                                  [&](const MethodOption* o) { return o->name == condition.option; });
  CSHAPES_REQUIRE(other != all.end(), option.name, ": its condition names an unknown option '",
                  condition.option, "'");
  if (condition_holds(condition, (*other)->get(options))) return;
  const std::string other_name = face.name(**other);
  if (condition.values.empty())
    fail(face.name(option), " applies only ", condition.phrase, " (", other_name, " > 0)");
  std::string values;
  for (size_t k = 0; k < condition.values.size(); ++k)
    values += (k == 0 ? "" : k + 1 == condition.values.size() ? " or " : ", ") +
              face.value(**other, condition.values[k]);
  fail(face.name(option), " applies to ", other_name, face.cli ? " " : "=", values, " only");
}

MethodOption option_of(std::string name, MethodOption::Type type, std::string help,
                       std::vector<std::string> fields) {
  MethodOption o;
  o.name = std::move(name);
  o.type = type;
  o.help = std::move(help);
  o.fields = std::move(fields);
  return o;
}

MethodOption number_option(std::string name, std::string help, const Limit& limit,
                           std::vector<std::string> fields, FieldRef<double> ref) {
  MethodOption o = option_of(std::move(name), MethodOption::Type::Number, std::move(help), std::move(fields));
  o.limit = limit;
  o.get = [ref](const CanonicalFormOptions& c) { return OptionValue(ref(const_cast<CanonicalFormOptions&>(c))); };
  o.set = [ref](CanonicalFormOptions& c, const OptionValue& v) { ref(c) = std::get<double>(v); };
  return o;
}

MethodOption option_in_extra(MethodOption option, OptionValue fallback) {
  option.fields = {"extra"};
  const std::string name = option.name;
  const MethodOption::Type type = option.type;
  option.get = [name, type, fallback](const CanonicalFormOptions& c) {
    const auto at = c.extra.find(name);
    if (at == c.extra.end()) return fallback;
    MethodOption typed;
    typed.type = type;
    return parse_option_text(typed, at->second);
  };
  option.set = [name](CanonicalFormOptions& c, const OptionValue& v) {
    c.extra[name] = option_text(v);  // numbers in their shortest round-trip form
  };
  return option;
}

double extra_number(const CanonicalFormOptions& options, const MethodOption& option) {
  const OptionValue v = option.get(options);
  if (const long long* i = std::get_if<long long>(&v)) return static_cast<double>(*i);
  return std::get<double>(v);
}

long long extra_integer(const CanonicalFormOptions& options, const MethodOption& option) {
  return std::get<long long>(option.get(options));
}

std::string extra_text(const CanonicalFormOptions& options, const MethodOption& option) {
  return option_text(option.get(options));
}

}  // namespace cshapes
