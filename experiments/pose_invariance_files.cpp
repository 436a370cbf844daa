#include "cshapes/experiments/pose_invariance_detail.h"

#include <algorithm>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cshapes/support/csv.h"
#include "cshapes/support/format.h"
#include "cshapes/support/timing.h"
#include "cshapes/experiments/figures.h"
#include "cshapes/pipeline/canonical_form_methods.h"

namespace cshapes {

using pose_detail::csv_number;
using pose_detail::forms_of_run;
using pose_detail::label_of;
using pose_detail::measured_stress;

namespace {

// ---- Data files -------------------------------------------------------------------------------------------

// Text fields quoted where they must be: a label "a,b" stays one column.
void write_pairs_csv(const ExperimentFolder& folder, const std::string& label,
                     const PoseInvarianceResult& result) {
  std::ostringstream csv;
  csv << "config,a,b,class,form,rms,input_rms,samples\n";
  for (const PosePairRow& r : result.pairs)
    csv << csv_field(label) << "," << csv_field(r.a) << "," << csv_field(r.b) << ","
        << csv_field(r.class_name) << "," << csv_field(r.form) << "," << csv_number(r.rms) << ","
        << csv_number(r.input_rms) << "," << r.samples << "\n";
  folder.write_text("pose_pairs.csv", csv.str());
}

void write_shapes_csv(const ExperimentFolder& folder, const std::string& label,
                      const PoseInvarianceResult& result) {
  std::ostringstream csv;
  csv << "config,shape,form,mean_abs_stretch,p99_stretch,max_stretch,geodesic_stress,iterations,seconds,"
         "torn_vertices\n";
  for (const PoseShapeRow& r : result.shapes)
    csv << csv_field(label) << "," << csv_field(r.shape) << "," << csv_field(r.form) << ","
        << csv_number(r.mean_abs_stretch) << "," << csv_number(r.p99_stretch) << ","
        << csv_number(r.max_stretch) << "," << (r.stress >= 0 ? csv_number(r.stress) : "") << ","
        << r.iterations << "," << csv_number(r.seconds, 4) << "," << r.torn_edges << "\n";
  folder.write_text("pose_shapes.csv", csv.str());
}

void write_summary_csv(const ExperimentFolder& folder, const std::string& label,
                       const PoseInvarianceResult& result) {
  std::ostringstream csv;
  csv << "config,form,class,pairs,median_rms,mean_rms,median_input_rms,removed,median_mean_abs_stretch,"
         "max_stretch,median_geodesic_stress\n";
  for (const PoseSummaryRow& r : result.summary)
    csv << csv_field(label) << "," << csv_field(r.form) << "," << csv_field(r.class_name) << "," << r.pairs
        << "," << csv_number(r.median_rms) << "," << csv_number(r.mean_rms) << ","
        << csv_number(r.median_input_rms) << "," << csv_number(r.removed) << ","
        << csv_number(r.mean_abs_stretch) << "," << csv_number(r.max_stretch) << ","
        << (r.stress >= 0 ? csv_number(r.stress) : "") << "\n";
  folder.write_text("pose_summary.csv", csv.str());
}

void write_parts_csv(const ExperimentFolder& folder, const std::string& label,
                     const PoseInvarianceResult& result) {
  std::map<std::string, const PoseClassParts*> class_parts;
  for (const PoseClassParts& c : result.classes) class_parts[c.class_name] = &c;
  std::ostringstream csv;
  csv << "config,a,b,class,form,part,parts_shape,extremity_vertex,samples,rms\n";
  for (const PosePartRow& r : result.parts) {
    const PoseClassParts& c = *class_parts.at(r.class_name);
    csv << csv_field(label) << "," << csv_field(r.a) << "," << csv_field(r.b) << ","
        << csv_field(r.class_name) << "," << csv_field(r.form) << "," << r.part << "," << csv_field(c.shape)
        << "," << (r.part >= 1 ? std::to_string(c.extremities[static_cast<size_t>(r.part - 1)]) : "") << ","
        << r.samples << "," << csv_number(r.rms) << "\n";
  }
  folder.write_text("pose_parts.csv", csv.str());
}

// The figure's data: pose_residuals.csv (a row per sample: its vertex of b, position, part, and per form the
// residual) and pose_residuals.json (the pair, why, the forms and their pose RMS).
void write_figure_data(const ExperimentFolder& folder, const PoseFigurePair& fig) {
  std::ostringstream csv;
  csv << "sample,vertex,x,y,z,part";
  for (const std::string& f : fig.forms) csv << "," << csv_field(f);
  csv << "\n";
  for (Index k = 0; k < fig.positions.rows(); ++k) {
    csv << k << "," << fig.vertices[static_cast<size_t>(k)];
    for (int c = 0; c < 3; ++c) csv << "," << csv_number(fig.positions(k, c), 9);
    csv << "," << fig.parts[static_cast<size_t>(k)];
    for (Index f = 0; f < fig.residuals.cols(); ++f) csv << "," << csv_number(fig.residuals(k, f));
    csv << "\n";
  }
  folder.write_text("pose_residuals.csv", csv.str());
  nlohmann::json rms = nlohmann::json::object();
  for (size_t f = 0; f < fig.forms.size(); ++f) rms[fig.forms[f]] = fig.rms[f];
  nlohmann::json titles = nlohmann::json::object();
  for (const std::string& f : fig.forms) titles[f] = f == "input" ? "input" : canonical_form_method_title(f);
  folder.write_json("pose_residuals.json", {{"a", fig.a},
                                            {"b", fig.b},
                                            {"class", fig.class_name},
                                            {"chosen_by", fig.chosen_by},
                                            {"forms", fig.forms},
                                            {"titles", titles},
                                            {"rms", rms}});
}

size_t count_form(const std::vector<PosePairRow>& rows, const std::string& form) {
  return static_cast<size_t>(
      std::count_if(rows.begin(), rows.end(), [&](const PosePairRow& r) { return r.form == form; }));
}
size_t count_form(const std::vector<PoseShapeRow>& rows, const std::string& form) {
  return static_cast<size_t>(
      std::count_if(rows.begin(), rows.end(), [&](const PoseShapeRow& r) { return r.form == form; }));
}

// With resampling: how the samples were carried to the remeshes, and how far they moved.
std::string located_markdown(const PoseInvarianceResult& result) {
  long samples = 0, relocated = 0, off_part = 0;
  double sum = 0, worst = 0;
  std::string worst_shape;
  std::ostringstream table;
  table << "| shape | samples | mean distance | max distance | relocated | off their part |\n"
           "|---|---:|---:|---:|---:|---:|\n";
  for (const PoseLocatedRow& r : result.located) {
    table << "| " << r.shape << " | " << r.samples << " | ";
    if (!r.remeshed) {
      table << "— | — | — | — |\n";  // its samples are its own vertices
      continue;
    }
    table << percent(r.mean_distance, 3) << " | " << percent(r.max_distance, 3) << " | " << r.relocated
          << " | " << r.off_part << " |\n";
    samples += r.samples;
    relocated += r.relocated;
    off_part += r.off_part;
    sum += r.mean_distance * r.samples;
    if (r.max_distance >= worst) {
      worst = r.max_distance;
      worst_shape = r.shape;
    }
  }
  std::ostringstream md;
  md << "Each ground-truth correspondence sample (a vertex of the input) was carried to its shape's "
        "remesh as the closest point of the remeshed surface, and each form's position of it interpolated "
        "there on the remesh's triangle (barycentric; mesh/locate_on_surface.h); poses that shared their "
        "faces "
        "are still paired vertex i with vertex i of the inputs. Edge stretch and geodesic stress are "
        "measured "
        "on the remeshes. Distance from the located points to the input vertices, over the input's "
        "bounding-box diagonal: mean "
     << percent(samples ? sum / static_cast<double>(samples) : NAN, 3) << ", largest " << percent(worst, 3)
     << (worst_shape.empty() ? "" : " (" + worst_shape + ")") << ". " << relocated + off_part << " of "
     << samples
     << " samples were closest to another part of the surface (a remeshed triangle whose corners lie, on "
        "the input, out of reach of the sample along it, as where an arm lies against the body: "
        "pipeline/remesh_samples.h); "
     << relocated << " of them were located on the closest triangle of their own part instead, " << off_part
     << " found none within reach and stayed.\n\n"
     << table.str();
  return md.str();
}

// The per-part section: the parts of each class, and per part the median RMS over pairs of each form.
std::string parts_markdown(const PoseInvarianceResult& result, const PoseInvarianceOptions& o) {
  std::ostringstream md;
  md << "\n## Where the pose stays: per part\n\n"
     << "Parts found on each class's first pose from its geometry alone (geodesics/geodesic_parts.h): a centre "
        "(the "
        "vertex of least summed geodesic distance to "
     << o.part_finder.centre_sources
     << " evenly spaced vertices), the extremities (the local maxima of the geodesic distance from the "
        "centre whose topological persistence is at least "
     << fixed(o.part_finder.min_persistence, 2)
     << " of the largest distance: tips of limbs, not bumps), and each vertex in the part of its nearest "
        "extremity when nearer than "
     << fixed(o.part_finder.part_fraction, 2)
     << " of that extremity's distance to the centre, else in the core; carried to the other poses through "
        "the ground truth. Per part: the RMS of the residuals of its samples after the pair's whole-shape "
        "rigid fit (the fit of the pose RMS above, not one per part), over the mean diagonal; medians over "
        "pairs. The parts' mean squares, weighted by their samples, add up to the pose RMS². Parts are named "
        "by their extremity's vertex (0-based) on the class's first pose: which is a hand is not known. Per "
        "pair and form in `pose_parts.csv`.\n";
  const std::vector<std::string> forms = forms_of_run(o);
  for (const PoseClassParts& c : result.classes) {
    md << "\n**" << c.class_name << "** (parts found on " << c.shape << "): ";
    if (!c.problem.empty()) {
      md << "none (" << c.problem << ").\n";
      continue;
    }
    md << c.extremities.size() << " extremities";
    for (size_t e = 0; e < c.extremities.size(); ++e)
      md << (e ? "; " : ": ") << "part " << e + 1 << " at vertex " << c.extremities[e] << " (distance "
         << fixed(c.reach[e], 2) << ", persistence " << fixed(c.persistence[e], 2) << ")";
    md << "; centre: vertex " << c.centre << (c.repair_text.empty() ? "" : "; " + c.repair_text) << ".\n\n";
    md << "| part | samples per pair |";
    for (const std::string& f : forms)
      md << " " << (f == "input" ? "input" : canonical_form_method_title(f)) << " |";
    md << "\n| --- | --- |";
    for (size_t f = 0; f < forms.size(); ++f) md << " --- |";
    md << "\n";
    std::set<int> parts;
    for (const PosePartSummaryRow& r : result.part_summary)
      if (r.class_name == c.class_name) parts.insert(r.part);
    for (int part : parts) {
      std::string name =
          part < 0    ? "unassigned"
          : part == 0 ? "core"
                      : detail::concat("part ", part, " (extremity at vertex ",
                                       c.extremities[static_cast<size_t>(part - 1)], " of ", c.shape, ")");
      std::ostringstream cells;
      double samples = 0;
      for (const std::string& f : forms)
        for (const PosePartSummaryRow& r : result.part_summary)
          if (r.class_name == c.class_name && r.part == part && r.form == f) {
            cells << " " << percent(r.median_rms) << " |";
            if (f == "input") samples = r.median_samples;
          }
      md << "| " << name << " | " << fixed(samples, 0) << " |" << cells.str() << "\n";
    }
  }
  return md.str();
}

// The figure, or why there is none, and how to draw it.
std::string residuals_markdown(const PoseInvarianceResult& result, const PoseInvarianceOptions& o) {
  const PoseFigurePair& fig = result.figure_pair;
  if (fig.a.empty()) return "";
  std::ostringstream md;
  md << "\n## Residuals of one pair\n\n";
  if (!result.figure.empty())
    md << figure_markdown("residuals of " + fig.a + "-" + fig.b, result.figure) << "\n\n";
  else
    md << "No figure (" << result.figure_problem << ").\n\n";
  md << fig.a << " against " << fig.b << " (class " << fig.class_name << "), " << fig.chosen_by
     << ": each sample of " << fig.b
     << " at its input position, coloured by its residual after the pair's "
        "whole-shape rigid fit, in % of the mean diagonal, one colour scale for every panel. Pose RMS:";
  for (size_t f = 0; f < fig.forms.size(); ++f)
    md << (f ? "," : "") << " "
       << (fig.forms[f] == "input" ? "input" : canonical_form_method_title(fig.forms[f])) << " "
       << percent(fig.rms[f]);
  md << ". Data: `pose_residuals.csv`, `pose_residuals.json`; redraw with `scripts/python.sh "
        "experiments/plots/pose_figure.py "
     << o.out << "`.\n";
  return md.str();
}

}  // namespace

namespace pose_detail {

// "all", then each class of a measured shape in shape order; "all" alone when there is one class.
std::vector<std::string> summary_classes(const std::vector<PoseShape>& shapes,
                                         const std::vector<char>& failed) {
  std::vector<std::string> classes = {"all"};
  for (size_t i = 0; i < shapes.size(); ++i)
    if (!failed[i] && std::find(classes.begin(), classes.end(), shapes[i].class_name) == classes.end())
      classes.push_back(shapes[i].class_name);
  if (classes.size() == 2) classes.pop_back();  // one class: "all" says it
  return classes;
}

// One form over the pairs and shapes of one class ("all": every class). class_of: shape name → class.
PoseSummaryRow summary_row(const std::string& form, const std::string& class_name,
                           const PoseInvarianceResult& result,
                           const std::map<std::string, std::string>& class_of) {
  PoseSummaryRow row;
  row.form = form;
  row.class_name = class_name;
  std::vector<double> rms, input;
  for (const PosePairRow& p : result.pairs)
    if (p.form == form && (class_name == "all" || p.class_name == class_name)) {
      rms.push_back(p.rms);
      input.push_back(p.input_rms);
    }
  row.pairs = static_cast<int>(rms.size());
  row.median_rms = median(rms);
  row.median_input_rms = median(input);
  double sum = 0;
  for (double v : rms) sum += v;
  row.mean_rms = rms.empty() ? NAN : sum / rms.size();
  row.removed = 1 - row.median_rms / row.median_input_rms;
  std::vector<double> stretch, stress;
  for (const PoseShapeRow& s : result.shapes)
    if (s.form == form && (class_name == "all" || class_of.at(s.shape) == class_name)) {
      stretch.push_back(s.mean_abs_stretch);
      row.max_stretch = std::max(row.max_stretch, s.max_stretch);
      if (s.stress >= 0) stress.push_back(s.stress);
    }
  row.mean_abs_stretch = median(stretch);
  row.stress = stress.empty() ? -1 : median(stress);
  return row;
}

std::string label_of(const PoseInvarianceOptions& o) {
  return o.label.empty() ? "default" : o.label;
}

void write_data_files(const ExperimentFolder& folder, const PoseInvarianceOptions& o,
                      const PoseInvarianceResult& result) {
  write_pairs_csv(folder, label_of(o), result);
  write_shapes_csv(folder, label_of(o), result);
  write_summary_csv(folder, label_of(o), result);
  if (o.parts) write_parts_csv(folder, label_of(o), result);
  if (!result.figure_pair.a.empty()) write_figure_data(folder, result.figure_pair);
}

}  // namespace pose_detail

nlohmann::json pose_invariance_json(const PoseInvarianceResult& result) {
  nlohmann::json rows = nlohmann::json::array();
  for (const PoseSummaryRow& r : result.summary)
    rows.push_back({{"form", r.form},
                    {"class", r.class_name},
                    {"pairs", r.pairs},
                    {"median_rms", r.median_rms},
                    {"mean_rms", r.mean_rms},
                    {"median_input_rms", r.median_input_rms},
                    {"removed", r.removed},
                    {"mean_abs_stretch", r.mean_abs_stretch},
                    {"max_stretch", r.max_stretch},
                    {"stress", r.stress >= 0 ? nlohmann::json(r.stress) : nlohmann::json(nullptr)}});
  return {{"shapes", result.shapes.size()},
          {"pairs", result.pairs.size()},
          {"summary", rows},
          {"figure", result.figure},
          {"figure_problem", result.figure_problem},
          {"failures", shape_failures_json(result.failures)}};
}

std::string pose_invariance_markdown(const PoseInvarianceResult& result, const PoseInvarianceOptions& o) {
  std::ostringstream md;
  md << "# Pose invariance (" << label_of(o) << ")\n\n"
     << build_sentence() << "\n\n"
     << "Data: `" << o.data << "`, " << count_form(result.shapes, "input") << " shapes, "
     << count_form(result.pairs, "input") << " pairs of poses, up to " << o.samples
     << " ground-truth correspondences per pair"
     << (result.resampled ? detail::concat(", every shape remeshed to about ", o.resample.vertices,
                                           " vertices first (see Resampling below)")
                          : std::string())
     << ". Pose RMS: RMS distance between corresponding points of the "
        "two forms after the best rigid fit (reflections allowed), over the mean bounding-box diagonal; "
        "removed = 1 − form / input (medians over pairs). Stretch: edge length in the form / in the input, "
        "edges not torn; stress: against fast marching from "
     << o.stress_sources << " sources per shape (medians over shapes; max stretch: the worst edge).\n\n"
     << "| form | class | pairs | pose RMS (median) | mean | input | removed | mean \\|stretch−1\\| | max "
        "stretch | geodesic stress |\n| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
  for (const PoseSummaryRow& r : result.summary)
    md << "| " << r.form << " | " << r.class_name << " | " << r.pairs << " | " << percent(r.median_rms)
       << " | " << percent(r.mean_rms) << " | " << percent(r.median_input_rms) << " | "
       << percent(r.removed, 0) << " | " << (r.form == "input" ? "—" : fixed(r.mean_abs_stretch, 3)) << " | "
       << (r.form == "input" ? "—" : fixed(r.max_stretch, 2)) << " | " << fixed(measured_stress(r.stress), 3)
       << " |\n";
  if (o.parts && !result.classes.empty()) md << parts_markdown(result, o);
  md << residuals_markdown(result, o);
  if (result.resampled)
    md << "\n## Resampling\n\n" << resampling_markdown(result.resampling) << "\n" << located_markdown(result);
  if (!result.failures.empty()) md << "\n" << shape_failures_markdown(result.failures);
  return md.str();
}

void write_pose_invariance_report(const PoseInvarianceResult& result, const PoseInvarianceOptions& options,
                                  const std::string& folder) {
  ExperimentFolder(folder).write_text("pose.md", pose_invariance_markdown(result, options));
}

}  // namespace cshapes
