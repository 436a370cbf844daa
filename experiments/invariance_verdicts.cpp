// The invariance experiment's cases, summaries and verdicts (experiments/invariance_experiment.h), from the
// rows a run measured.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "cshapes/experiments/invariance_experiment_detail.h"
#include "cshapes/support/format.h"
#include "cshapes/support/timing.h"

namespace cshapes::invariance_detail {

std::string ExactCase::name(bool words) const {
  if (!is_seeded(transform)) return to_string(transform);
  return to_string(transform) + (words ? " seed " : "-") + std::to_string(seed);
}

std::vector<ExactCase> exact_cases(const InvarianceOptions& o) {
  std::vector<ExactCase> cases;
  for (int k = 0; k < o.seeds; ++k)
    cases.push_back({ExactTransform::Renumber, o.seed + static_cast<std::uint64_t>(k)});
  for (ExactTransform t : exact_transforms())
    if (t != ExactTransform::Renumber) cases.push_back({t, o.seed});
  return cases;
}

std::string factor_text(double factor) {
  std::ostringstream s;
  s << factor;
  return s.str();
}

std::vector<std::string> transformation_names() {
  std::vector<std::string> names;
  for (ExactTransform t : exact_transforms()) names.push_back(to_string(t));
  for (double factor : kInvarianceRemeshFactors) names.push_back("remesh-" + factor_text(factor));
  return names;
}

std::string resolution_text(Index resolution) {
  return resolution == 0 ? "as given" : std::to_string(resolution) + " vertices";
}

namespace {

// A fraction as a percentage for a note: two significant figures ("3.1e-09%"), "0%" for an exact zero.
std::string percent_note(double fraction) {
  if (!std::isfinite(fraction)) return "—";
  return fraction == 0 ? "0%" : significant(100 * fraction, 2) + "%";
}

}  // namespace

std::string case_note(const std::string& shape, Index resolution, const std::vector<InvarianceRow>& rows,
                      const std::vector<std::string>& methods) {
  std::ostringstream line;
  line << "  " << shape << " (" << resolution_text(resolution) << "), largest RMSE exact / remeshed:";
  for (const std::string& m : methods) {
    double exact = NAN, remeshed = NAN;
    for (const InvarianceRow& r : rows) {
      if (r.shape != shape || r.resolution != resolution || r.method != m) continue;
      double& worst = r.exact ? exact : remeshed;
      worst = std::isnan(worst) ? r.rmse : std::max(worst, r.rmse);
    }
    line << " " << m << " " << percent_note(exact) << " / " << percent_note(remeshed) << ";";
  }
  std::string text = line.str();
  text.pop_back();
  return text;
}

namespace {

InvarianceSummaryRow summary_row(const InvarianceResult& result, Index resolution, const std::string& method,
                                 const std::string& transformation) {
  InvarianceSummaryRow s;
  s.resolution = resolution;
  s.method = method;
  s.transformation = transformation;
  s.exact = transformation.rfind("remesh-", 0) != 0;
  std::vector<double> rmse, hausdorff;
  for (const InvarianceRow& r : result.rows)
    if (r.resolution == resolution && r.method == method && r.transformation == transformation) {
      rmse.push_back(r.rmse);
      hausdorff.push_back(r.hausdorff);
    }
  s.count = static_cast<int>(rmse.size());
  if (rmse.empty()) return s;
  s.median_rmse = median(rmse);
  s.max_rmse = *std::max_element(rmse.begin(), rmse.end());
  s.median_hausdorff = median(hausdorff);
  s.max_hausdorff = *std::max_element(hausdorff.begin(), hausdorff.end());
  return s;
}

// One method at one resolution (see the header's verdict).
InvarianceVerdict verdict_at(const InvarianceOptions& o, const InvarianceResult& result, Index resolution,
                             const std::string& method, const MethodTally& tally) {
  InvarianceVerdict v;
  v.resolution = resolution;
  v.method = method;
  std::vector<double> pose_rmse, pose_hausdorff;
  for (const InvariancePosePair& p : result.pose_pairs)
    if (p.resolution == resolution && p.method == method) {
      pose_rmse.push_back(p.rmse);
      pose_hausdorff.push_back(p.hausdorff);
    }
  v.pose_pairs = static_cast<int>(pose_rmse.size());
  if (!pose_rmse.empty()) {
    v.pose_rmse = median(pose_rmse);
    v.pose_hausdorff = median(pose_hausdorff);
  }
  v.tolerance = o.tolerance_floor_percent / 100;
  if (std::isfinite(v.pose_rmse))
    v.tolerance = std::max(v.tolerance, o.tolerance_pose_percent / 100 * v.pose_rmse);
  for (const InvarianceRow& r : result.rows) {
    if (r.resolution != resolution || r.method != method || !r.exact) continue;
    ++v.measured;
    if (std::isnan(v.worst_rmse) || r.rmse > v.worst_rmse || std::isnan(r.rmse)) {
      v.worst_rmse = r.rmse;
      v.worst = r.shape + ", " + r.transformation + (r.seed >= 0 ? " seed " + std::to_string(r.seed) : "");
    }
  }
  v.failed_forms = tally.failed_forms;
  v.missing_forms = tally.missing_forms;
  v.converged_known = tally.converged_known;
  v.not_converged = tally.not_converged;
  if (v.failed_forms > 0) {
    v.verdict = "fail";
    v.reason = std::to_string(v.failed_forms) + " transformed forms failed where the reference's did not";
  } else if (v.measured == 0) {
    v.verdict = "not measured";
    v.reason = v.missing_forms > 0 ? "the forms of the transformed meshes are missing (OUT/forms-needed)"
                                   : "no reference form was computed";
  } else if (!(v.worst_rmse <= v.tolerance)) {
    v.verdict = "fail";
    v.reason = "largest RMSE " + percent_note(v.worst_rmse) + " > tolerance " + percent_note(v.tolerance) +
               " (" + v.worst + ")";
  } else {
    v.verdict = "pass";
  }
  if (v.missing_forms > 0 && v.measured > 0)
    v.reason += (v.reason.empty() ? "" : "; ") + std::to_string(v.missing_forms) +
                " transformed forms missing (OUT/forms-needed), not measured";
  return v;
}

// One method over every resolution: fail when one fails, pass when every measured one passes.
InvarianceVerdict verdict_overall(const std::vector<InvarianceVerdict>& at) {
  InvarianceVerdict v;
  v.resolution = -1;
  v.method = at.front().method;
  std::vector<std::string> failed, unmeasured;
  for (const InvarianceVerdict& r : at) {
    v.measured += r.measured;
    v.failed_forms += r.failed_forms;
    v.missing_forms += r.missing_forms;
    v.converged_known += r.converged_known;
    v.not_converged += r.not_converged;
    v.pose_pairs += r.pose_pairs;
    if (r.measured > 0 && (std::isnan(v.worst_rmse) || r.worst_rmse > v.worst_rmse)) {
      v.worst_rmse = r.worst_rmse;
      v.worst = r.worst + " (" + resolution_text(r.resolution) + ")";
    }
    if (r.verdict == "fail") failed.push_back(resolution_text(r.resolution));
    if (r.verdict == "not measured") unmeasured.push_back(resolution_text(r.resolution));
  }
  auto joined = [](const std::vector<std::string>& items) {
    std::string text;
    for (const std::string& item : items) text += (text.empty() ? "" : ", ") + item;
    return text;
  };
  if (!failed.empty()) {
    v.verdict = "fail";
    v.reason = "fails at " + joined(failed);
  } else if (unmeasured.size() == at.size()) {
    v.verdict = "not measured";
    v.reason = "no reference form was computed";
  } else {
    v.verdict = "pass";
    if (!unmeasured.empty()) v.reason = "not measured at " + joined(unmeasured);
  }
  return v;
}

}  // namespace

void summarise(const InvarianceOptions& o,
               const std::map<std::pair<Index, std::string>, MethodTally>& tallies,
               InvarianceResult& result) {
  result.summary.clear();
  result.verdicts.clear();
  for (Index resolution : o.vertices)
    for (const std::string& method : o.methods)
      for (const std::string& t : transformation_names())
        result.summary.push_back(summary_row(result, resolution, method, t));
  for (const std::string& method : o.methods) {
    std::vector<InvarianceVerdict> at;
    for (Index resolution : o.vertices) {
      const auto found = tallies.find({resolution, method});
      at.push_back(
          verdict_at(o, result, resolution, method, found == tallies.end() ? MethodTally{} : found->second));
    }
    result.verdicts.insert(result.verdicts.end(), at.begin(), at.end());
    result.verdicts.push_back(verdict_overall(at));
  }
}

}  // namespace cshapes::invariance_detail
