#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>
#include <sstream>

#include "cshapes/pipeline/outside_methods.h"
#include "cshapes/experiments/figures.h"
#include "cshapes/experiments/topkids_experiment_detail.h"
#include "cshapes/support/error.h"
#include "cshapes/support/timing.h"

namespace cshapes {

using nlohmann::json;
using topkids_detail::kInputs;

namespace {

// ---- Data files -------------------------------------------------------------------------------------------

void write_rows_csv(const ExperimentFolder& folder, const TopkidsExperimentResult& r) {
  folder.write("topkids.csv", [&](std::ostream& s) {
    s << "pose,method,samples,mean_error,median_error,under_0.1,under_0.25,unmapped,symmetric_chosen,"
         "whole_map_mirrored,whole_map_mean_error,whole_map_under_0.1,whole_map_under_0.25,direct_mean_error,"
         "mirrored_mean_error,mirror_ratio,mirrored,reflected,icp_rmse,icp_rmse_relative,torn_edges,repair\n";
    s.precision(6);
    for (const TopkidsRow& row : r.rows) {
      std::string repair = row.repair;
      std::replace(repair.begin(), repair.end(), '"', '\'');
      s << row.pose << ',' << row.method << ',' << row.samples << ',' << row.mean_error << ','
        << row.median_error << ',' << row.under_0_1 << ',' << row.under_0_25 << ',' << row.unmapped << ','
        << row.symmetric_chosen << ',' << (row.whole_map_mirrored ? 1 : 0) << ',' << row.whole_map_mean_error
        << ',' << row.whole_map_under_0_1 << ',' << row.whole_map_under_0_25 << ',' << row.direct_mean_error
        << ',' << row.mirrored_mean_error << ',' << row.mirror_ratio << ',' << (row.mirrored ? 1 : 0) << ','
        << (row.reflected ? 1 : 0) << ',' << row.icp_rmse << ',' << row.icp_rmse_relative << ','
        << row.torn_edges << ",\"" << repair << "\"\n";
    }
  });
}

void write_curves_csv(const ExperimentFolder& folder, const TopkidsExperimentResult& r) {
  folder.write("curves.csv", [&](std::ostream& s) {
    s << "method,forgiven,error,fraction\n";
    s.precision(6);
    for (const TopkidsSummary& sm : r.summaries)
      for (Index t = 0; t < r.thresholds.size(); ++t)
        s << sm.method << ",vertex," << r.thresholds[t] << ',' << sm.fraction[t] << '\n';
    for (const TopkidsSummary& sm : r.summaries)
      for (Index t = 0; t < r.thresholds.size(); ++t)
        s << sm.method << ",map," << r.thresholds[t] << ',' << sm.whole_map_fraction[t] << '\n';
  });
}

json finite_or_null(double v) {
  return std::isfinite(v) ? json(v) : json(nullptr);
}
std::vector<double> vector_of(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

json summary_json(const TopkidsSummary& s) {
  return {{"method", s.method},
          {"samples", s.samples},
          {"mean_error", finite_or_null(s.mean_error)},
          {"median_error", finite_or_null(s.median_error)},
          {"under_0.1", s.under_0_1},
          {"under_0.25", s.under_0_25},
          {"fraction", vector_of(s.fraction)},
          {"whole_map_mean_error", finite_or_null(s.whole_map_mean_error)},
          {"whole_map_under_0.1", s.whole_map_under_0_1},
          {"whole_map_under_0.25", s.whole_map_under_0_25},
          {"whole_map_fraction", vector_of(s.whole_map_fraction)},
          {"poses", s.poses},
          {"mirrored_poses", s.mirrored_poses},
          {"median_pose_mean_error", finite_or_null(s.median_pose_mean_error)},
          {"median_pose_direct_error", finite_or_null(s.median_pose_direct_error)}};
}

json row_json(const TopkidsRow& row) {
  return {{"pose", row.pose},
          {"method", row.method},
          {"samples", row.samples},
          {"mean_error", finite_or_null(row.mean_error)},
          {"median_error", finite_or_null(row.median_error)},
          {"under_0.1", row.under_0_1},
          {"under_0.25", row.under_0_25},
          {"unmapped", row.unmapped},
          {"symmetric_chosen", row.symmetric_chosen},
          {"whole_map_mirrored", row.whole_map_mirrored},
          {"whole_map_mean_error", finite_or_null(row.whole_map_mean_error)},
          {"whole_map_under_0.1", row.whole_map_under_0_1},
          {"whole_map_under_0.25", row.whole_map_under_0_25},
          {"direct_mean_error", finite_or_null(row.direct_mean_error)},
          {"mirrored_mean_error", finite_or_null(row.mirrored_mean_error)},
          {"mirror_ratio", finite_or_null(row.mirror_ratio)},
          {"mirrored", row.mirrored},
          {"reflected", row.reflected},
          {"icp_rmse", row.icp_rmse},
          {"icp_rmse_relative", row.icp_rmse_relative},
          {"torn_edges", row.torn_edges},
          {"repair", row.repair}};
}

// topkids.json: everything, with the figure's outcome as far as it is known (the figure script reads this
// file for its legend and title, so it is written before the figure is drawn and again after).
void write_topkids_json(const ExperimentFolder& folder, const TopkidsExperimentResult& r,
                        const TopkidsExperimentOptions& o) {
  json j{{"data", o.data},
         {"reference", o.reference},
         {"poses", r.poses},
         {"methods", r.methods},
         {"samples_per_pose", o.samples},
         {"scoring_geodesics", to_string(o.scoring_geodesics.method)},
         {"icp", to_key_string(o.icp)},
         {"reference_sqrt_area", r.reference_sqrt_area},
         {"reference_repair", r.reference_repair},
         {"scoring_repair", r.scoring_repair},
         {"forms_computed", r.forms_computed},
         {"forms_cached", r.forms_cached},
         {"thresholds", vector_of(r.thresholds)},
         {"summary", json::array()},
         {"rows", json::array()},
         {"figure", r.figure},
         {"figure_problem", r.figure_problem}};
  if (!r.failures.empty()) j["failures"] = shape_failures_json(r.failures);
  if (r.resampled) {
    json carried = json::array();
    for (const TopkidsCarriedRow& c : r.carried)
      carried.push_back({{"pose", c.pose},
                         {"vertices", c.vertices},
                         {"mean_distance", c.mean_distance},
                         {"max_distance", c.max_distance},
                         {"relocated", c.relocated},
                         {"off_part", c.off_part}});
    json shapes = json::array();
    for (const ResampledShape& rs : r.resampling.shapes)
      shapes.push_back({{"name", rs.name},
                        {"input_vertices", rs.input_vertices},
                        {"vertices", rs.vertices},
                        {"hausdorff", finite_or_null(rs.hausdorff)},
                        {"remeshed", rs.remeshed}});
    j["resample"] = {{"vertices", r.resampling.options.vertices},
                     {"shapes", shapes},
                     {"carried", carried},
                     {"reference_back_distance", r.reference_back_distance}};
  }
  for (const TopkidsSummary& s : r.summaries) j["summary"].push_back(summary_json(s));
  for (const TopkidsRow& row : r.rows) j["rows"].push_back(row_json(row));
  j["build"] = build_json();
  folder.write_json("topkids.json", j);
}

}  // namespace

void topkids_detail::write_data_files(const ExperimentFolder& folder, const TopkidsExperimentResult& r,
                                      const TopkidsExperimentOptions& o) {
  write_rows_csv(folder, r);
  write_curves_csv(folder, r);
  write_topkids_json(folder, r, o);
}

void draw_topkids_figure(TopkidsExperimentResult& r, const TopkidsExperimentOptions& o) {
  const ExperimentFolder folder(o.out);
  if (o.figure) {
    const FigureRun drawn =
        draw_figure("topkids_figure.py", {o.out}, folder.path("topkids"), o.figure_format, o.methods);
    r.figure = drawn.drawn ? figure_file_name("topkids", o.figure_format) : "";
    r.figure_problem = drawn.problem;
  } else {
    r.figure = "";
    r.figure_problem = "not requested (--no-draw)";
  }
  write_topkids_json(folder, r, o);
}

// ---- report.md
// ----------------------------------------------------------------------------------------------

namespace {

std::string label(const std::string& m) {
  if (m == kInputs) return "inputs (no canonical form)";
  return canonical_form_method_title(m);
}

// The data, the alignment and the error protocol.
void write_method(std::ostream& s, const TopkidsExperimentResult& r, const TopkidsExperimentOptions& o) {
  s << "# TOPKIDS: point maps under real topological noise\n\n";
  s << build_sentence() << "\n\n";
  s << "Data: `" << o.data
    << "` (SHREC'16 \"Matching of deformable shapes with topological noise\", Lähner et al. 2016, low "
       "resolution). Reference `"
    << o.reference << "`; " << r.poses.size() << " query poses (";
  for (size_t i = 0; i < r.poses.size(); ++i) s << (i ? ", " : "") << r.poses[i];
  s << "). Each pose's canonical form was aligned onto the reference's by ICP ("
    << (o.icp.try_axis_swaps ? "principal-axis starts and their axis swaps"
                             : "the retrieval's options: principal-axis starts")
    << (o.icp.allow_reflections ? ", reflections allowed" : ", no reflections")
    << "; all options in `topkids.json`); every vertex of the pose goes to the nearest vertex of the "
       "reference's aligned form. *inputs*: the same ICP on the meshes themselves, no canonical form.\n\n";
  s << "Error (SHREC'16 protocol): geodesic distance on the reference between the mapped and the true "
       "vertex, over √area of the reference ("
    << fixed(r.reference_sqrt_area, 2)
    << "); where the pose's `_sym.txt` gives a mirrored truth the smaller of the two distances counts, "
       "vertex "
       "by vertex (a left-right flip is forgiven). "
    << (o.samples > 0
            ? std::to_string(o.samples) + " ground-truth vertices per pose, evenly spaced over `NAME_ref.txt`"
            : std::string("every ground-truth vertex"))
    << "; geodesics by " << to_string(o.scoring_geodesics.method)
    << " on the reference (fast marching against exact geodesics on kid00, from 2 sources: 1.5–1.7% "
       "mean relative error, i.e. a mean 0.007 and at most 0.026 in units of √area over all distances, "
       "about 0.004 at an error of 0.25). Mean error over mapped vertices; fractions over all scored "
       "vertices.\n\n"
       "The per-vertex minimum also rewards maps that mix the sides: a map unrelated to the truth has about "
       "half its vertices nearer the mirrored truth. The *whole map* columns forgive the flip only for a map "
       "as a whole (the better of truth and mirrored truth for all its vertices together, as Kim, Lipman & "
       "Funkhouser 2011 score symmetric shapes): the stricter reading.\n\n"
       "A pose's map is *mirrored* when it is clearly nearer the mirrored truth than the truth: its mean "
       "error against the mirrored truth (`NAME_sym.txt` gives each vertex's mirror on the pose, whose truth "
       "is the mirrored truth; the truth where there is none) is at most "
    << fixed(kMirroredErrorRatio, 2)
    << " of its mean error against the truth alone. Maps that mix the sides, or unrelated to the truth, are "
       "about as far from both and are not counted. With few poses and bimodal errors a pooled mean moves "
       "with one flipped pose; the medians and the share of mirrored poses say whether it did.\n\n";
  if (r.resampled)
    s << "Resampled: the reference and every pose were remeshed to about " << o.resample.vertices
      << " vertices first, and the forms and ICP computed on the remeshes; the ground truth and the scoring "
         "stay on the inputs. Each ground-truth vertex of a pose was carried to its remesh (the closest "
         "point "
         "of the remeshed surface), its form position interpolated there and aligned; its image is the "
         "nearest vertex of the reference's aligned form, taken back to the reference input's nearest vertex "
         "(see Resampling below).\n\n";
}

// With resampling: the remeshes, and how far the carried vertices moved.
void write_resampling(std::ostream& s, const TopkidsExperimentResult& r) {
  if (!r.resampled) return;
  s << "## Resampling\n\n" << resampling_markdown(r.resampling) << "\n";
  s << "Ground-truth vertices carried to their pose's remesh (pipeline/remesh_samples.h), distance over the "
       "pose's bounding-box diagonal; relocated: closest to a remeshed triangle of another part of the "
       "surface "
       "(two parts in contact), located on the closest triangle of their own part instead; off their part: "
       "the same with none of their own within reach (left where they were). The reference's remesh vertices "
       "lie at most "
    << percent(r.reference_back_distance, 3)
    << " of its diagonal from the input vertices they go back to.\n\n| pose | vertices | mean distance | max "
       "distance | relocated | off their part |\n|---|---:|---:|---:|---:|---:|\n";
  for (const TopkidsCarriedRow& c : r.carried)
    s << "| " << c.pose << " | " << c.vertices << " | " << percent(c.mean_distance, 3) << " | "
      << percent(c.max_distance, 3) << " | " << c.relocated << " | " << c.off_part << " |\n";
  s << "\n";
}

void write_pooled_table(std::ostream& s, const TopkidsExperimentResult& r) {
  s << "## Pooled over poses\n\n| method | samples | mean error | median error | median of pose means | "
       "mirrored poses | ≤ 0.1 | ≤ 0.25 | whole map: mean error | ≤ 0.1 | ≤ 0.25 |\n| --- | --- | --- | --- "
       "| --- | --- | --- | --- | --- | --- | --- |\n";
  for (const TopkidsSummary& sm : r.summaries)
    s << "| " << label(sm.method) << " | " << sm.samples << " | " << fixed(sm.mean_error, 3) << " | "
      << fixed(sm.median_error, 3) << " | " << fixed(sm.median_pose_mean_error, 3) << " | "
      << sm.mirrored_poses << " of " << sm.poses << " | " << fixed(sm.under_0_1, 3) << " | "
      << fixed(sm.under_0_25, 3) << " | " << fixed(sm.whole_map_mean_error, 3) << " | "
      << fixed(sm.whole_map_under_0_1, 3) << " | " << fixed(sm.whole_map_under_0_25, 3) << " |\n";
  s << "\nMean and median error: over every scored vertex of every pose (flip forgiven per vertex); "
       "median of pose means: the median over poses of each pose's mean error; mirrored poses: maps clearly "
       "nearer the mirrored truth (above). `topkids.json`'s summary also has the median over poses of the "
       "error against the truth alone (`median_pose_direct_error`).\n\n";
}

void write_figure(std::ostream& s, const TopkidsExperimentResult& r, const std::string& folder) {
  if (!r.figure.empty())
    s << figure_markdown("cumulative error curves and per-pose errors", r.figure)
      << "\n\nLeft: cumulative error curves "
         "(fraction of ground-truth vertices mapped within each error), pooled over the poses, the flip "
         "forgiven per vertex, then per whole map; data in `curves.csv`. Right: each pose's mean error (flip "
         "forgiven per vertex), a dot per pose and method, the bar at the median over poses: poses whose "
         "alignment failed form their own cluster; a cross joined to a dot: a mirrored map's mean error "
         "against the truth alone, what the flip costs unforgiven; data in `topkids.csv`.\n\n";
  else
    s << "No figure (" << r.figure_problem
      << "); draw it with `scripts/python.sh experiments/plots/topkids_figure.py " << folder
      << "` from `curves.csv`.\n\n";
}

void write_pose_table(std::ostream& s, const TopkidsExperimentResult& r) {
  s << "## Per pose: mean error (fraction ≤ 0.25), flip forgiven per vertex | per whole map\n\n| pose |";
  for (const std::string& m : r.methods) s << " " << label(m) << " | whole map |";
  s << "\n| --- |";
  for (size_t i = 0; i < r.methods.size(); ++i) s << " --- | --- |";
  s << "\n";
  for (const std::string& pose : r.poses) {
    s << "| " << pose << " |";
    for (const std::string& m : r.methods)
      for (const TopkidsRow& row : r.rows)
        if (row.pose == pose && row.method == m)
          s << " " << fixed(row.mean_error, 3) << " (" << fixed(row.under_0_25, 2) << ") | "
            << fixed(row.whole_map_mean_error, 3) << " (" << fixed(row.whole_map_under_0_25, 2) << ")"
            << (row.mirrored             ? " M"
                : row.whole_map_mirrored ? " m"
                                         : "")
            << (row.reflected ? " R" : "") << " |";
    s << "\n";
  }
  s << "\nM: the map is mirrored (mean error against the mirrored truth ≤ " << fixed(kMirroredErrorRatio, 2)
    << " × against the truth; the whole map is scored against the mirrored truth); m: the mirrored truth is "
       "nearer, but not clearly (the whole map is scored against it, the map is not counted as mirrored). R: "
       "the ICP alignment is a reflection. `topkids.csv` has per pose and method: median, unmapped vertices, "
       "vertices scored against the mirrored truth, the mean errors against the truth and the mirrored truth "
       "and their ratio, ICP RMSE, torn edges (Coulomb) and repairs.\n\n";
}

void write_repairs(std::ostream& s, const TopkidsExperimentResult& r) {
  s << "## Repairs and tearing\n\n";
  bool any = false;
  for (const auto& [m, text] : r.reference_repair)
    if (!text.empty()) s << "- " << label(m) << ", reference: " << text << "\n", any = true;
  if (!r.scoring_repair.empty()) s << "- scoring geodesics: " << r.scoring_repair << "\n", any = true;
  std::set<std::string> said;
  for (const TopkidsRow& row : r.rows)
    if (!row.repair.empty() && said.insert(row.repair).second)
      s << "- " << label(row.method) << ": " << row.repair << "\n", any = true;
  if (!any) s << "- no mesh needed a repair\n";
  for (const TopkidsRow& row : r.rows)
    if (row.torn_edges >= 0 && !said.count("torn " + row.method)) {
      said.insert("torn " + row.method);
      s << "- " << label(row.method) << " torn edges per pose:";
      for (const TopkidsRow& q : r.rows)
        if (q.method == row.method) s << " " << q.pose << " " << q.torn_edges;
      s << "\n";
    }
}

void write_reproduce(std::ostream& s, const TopkidsExperimentOptions& o, const std::string& folder) {
  s << "\nReproduce: `cshapes experiment topkids --data " << o.data << " --out " << folder << " --methods "
    << methods_command_argument(o.methods);
  s << " --samples " << o.samples << (o.icp.try_axis_swaps ? " --icp-axis-swaps" : "")
    << (o.resample.vertices > 0 ? " --resample " + std::to_string(o.resample.vertices) : std::string())
    << "` (canonical forms and scorings are cached in `cache/`).\n";
}

}  // namespace

void write_topkids_report(const TopkidsExperimentResult& r, const TopkidsExperimentOptions& o,
                          const std::string& folder) {
  std::ostringstream s;
  write_method(s, r, o);
  write_pooled_table(s, r);
  write_figure(s, r, folder);
  s << shape_failures_markdown(r.failures);
  write_pose_table(s, r);
  write_resampling(s, r);
  write_repairs(s, r);
  write_reproduce(s, o, folder);
  ExperimentFolder(folder).write_text("report.md", s.str());
}

}  // namespace cshapes
