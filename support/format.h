// Numbers in text for people (notes, summaries, error messages): a few significant figures, not the six
// decimals of std::to_string. Files keep full precision (support/atomic_file.h, the JSON writers).
#pragma once

#include <cmath>
#include <cstdio>
#include <string>

namespace cshapes {

// x with `digits` significant figures: 1.795905 → "1.8", 0.019503 → "0.0195", 98.553 → "98.6",
// 4677188.9 → "4.68e+06".
inline std::string significant(double x, int digits = 3) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, x);
  return buffer;
}

// A duration with its unit, three significant figures: 5.1342 → "5.13 s", 0.013812 → "0.0138 s". From 1,000 s
// on, whole seconds (4677.3 → "4677 s"): a run's length read at a glance, not "4.68e+03 s".
inline std::string seconds_text(double s) {
  if (std::isfinite(s) && std::abs(s) >= 1000) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.0f s", s);
    return buffer;
  }
  return significant(s) + " s";
}

// A duration in the unit that reads best, three significant figures: 46.81 → "46.8 s", 0.2083 → "208 ms",
// 0.000111 → "111 µs" (a table of times from microseconds to minutes, read without counting zeros).
inline std::string duration_text(double s) {
  if (!std::isfinite(s) || std::abs(s) >= 1) return seconds_text(s);
  if (std::abs(s) >= 1e-3) return significant(1e3 * s) + " ms";
  return significant(1e6 * s) + " µs";
}

// A count with thousands separators: 5000 → "5,000", 22738 → "22,738", -1234 → "-1,234".
inline std::string grouped(long long n) {
  std::string digits = std::to_string(n < 0 ? -n : n), out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return (n < 0 ? "-" : "") + out;
}

// A count with its noun, singular or plural as the count asks, thousands grouped: counted(1, "glue") →
// "1 glue", counted(2, "glue") → "2 glues", counted(2, "vertex", "vertices") → "2 vertices",
// counted(5000, "point") → "5,000 points".
inline std::string counted(long long n, const std::string& singular, const std::string& plural = "") {
  return grouped(n) + " " + (n == 1 ? singular : plural.empty() ? singular + "s" : plural);
}

}  // namespace cshapes
