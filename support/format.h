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

}  // namespace cshapes
