// Internal to the pose experiment's files: experiments/pose_invariance.cpp (discovery, measurement, the run),
// pose_invariance_parts.cpp (the parts of each class) and pose_invariance_files.cpp (the data files and
// pose.md, written from a PoseInvarianceResult).
#pragma once

#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cshapes/experiments/pose_invariance.h"
#include "cshapes/pipeline/experiment_kit.h"

namespace cshapes::pose_detail {

struct PoseShape {
  std::string name, class_name, path;
  Mesh mesh;
  std::vector<int> vts;  // TOSCA: the sample list of corres/NAME.vts
};

struct PosePair {
  int a = 0, b = 0;         // shape indices
  std::vector<int> va, vb;  // corresponding vertices (0-based), equal lengths
};

// Per shape, per input vertex: its part (−1: unknown). Each class's parts are found on its first pose and
// carried to the other poses through the pairs with the first pose (every correspondence of the pair, not
// only the kept samples). result.classes gets one entry per class.
std::vector<std::vector<int>> find_parts(const PoseInvarianceOptions& o, const std::vector<PoseShape>& shapes,
                                         const std::vector<PosePair>& pairs, PoseInvarianceResult& result);

// The part of each kept sample of a pair: its vertex's part on a, else on b, else −1.
std::vector<int> sample_parts(const PosePair& p, const std::vector<size_t>& keep,
                              const std::vector<std::vector<int>>& part_of);

// One pair and form: a row per part that has samples (finite residuals), the unassigned ones as part −1.
void add_part_rows(const PosePairRow& pair_row, const Eigen::VectorXd& residuals, const std::vector<int>& parts,
                   PoseInvarianceResult& result);

// Medians over the pairs per class, part and form, in the order of result.classes, parts −1 (when any), 0,
// 1, ..., forms in run order.
void summarise_parts(const std::vector<std::string>& forms, PoseInvarianceResult& result);

// A number in a CSV cell: 6 significant digits; empty when not finite.
inline std::string csv_number(double v, int precision = 6) {
  if (!std::isfinite(v)) return "";
  std::ostringstream s;
  s.precision(precision);
  s << v;
  return s.str();
}

// A geodesic stress for a report: NaN (shown "—") when not measured (−1).
inline double measured_stress(double stress) {
  return stress >= 0 ? stress : NAN;
}

// "all", then each class of a measured shape (failed[i] == 0) in shape order; "all" alone when there is one
// class.
std::vector<std::string> summary_classes(const std::vector<PoseShape>& shapes, const std::vector<char>& failed);

// One form over the pairs and shapes of one class ("all": every class). class_of: shape name → class.
PoseSummaryRow summary_row(const std::string& form, const std::string& class_name,
                           const PoseInvarianceResult& result, const std::map<std::string, std::string>& class_of);

// The forms the run measures: "input" (the meshes themselves), then the options' methods.
inline std::vector<std::string> forms_of_run(const PoseInvarianceOptions& o) {
  std::vector<std::string> forms = {"input"};
  forms.insert(forms.end(), o.methods.begin(), o.methods.end());
  return forms;
}

// The run's label in the CSV files ("default" when none was given).
std::string label_of(const PoseInvarianceOptions& o);

// The CSV files, and the figure's data when a pair was chosen for it.
void write_data_files(const ExperimentFolder& folder, const PoseInvarianceOptions& o,
                      const PoseInvarianceResult& result);

}  // namespace cshapes::pose_detail
