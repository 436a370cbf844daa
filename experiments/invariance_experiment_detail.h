// Internal to the invariance experiment's files: experiments/invariance_experiment.cpp (the run) and
// invariance_experiment_files.cpp (summaries, verdicts, the data files and invariance.md from a result).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "cshapes/experiments/invariance_experiment.h"
#include "cshapes/experiments/invariance_transforms.h"
#include "cshapes/pipeline/experiment_kit.h"

namespace cshapes::invariance_detail {

// One exact transformation of a reference mesh with its seed.
struct ExactCase {
  ExactTransform transform = ExactTransform::Renumber;
  std::uint64_t seed = 0;
  // "renumber-2" (a mesh's name, words = false) or "renumber seed 2" (a report's); the scales: "scale-1e3".
  std::string name(bool words) const;
};
// The run's exact cases, in CSV order: options.seeds renumberings (seed, seed + 1, ...), then the face order,
// the rigid motion, the two scales and the jitter (seed: options.seed).
std::vector<ExactCase> exact_cases(const InvarianceOptions& options);

// The transformations in CSV and figure order: the exact ones, then "remesh-0.8", "remesh-1.2".
std::vector<std::string> transformation_names();
// 0.8 → "0.8".
std::string factor_text(double factor);
// "as given" for 0, "1000 vertices".
std::string resolution_text(Index resolution);

// What the verdict of one method at one resolution counts besides the rows.
struct MethodTally {
  int failed_forms = 0;     // transformed forms that failed where the reference form did not
  int missing_forms = 0;    // transformed forms a forms-door method does not have (OUT/forms-needed)
  int converged_known = 0;  // forms with a convergence test
  int not_converged = 0;
  void count_convergence(int converged) {
    if (converged < 0) return;
    ++converged_known;
    not_converged += converged == 0;
  }
};

// The progress line of one shape at one resolution from its rows: each method's largest exact RMSE and
// remesh RMSE, in % of the diagonal.
std::string case_note(const std::string& shape, Index resolution, const std::vector<InvarianceRow>& rows,
                      const std::vector<std::string>& methods);

// result.summary and result.verdicts from result.rows, result.pose_pairs and the tallies.
void summarise(const InvarianceOptions& options,
               const std::map<std::pair<Index, std::string>, MethodTally>& tallies, InvarianceResult& result);

// invariance.csv, invariance_pose.csv, invariance_summary.csv and invariance.json.
void write_data_files(const ExperimentFolder& folder, const InvarianceOptions& options,
                      const InvarianceResult& result);

}  // namespace cshapes::invariance_detail
