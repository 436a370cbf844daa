// FormQuality (canon/form_quality.h) as JSON, for the summaries of `canon --json` and the canonical-form
// cache.
#pragma once

#include <cmath>
#include <nlohmann/json.hpp>

#include "cshapes/canon/form_quality.h"

namespace cshapes {

inline nlohmann::json form_quality_json(const FormQuality& q) {
  // NaN is not JSON: a non-finite statistic (a form with NaN coordinates) is written as null.
  auto number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
  return {{"ok", q.ok},
          {"max_stretch", number(q.max_stretch)},
          {"p99_stretch", number(q.p99_stretch)},
          {"mean_stretch", number(q.mean_stretch)},
          {"min_stretch", number(q.min_stretch)},
          {"max_distance_diagonals", number(q.max_distance)},
          {"runaway_vertices", q.runaway_vertices},
          {"far_vertices", q.far_vertices},
          {"stretched_vertices", q.stretched_vertices},
          {"detached_vertices", q.detached_vertices},
          {"coincident_vertices", q.coincident_vertices},
          {"runaway_examples", q.runaway_examples},
          {"description", q.description}};
}

}  // namespace cshapes
