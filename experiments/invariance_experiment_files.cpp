// The invariance experiment's files (experiments/invariance_experiment.h): the CSV files and invariance.json
// written by the run, invariance.md written from the result alone.
#include <algorithm>
#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cshapes/experiments/invariance_experiment_detail.h"
#include "cshapes/pipeline/outside_methods.h"
#include "cshapes/support/csv.h"
#include "cshapes/support/format.h"
#include "cshapes/experiments/figures.h"

namespace cshapes {

using invariance_detail::resolution_text;
using invariance_detail::transformation_names;

namespace {

// A fraction in a CSV cell as a percentage: 6 significant digits; empty when not finite.
std::string csv_number(double value) {
  if (!std::isfinite(value)) return "";
  std::ostringstream s;
  s.precision(4);
  s << value;
  return s.str();
}

std::string csv_percent(double fraction) {
  if (!std::isfinite(fraction)) return "";
  std::ostringstream s;
  s.precision(6);
  s << 100 * fraction;
  return s.str();
}

// A fraction in a report as a percentage: two significant figures ("3.1e-09%"), "0%" for an exact zero, "—"
// when not measured.
std::string percent_cell(double fraction) {
  if (!std::isfinite(fraction)) return "—";
  return fraction == 0 ? "0%" : significant(100 * fraction, 2) + "%";
}

nlohmann::json percent_json(double fraction) {
  return std::isfinite(fraction) ? nlohmann::json(100 * fraction) : nlohmann::json(nullptr);
}

std::string method_title(const std::string& method) {
  return canonical_form_method_title(method);
}

const InvarianceSummaryRow* summary_of(const InvarianceResult& r, Index resolution, const std::string& method,
                                       const std::string& transformation) {
  for (const InvarianceSummaryRow& s : r.summary)
    if (s.resolution == resolution && s.method == method && s.transformation == transformation) return &s;
  return nullptr;
}

const InvarianceVerdict& verdict_of(const InvarianceResult& r, Index resolution, const std::string& method) {
  for (const InvarianceVerdict& v : r.verdicts)
    if (v.resolution == resolution && v.method == method) return v;
  fail("experiment invariance: no verdict for ", method, " at ", resolution);
}

void write_rows_csv(const ExperimentFolder& folder, const InvarianceResult& result) {
  std::ostringstream csv;
  csv << "resolution,shape,method,transformation,group,seed,vertices,rmse_percent,hausdorff_percent,"
         "converged,"
         "reference_converged,seconds\n";
  auto status = [](int c) { return c < 0 ? std::string() : std::to_string(c); };
  for (const InvarianceRow& r : result.rows)
    csv << r.resolution << "," << csv_field(r.shape) << "," << csv_field(r.method) << "," << r.transformation
        << "," << (r.exact ? "exact" : "remesh") << "," << (r.seed >= 0 ? std::to_string(r.seed) : "") << ","
        << r.vertices << "," << csv_percent(r.rmse) << "," << csv_percent(r.hausdorff) << ","
        << status(r.converged) << "," << status(r.reference_converged) << "," << csv_number(r.seconds)
        << "\n";
  folder.write_text("invariance.csv", csv.str());
}

void write_pose_csv(const ExperimentFolder& folder, const InvarianceResult& result) {
  std::ostringstream csv;
  csv << "resolution,method,class,a,b,rmse_percent,hausdorff_percent\n";
  for (const InvariancePosePair& p : result.pose_pairs)
    csv << p.resolution << "," << csv_field(p.method) << "," << csv_field(p.class_name) << ","
        << csv_field(p.a) << "," << csv_field(p.b) << "," << csv_percent(p.rmse) << ","
        << csv_percent(p.hausdorff) << "\n";
  folder.write_text("invariance_pose.csv", csv.str());
}

void write_summary_csv(const ExperimentFolder& folder, const InvarianceResult& result) {
  std::ostringstream csv;
  csv << "resolution,method,transformation,group,count,median_rmse_percent,max_rmse_percent,"
         "median_hausdorff_percent,max_hausdorff_percent,pose_rmse_percent,tolerance_percent,within_"
         "tolerance\n";
  for (const InvarianceSummaryRow& s : result.summary) {
    const InvarianceVerdict& v = verdict_of(result, s.resolution, s.method);
    csv << s.resolution << "," << csv_field(s.method) << "," << s.transformation << ","
        << (s.exact ? "exact" : "remesh") << "," << s.count << "," << csv_percent(s.median_rmse) << ","
        << csv_percent(s.max_rmse) << "," << csv_percent(s.median_hausdorff) << ","
        << csv_percent(s.max_hausdorff) << "," << csv_percent(v.pose_rmse) << "," << csv_percent(v.tolerance)
        << "," << (s.exact && s.count > 0 ? (s.max_rmse <= v.tolerance ? "1" : "0") : "") << "\n";
  }
  folder.write_text("invariance_summary.csv", csv.str());
}

nlohmann::json verdict_json(const InvarianceVerdict& v) {
  return {{"resolution", v.resolution < 0 ? nlohmann::json("all") : nlohmann::json(v.resolution)},
          {"method", v.method},
          {"title", method_title(v.method)},
          {"verdict", v.verdict},
          {"reason", v.reason},
          {"measured", v.measured},
          {"worst_rmse_percent", percent_json(v.worst_rmse)},
          {"worst", v.worst},
          {"pose_pairs", v.pose_pairs},
          {"pose_rmse_percent", percent_json(v.pose_rmse)},
          {"pose_hausdorff_percent", percent_json(v.pose_hausdorff)},
          {"tolerance_percent", percent_json(v.tolerance)},
          {"failed_forms", v.failed_forms},
          {"missing_forms", v.missing_forms},
          {"converged_known", v.converged_known},
          {"not_converged", v.not_converged}};
}

// The verdicts: a row per method, a column per resolution and "all".
std::string verdicts_markdown(const InvarianceResult& r) {
  std::ostringstream md;
  md << "| method |";
  for (Index n : r.resolutions) md << " " << resolution_text(n) << " |";
  md << " all |\n| --- |";
  for (size_t k = 0; k <= r.resolutions.size(); ++k) md << " --- |";
  md << "\n";
  for (const std::string& m : r.methods) {
    md << "| " << method_title(m) << " |";
    for (Index n : r.resolutions) {
      const InvarianceVerdict& v = verdict_of(r, n, m);
      md << " **" << v.verdict << "**";
      if (v.failed_forms > 0)
        md << " (" << v.failed_forms << (v.failed_forms == 1 ? " form" : " forms") << " failed";
      if (v.measured > 0)
        md << (v.failed_forms > 0 ? "; " : " (") << percent_cell(v.worst_rmse)
           << (v.worst_rmse <= v.tolerance ? " ≤ " : " > ") << percent_cell(v.tolerance);
      md << (v.measured > 0 || v.failed_forms > 0 ? ")" : "") << " |";
    }
    const InvarianceVerdict& all = verdict_of(r, -1, m);
    md << " **" << all.verdict << "**" << (all.reason.empty() ? "" : " (" + all.reason + ")") << " |\n";
  }
  return md.str();
}

// One resolution: the exact transformations' largest RMSE and Hausdorff per method, the pose variation, the
// tolerance; then the remeshes apart.
std::string resolution_markdown(const InvarianceResult& r, Index n) {
  std::ostringstream md;
  md << "\n## " << (n == 0 ? "Shapes as given" : "Remeshed to about " + std::to_string(n) + " vertices")
     << "\n\n";
  std::vector<std::string> exact, remesh;
  for (const std::string& t : transformation_names())
    (t.rfind("remesh-", 0) == 0 ? remesh : exact).push_back(t);
  for (const char* measure : {"RMSE", "Hausdorff"}) {
    const bool rmse = std::string(measure) == "RMSE";
    md << "Largest " << measure << " over the shapes" << (rmse ? " and seeds" : "") << " (% of the diagonal)"
       << (rmse ? "; the pose variation and tolerance beside it:" : ":") << "\n\n| method |";
    for (const std::string& t : exact) md << " " << t << " |";
    md << (rmse ? " pose variation | tolerance | verdict |\n" : "\n") << "| --- |";
    for (size_t k = 0; k < exact.size() + (rmse ? 3 : 0); ++k) md << " ---: |";
    md << "\n";
    for (const std::string& m : r.methods) {
      md << "| " << method_title(m) << " |";
      for (const std::string& t : exact) {
        const InvarianceSummaryRow* s = summary_of(r, n, m, t);
        md << " " << percent_cell(s ? (rmse ? s->max_rmse : s->max_hausdorff) : NAN) << " |";
      }
      const InvarianceVerdict& v = verdict_of(r, n, m);
      if (rmse)
        md << " " << percent_cell(v.pose_rmse)
           << (v.pose_pairs ? " (" + std::to_string(v.pose_pairs) + (v.pose_pairs == 1 ? " pair)" : " pairs)")
                            : "")
           << " | " << percent_cell(v.tolerance) << " | " << v.verdict << " |";
      md << "\n";
    }
    md << "\n";
  }
  md << "Remeshed (reported apart, no verdict: a remesh should change the form little, not nothing): RMSE "
        "and "
        "Hausdorff after ICP, median / largest over the shapes (% of the diagonal), and the median RMSE over "
        "the pose variation:\n\n| method |";
  for (const std::string& t : remesh)
    md << " " << t << " RMSE | " << t << " Hausdorff | " << t << " / pose |";
  md << "\n| --- |";
  for (size_t k = 0; k < 3 * remesh.size(); ++k) md << " ---: |";
  md << "\n";
  for (const std::string& m : r.methods) {
    const InvarianceVerdict& v = verdict_of(r, n, m);
    md << "| " << method_title(m) << " |";
    for (const std::string& t : remesh) {
      const InvarianceSummaryRow* s = summary_of(r, n, m, t);
      const bool has = s && s->count > 0;
      md << " " << (has ? percent_cell(s->median_rmse) + " / " + percent_cell(s->max_rmse) : "—") << " | "
         << (has ? percent_cell(s->median_hausdorff) + " / " + percent_cell(s->max_hausdorff) : "—") << " | "
         << (has && std::isfinite(v.pose_rmse) && v.pose_rmse > 0
                 ? significant(s->median_rmse / v.pose_rmse, 2)
                 : "—")
         << " |";
    }
    md << "\n";
  }
  return md.str();
}

std::string convergence_markdown(const InvarianceResult& r) {
  std::ostringstream rows;
  for (const InvarianceVerdict& v : r.verdicts)
    if (v.resolution >= 0 && v.converged_known > 0)
      rows << "| " << method_title(v.method) << " | " << resolution_text(v.resolution) << " | "
           << v.converged_known << " | " << v.not_converged << " |\n";
  if (rows.str().empty()) return "";
  return "\n## Convergence\n\nForms of the methods that test their convergence (Coulomb's `converged`, "
         "SMACOF's "
         "stop reason), references and transformed together; per form in the `converged` and "
         "`reference_converged` columns of `invariance.csv`.\n\n| method | resolution | forms | not "
         "converged "
         "|\n| --- | --- | ---: | ---: |\n" +
         rows.str();
}

}  // namespace

namespace invariance_detail {

void write_data_files(const ExperimentFolder& folder, const InvarianceOptions& o,
                      const InvarianceResult& result) {
  write_rows_csv(folder, result);
  write_pose_csv(folder, result);
  write_summary_csv(folder, result);
  folder.write_json("invariance.json", invariance_json(result, o));
}

}  // namespace invariance_detail

nlohmann::json invariance_json(const InvarianceResult& result, const InvarianceOptions& o) {
  nlohmann::json verdicts = nlohmann::json::array(), summary = nlohmann::json::array();
  for (const InvarianceVerdict& v : result.verdicts) verdicts.push_back(verdict_json(v));
  for (const InvarianceSummaryRow& s : result.summary)
    summary.push_back({{"resolution", s.resolution},
                       {"method", s.method},
                       {"transformation", s.transformation},
                       {"exact", s.exact},
                       {"count", s.count},
                       {"median_rmse_percent", percent_json(s.median_rmse)},
                       {"max_rmse_percent", percent_json(s.max_rmse)},
                       {"median_hausdorff_percent", percent_json(s.median_hausdorff)},
                       {"max_hausdorff_percent", percent_json(s.max_hausdorff)}});
  nlohmann::json titles = nlohmann::json::object();
  for (const std::string& m : result.methods) titles[m] = method_title(m);
  return {{"experiment", "invariance"},
          {"data", o.data},
          {"resolutions", result.resolutions},
          {"methods", result.methods},
          {"titles", titles},
          {"shapes", result.shapes},
          {"seeds", o.seeds},
          {"seed", o.seed},
          {"transformations", transformation_names()},
          {"tolerance",
           {{"floor_percent", o.tolerance_floor_percent}, {"pose_percent", o.tolerance_pose_percent}}},
          {"verdicts", verdicts},
          {"summary", summary},
          {"figure", result.figure},
          {"figure_problem", result.figure_problem},
          {"failures", shape_failures_json(result.failures)},
          {"seconds", result.seconds},
          {"build", build_json()}};
}

std::string invariance_markdown(const InvarianceResult& r, const InvarianceOptions& o) {
  std::ostringstream md;
  md << "# Invariance of the canonical forms\n\n"
     << build_sentence() << "\n\n"
     << "Data: `" << o.data << "`, " << r.shapes.size() << " shapes; resolutions:";
  for (size_t k = 0; k < r.resolutions.size(); ++k)
    md << (k ? "," : "") << " " << resolution_text(r.resolutions[k]);
  md << "; " << o.seeds << (o.seeds == 1 ? " vertex renumbering (seed " : " vertex renumberings (seeds ")
     << o.seed << (o.seeds == 1 ? "" : " to " + std::to_string(o.seed + o.seeds - 1))
     << "), face order, rigid motion and jitter with seed " << o.seed << "; " << seconds_text(r.seconds)
     << ".\n\n"
     << "Each method's form of every shape is compared with its form of the same shape under transformations "
        "that must not change it. With the vertex correspondence known (renumbering, face order, rigid "
        "motion, "
        "scale ×1e-6 and ×1e3 with the form divided back, jitter of 1e-9 of the diagonal): the RMSE over "
        "corresponding vertices after the best rigid fit (Kabsch, reflections allowed) and the Hausdorff "
        "distance after that same fit. Remeshed at 0.8× and 1.2× the vertex count, reported apart: RMSE and "
        "Hausdorff after ICP. All in % of the reference form's bounding-box diagonal. The pose variation "
        "(signal) is the median over pairs of poses of one class of the RMSE after ICP between their forms. "
        "**Verdict**: pass when every exact transformation's RMSE is at most max("
     << o.tolerance_floor_percent << "% of the diagonal, " << o.tolerance_pose_percent
     << "% of the method's median pose variation) and every transformed form was computed.\n\n"
     << "## Verdicts\n\n"
     << verdicts_markdown(r);
  for (const InvarianceVerdict& v : r.verdicts)
    if (v.resolution >= 0 && !v.reason.empty())
      md << "\n- " << method_title(v.method) << ", " << resolution_text(v.resolution) << ": " << v.reason;
  md << "\n";
  for (Index n : r.resolutions) md << resolution_markdown(r, n);
  md << convergence_markdown(r) << "\n## Figure\n\n";
  if (!r.figure.empty())
    md << figure_markdown("invariance", r.figure)
       << "\n\nRMSE per transformation (log scale), one colour per method "
          "(small dots: every row; large: the largest); the tolerance floor as a grey dashed line over the "
          "exact "
          "transformations (a method whose tolerance is above it, its own dashed line), the pose variation "
          "as a "
          "star; exact zeros on the grey band at the bottom.\n";
  else
    md << "No figure (" << r.figure_problem << ").\n";
  md << "\n## Files\n\n`invariance.csv` (a row per resolution, shape, method, transformation and seed), "
        "`invariance_pose.csv` (the pose pairs), `invariance_summary.csv` (medians and maxima with the pose "
        "variation and tolerance), `invariance.json` (the verdicts and summary), `resampled/N/` (the "
        "remeshes).\n";
  if (!r.failures.empty()) md << "\n" << shape_failures_markdown(r.failures, LeftOutScope::Form);
  return md.str();
}

void write_invariance_report(const InvarianceResult& result, const InvarianceOptions& options) {
  ExperimentFolder(options.out).write_text("invariance.md", invariance_markdown(result, options));
}

}  // namespace cshapes
