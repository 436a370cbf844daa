#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "cshapes/experiments/pose_invariance_detail.h"
#include "cshapes/geodesics/geodesic_parts.h"
#include "cshapes/support/error.h"
#include "cshapes/support/format.h"
#include "cshapes/support/timing.h"

namespace cshapes::pose_detail {

// Per shape, per input vertex: its part (−1: unknown). Each class's parts are found on its first pose and
// carried to the other poses through the pairs with the first pose (every correspondence of the pair, not
// only the kept samples). result.classes gets one entry per class.
std::vector<std::vector<int>> find_parts(const PoseInvarianceOptions& o, const std::vector<PoseShape>& shapes,
                                         const std::vector<PosePair>& pairs, PoseInvarianceResult& result) {
  std::vector<std::vector<int>> part_of(shapes.size());
  for (size_t i = 0; i < shapes.size(); ++i)
    part_of[i].assign(static_cast<size_t>(shapes[i].mesh.num_vertices()), -1);
  if (!o.parts) return part_of;
  std::map<std::string, size_t> first_of_class;
  for (size_t i = 0; i < shapes.size(); ++i) first_of_class.emplace(shapes[i].class_name, i);
  std::vector<size_t> firsts;
  for (size_t i = 0; i < shapes.size(); ++i)
    if (first_of_class.at(shapes[i].class_name) == i) firsts.push_back(i);
  for (size_t f : firsts) {
    const PoseShape& s = shapes[f];
    PoseClassParts c;
    c.class_name = s.class_name;
    c.shape = s.name;
    try {
      const GeodesicPartsResult parts = geodesic_parts(s.mesh, o.part_finder);
      c.centre = parts.centre;
      c.extremities = parts.extremities;
      c.reach = parts.extremity_reach;
      c.persistence = parts.extremity_persistence;
      c.repair_text = parts.repair_text;
      part_of[f].assign(parts.part.data(), parts.part.data() + parts.part.size());
    } catch (const Error& e) {
      c.problem = e.what();
    }
    say(o.note, c.problem.empty() ? detail::concat("  parts of ", c.class_name, " on ", s.name, ": ",
                                                   c.extremities.size(), " extremities and the core")
                                  : detail::concat("  parts of ", c.class_name, ": none (", c.problem, ")"));
    result.classes.push_back(c);
  }
  for (const PosePair& p : pairs) {
    const size_t f = first_of_class.at(shapes[p.a].class_name);
    if (static_cast<size_t>(p.a) == f)
      for (size_t k = 0; k < p.va.size(); ++k) part_of[p.b][p.vb[k]] = part_of[f][p.va[k]];
    else if (static_cast<size_t>(p.b) == f)
      for (size_t k = 0; k < p.vb.size(); ++k) part_of[p.a][p.va[k]] = part_of[f][p.vb[k]];
  }
  return part_of;
}

// The part of each kept sample of a pair: its vertex's part on a, else on b, else −1.
std::vector<int> sample_parts(const PosePair& p, const std::vector<size_t>& keep,
                              const std::vector<std::vector<int>>& part_of) {
  std::vector<int> parts(keep.size(), -1);
  for (size_t k = 0; k < keep.size(); ++k) {
    const int on_a = part_of[p.a][p.va[keep[k]]];
    parts[k] = on_a >= 0 ? on_a : part_of[p.b][p.vb[keep[k]]];
  }
  return parts;
}

// One pair and form: a row per part that has samples (finite residuals), the unassigned ones as part −1.
void add_part_rows(const PosePairRow& pair_row, const Eigen::VectorXd& residuals,
                   const std::vector<int>& parts, PoseInvarianceResult& result) {
  std::map<int, std::pair<double, int>> squares;  // part → (Σ residual², samples)
  for (Index k = 0; k < residuals.size(); ++k) {
    if (!std::isfinite(residuals[k])) continue;
    auto& [sum, count] = squares[parts[static_cast<size_t>(k)]];
    sum += residuals[k] * residuals[k];
    ++count;
  }
  for (const auto& [part, sum_count] : squares) {
    PosePartRow row;
    row.a = pair_row.a;
    row.b = pair_row.b;
    row.class_name = pair_row.class_name;
    row.form = pair_row.form;
    row.part = part;
    row.samples = sum_count.second;
    row.rms = std::sqrt(sum_count.first / sum_count.second);
    result.parts.push_back(row);
  }
}

// Medians over the pairs per class, part and form, in the order of result.classes, parts −1 (when any), 0,
// 1, ..., forms in run order.
void summarise_parts(const std::vector<std::string>& forms, PoseInvarianceResult& result) {
  for (const PoseClassParts& c : result.classes) {
    std::set<int> parts;
    for (const PosePartRow& r : result.parts)
      if (r.class_name == c.class_name) parts.insert(r.part);
    for (int part : parts)
      for (const std::string& f : forms) {
        PosePartSummaryRow row;
        row.class_name = c.class_name;
        row.form = f;
        row.part = part;
        std::vector<double> rms, samples;
        for (const PosePartRow& r : result.parts)
          if (r.class_name == c.class_name && r.form == f && r.part == part) {
            rms.push_back(r.rms);
            samples.push_back(r.samples);
          }
        row.pairs = static_cast<int>(rms.size());
        row.median_rms = rms.empty() ? NAN : median(rms);
        row.median_samples = samples.empty() ? 0 : median(samples);
        result.part_summary.push_back(row);
      }
  }
}

}  // namespace cshapes::pose_detail
