#include "cshapes/support/option_limits.h"

#include <cmath>
#include <cstdio>
#include <set>

#include "cshapes/support/error.h"

namespace cshapes {

bool Limit::holds(double value) const {
  if (std::isnan(value)) return false;
  if (kind == Integer && value != std::floor(value)) return false;
  if (minimum_open ? !(value > minimum) : !(value >= minimum)) return false;
  if (maximum_open ? !(value < maximum) : !(value <= maximum)) return false;
  return true;
}

std::string format_limit_number(double value) {
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  if (value == std::floor(value) && std::abs(value) < 1e15)
    return std::to_string(static_cast<long long>(value));
  char text[32];
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, value);
    if (std::strtod(text, nullptr) == value) break;
  }
  return text;
}

std::string Limit::brief() const {
  const bool bounded = std::isfinite(maximum);
  const std::string lo = format_limit_number(minimum), hi = format_limit_number(maximum);
  if (!bounded) return (minimum_open ? "> " : ">= ") + lo;
  if (kind == Integer) return lo + ".." + hi;
  return "in " + std::string(minimum_open ? "(" : "[") + lo + ", " + hi + (maximum_open ? ")" : "]");
}

std::string Limit::describe() const {
  return (kind == Integer ? "an integer " : "a number ") + brief();
}

void check_limit(const Limit& limit, double value, const std::string& context) {
  if (limit.holds(value)) return;
  fail(context, context.empty() ? "" : ": ", limit.option, " must be ", limit.describe(), ", got ",
       format_limit_number(value));
}

void check_distinct(const std::vector<std::string>& items, const std::string& context) {
  std::set<std::string> seen;
  for (const std::string& item : items)
    if (!seen.insert(item).second) fail(context, context.empty() ? "" : ": ", "'", item, "' is listed twice");
}

}  // namespace cshapes
