// The validators of option values and the option adders that use them (cli/command.h): one message per
// refusal, "expected ..., got '...'", and the usage exit code.
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "cli/command.h"
#include "cshapes/mesh/remesh.h"
#include "cshapes/support/distance_matrix.h"
#include "cshapes/support/error.h"
#include "cshapes/support/format.h"
#include "cshapes/pipeline/resampled_dataset.h"

namespace cshapes::cli {

namespace {

// Parses a whole string as a number: "12", "-3", "1e-3"; false for "", "abc", "12abc".
bool parse_number(const std::string& text, double& value) {
  if (text.empty() || std::isspace(static_cast<unsigned char>(text[0]))) return false;
  char* end = nullptr;
  errno = 0;
  value = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && !std::isnan(value);
}
bool parse_integer(const std::string& text, long long& value) {
  if (text.empty() || std::isspace(static_cast<unsigned char>(text[0]))) return false;
  char* end = nullptr;
  errno = 0;
  value = std::strtoll(text.c_str(), &end, 10);
  return end == text.c_str() + text.size() && errno == 0;
}
std::string integer_range(long long minimum, long long maximum) {
  if (minimum == LLONG_MIN && maximum == LLONG_MAX) return "an integer";
  if (maximum == LLONG_MAX) return "an integer >= " + std::to_string(minimum);
  return "an integer in " + std::to_string(minimum) + ".." + std::to_string(maximum);
}
std::string format_number(double x) {
  std::ostringstream out;
  out << x;
  return out.str();
}

}  // namespace

std::string in_quotes(const std::string& text) {
  return "'" + text + "'";
}

CLI::Validator integer_in(long long minimum, long long maximum) {
  const std::string expected = integer_range(minimum, maximum);
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        long long value = 0;
        if (!parse_integer(text, value) || value < minimum || value > maximum)
          return "expected " + expected + ", got " + in_quotes(text);
        return {};
      },
      maximum == LLONG_MAX ? ">= " + std::to_string(minimum)
                           : std::to_string(minimum) + ".." + std::to_string(maximum));
}
CLI::Validator integer_at_least(long long minimum) {
  return integer_in(minimum, LLONG_MAX);
}

int integer_or_word(const std::string& option, const std::string& text, long long minimum, long long maximum,
                    const std::string& word, int word_value) {
  if (text == word) return word_value;
  long long value = 0;
  if (!parse_integer(text, value) || value < minimum || value > maximum)
    usage_fail(option, ": expected ", integer_range(minimum, maximum), " or '", word, "', got ",
               in_quotes(text));
  return static_cast<int>(value);
}

namespace {
CLI::Validator number_check(double minimum, double maximum, bool open_below, const std::string& range) {
  const std::string expected = range.empty() ? "a number" : "a number " + range;
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double value = 0;
        if (!parse_number(text, value) || !std::isfinite(value) || value < minimum || value > maximum ||
            (open_below && value == minimum))
          return "expected " + expected + ", got " + in_quotes(text);
        return {};
      },
      range);
}
}  // namespace

CLI::Validator number_at_least(double minimum) {
  return number_check(minimum, HUGE_VAL, false, ">= " + format_number(minimum));
}
CLI::Validator number_above(double minimum) {
  return number_check(minimum, HUGE_VAL, true, "> " + format_number(minimum));
}
CLI::Validator number_in(double minimum, double maximum) {
  if (std::isinf(minimum) && std::isinf(maximum)) return number_check(minimum, maximum, false, "");
  return number_check(minimum, maximum, false,
                      "in [" + format_number(minimum) + ", " + format_number(maximum) + "]");
}
CLI::Validator within(const Limit& limit) {
  return CLI::Validator(
      [limit](std::string& text) -> std::string {
        bool ok = false;
        if (limit.kind == Limit::Integer) {
          long long value = 0;
          ok = parse_integer(text, value) && limit.holds(static_cast<double>(value));
        } else {
          double value = 0;
          ok = parse_number(text, value) && std::isfinite(value) && limit.holds(value);
        }
        return ok ? std::string() : "expected " + limit.describe() + ", got " + in_quotes(text);
      },
      limit.brief());
}
CLI::Option* add_declared_flag(CLI::App& app, const OptionDeclaration& declaration, bool& value) {
  return app.add_flag(declaration.flag, value, option_help(declaration, OptionSkin::Cli));
}

CLI::Validator one_of(const std::vector<std::string>& names) {
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        if (std::find(names.begin(), names.end(), text) != names.end()) return {};
        return "expected one of " + list + ", got " + in_quotes(text);
      },
      "{" + list + "}");
}

void add_resample_option(CLI::App& app, Index& vertices) {
  add_declared(app, kResampleOption, vertices)
      ->capture_default_str()
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            long long n = 0;
            if (!parse_integer(text, n) || (n != 0 && (n < 4 || n > 100000000)))
              return "expected 0 (off) or a vertex count from 4 to 100000000, got " + in_quotes(text);
            // A remesh of N vertices that cannot fit is a usage error in every command (exit 2), before
            // any work: the library's own check (pipeline/resampled_dataset.h) is the same figure.
            if (n > 0) {
              try {
                require_memory(remesh_memory_bytes(static_cast<Index>(n)),
                               "remeshing to " + std::to_string(n) + " vertices");
              } catch (const Error& e) {
                return e.what();
              }
            }
            return {};
          },
          "0 or 4..100000000"));
}

}  // namespace cshapes::cli
