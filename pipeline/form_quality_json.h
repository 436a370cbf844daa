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

// The inverse, for a form read back from the cache: null statistics are NaN again.
inline FormQuality form_quality_from_json(const nlohmann::json& j) {
  auto number = [&j](const char* key) {
    return j.contains(key) && j[key].is_number() ? j[key].get<double>() : std::nan("");
  };
  FormQuality q;
  q.ok = j.value("ok", false);
  q.max_stretch = number("max_stretch");
  q.p99_stretch = number("p99_stretch");
  q.mean_stretch = number("mean_stretch");
  q.min_stretch = number("min_stretch");
  q.max_distance = number("max_distance_diagonals");
  q.runaway_vertices = j.value("runaway_vertices", Index(0));
  q.far_vertices = j.value("far_vertices", Index(0));
  q.stretched_vertices = j.value("stretched_vertices", Index(0));
  q.detached_vertices = j.value("detached_vertices", Index(0));
  q.coincident_vertices = j.value("coincident_vertices", Index(0));
  q.runaway_examples = j.value("runaway_examples", std::vector<Index>());
  q.description = j.value("description", std::string());
  return q;
}

}  // namespace cshapes
