// Numbers in text for people (notes, summaries, error messages): a few significant figures, not the six
// decimals of std::to_string. Files keep full precision (core/atomic_file.h, the JSON writers).
#pragma once

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

}  // namespace cshapes
