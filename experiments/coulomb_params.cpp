#include "cshapes/experiments/coulomb_params.h"

#include <algorithm>
#include <sstream>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/support/format.h"
#include "cshapes/geodesics/geodesics.h"
#include "cshapes/mesh/io.h"
#include "cshapes/mesh/rigid_transform.h"
#include "cshapes/data/topological_noise.h"
#include "cshapes/eval/correspondence_error.h"

namespace cshapes {

namespace {

// RMS distance between corresponding samples of two shapes after rigid alignment, over A's bbox diagonal:
// 0 when the two poses have the same canonical form up to a rigid motion.
double pose_distance(const Points& A, const std::vector<int>& a, const Points& B, const std::vector<int>& b) {
  CSHAPES_REQUIRE(a.size() == b.size(), "correspondences of different lengths: ", a.size(), " vs ", b.size());
  Points SA(static_cast<Index>(a.size()), 3), SB(static_cast<Index>(b.size()), 3);
  for (size_t s = 0; s < a.size(); ++s) {
    SA.row(static_cast<Index>(s)) = A.row(a[s]);
    SB.row(static_cast<Index>(s)) = B.row(b[s]);
  }
  return rigid_rms_distance(SB, SA) / bbox_diagonal(A);
}

std::string format(double v, int precision) {
  std::ostringstream s;
  s.precision(precision);
  s << v;
  return s.str();
}

}  // namespace

const std::vector<CoulombParamsConfig>& coulomb_params_configs() {
  static const std::vector<CoulombParamsConfig> configs = {
      {"default", [](CoulombCanonOptions&) {}},
      {"paper-1/1",
       [](CoulombCanonOptions& o) {
         o.scheme = CoulombScheme::Paper;
         o.start = CoulombStart::Input;
         o.flatten = 0;
         o.step_rule = CoulombStepRule::MaxEdge;
         o.projection.steps = 1;
       }},
      {"scheme=paper", [](CoulombCanonOptions& o) { o.scheme = CoulombScheme::Paper; }},
      {"start=input", [](CoulombCanonOptions& o) { o.start = CoulombStart::Input; }},
      {"flatten=0", [](CoulombCanonOptions& o) { o.flatten = 0; }},
      {"start=input,flatten=0",
       [](CoulombCanonOptions& o) {
         o.start = CoulombStart::Input;
         o.flatten = 0;
       }},
      {"k=1", [](CoulombCanonOptions& o) { o.projection.steps = 1; }},
      {"k=3", [](CoulombCanonOptions& o) { o.projection.steps = 3; }},
      {"k=30", [](CoulombCanonOptions& o) { o.projection.steps = 30; }},
      {"k=100", [](CoulombCanonOptions& o) { o.projection.steps = 100; }},
      {"step=max-edge", [](CoulombCanonOptions& o) { o.step_rule = CoulombStepRule::MaxEdge; }},
      {"step=mean-edge", [](CoulombCanonOptions& o) { o.step_rule = CoulombStepRule::MeanEdge; }},
      {"step=median-edge", [](CoulombCanonOptions& o) { o.step_rule = CoulombStepRule::MedianEdge; }},
      {"step=max-edge,k=100",
       [](CoulombCanonOptions& o) {
         o.step_rule = CoulombStepRule::MaxEdge;
         o.projection.steps = 100;
       }},
      {"factor=0.3,k=30",
       [](CoulombCanonOptions& o) {
         o.step_factor = 0.3;
         o.projection.steps = 30;
       }},
      {"gradient=mean@0.1",
       [](CoulombCanonOptions& o) {
         o.step_rule = CoulombStepRule::MeanEdge;
         o.step_gradient = StepGradient::Mean;
         o.step_factor = 0.1;
       }},
      {"gradient=mean@0.15",
       [](CoulombCanonOptions& o) {
         o.step_rule = CoulombStepRule::MeanEdge;
         o.step_gradient = StepGradient::Mean;
         o.step_factor = 0.15;
       }},
      {"gradient=mean@0.2",
       [](CoulombCanonOptions& o) {
         o.step_rule = CoulombStepRule::MeanEdge;
         o.step_gradient = StepGradient::Mean;
         o.step_factor = 0.2;
       }},
      {"step=max-edge@gradient=max",
       [](CoulombCanonOptions& o) {
         o.step_rule = CoulombStepRule::MaxEdge;
         o.step_gradient = StepGradient::Max;
         o.step_factor = 0.1;
       }},
      {"momentum=0.97", [](CoulombCanonOptions& o) { o.momentum = 0.97; }},
      {"l1", [](CoulombCanonOptions& o) { o.projection.norm = ProjectionNorm::L1; }},
      {"tear=50", [](CoulombCanonOptions& o) { o.tear_after = 50; }},
      {"tear=150", [](CoulombCanonOptions& o) { o.tear_after = 150; }},
      {"tear=200", [](CoulombCanonOptions& o) { o.tear_after = 200; }},
      {"tear=200 x3/30",
       [](CoulombCanonOptions& o) {
         o.tear_after = 200;
         o.tear_interval = 30;
       }},
      {"tear=convergence", [](CoulombCanonOptions& o) { o.tear_after = 1000000; }},
      {"p=0.5%", [](CoulombCanonOptions& o) { o.tear_fraction = 0.005; }},
      {"p=2%", [](CoulombCanonOptions& o) { o.tear_fraction = 0.02; }},
      {"tear once", [](CoulombCanonOptions& o) { o.tear_times = 1; }},
      {"tear x3/100", [](CoulombCanonOptions& o) { o.tear_interval = 100; }},
      {"no tearing", [](CoulombCanonOptions& o) { o.tear_fraction = 0; }},
      {"guard=vertex", [](CoulombCanonOptions& o) { o.tear_guard = TearGuard::Vertex; }},
      // The fast summation's accuracy during the iterations (relative L2 error of the gradient).
      {"accuracy=3e-4", [](CoulombCanonOptions& o) { o.energy.accuracy = 3e-4; }},
      {"accuracy=1e-3", [](CoulombCanonOptions& o) { o.energy.accuracy = 1e-3; }},
      {"accuracy=3e-3", [](CoulombCanonOptions& o) { o.energy.accuracy = 3e-3; }},
      {"accuracy=1e-2", [](CoulombCanonOptions& o) { o.energy.accuracy = 1e-2; }},
  };
  return configs;
}

std::vector<CoulombParamsRow> run_coulomb_params(const CoulombParamsOptions& options) {
  std::vector<CoulombParamsConfig> configs;
  const std::vector<CoulombParamsConfig>& known = coulomb_params_configs();
  if (options.configs.empty()) configs = known;
  for (const std::string& name : options.configs) {
    auto it = std::find_if(known.begin(), known.end(),
                           [&](const CoulombParamsConfig& c) { return c.name == name; });
    if (it == known.end()) {
      std::string names;
      for (const CoulombParamsConfig& c : known) names += (names.empty() ? "" : ", ") + c.name;
      fail("unknown --configs entry '", name, "'; known: ", names);
    }
    configs.push_back(*it);
  }
  const std::vector<std::string>& shapes = options.shapes;
  const std::vector<std::string>& partners = options.partners;
  CSHAPES_REQUIRE(partners.empty() || partners.size() == shapes.size(),
                  "--partners needs one pose per shape (", shapes.size(), "), or none");
  std::vector<CoulombParamsRow> rows;
  for (size_t si = 0; si < shapes.size(); ++si) {
    const std::string& shape = shapes[si];
    const Mesh mesh = read_mesh(options.data + "/" + shape + ".off");
    Mesh partner;
    std::vector<int> corr, partner_corr;
    double input_pose = -1;
    if (!partners.empty()) {
      partner = read_mesh(options.data + "/" + partners[si] + ".off");
      corr = read_vts(options.data + "/corres/" + shape + ".vts", mesh.num_vertices());
      partner_corr = read_vts(options.data + "/corres/" + partners[si] + ".vts", partner.num_vertices());
      input_pose = pose_distance(mesh.V, corr, partner.V, partner_corr);
    }
    const Edges clean = mesh_edges(mesh.F);
    const Edges bridges = glue_bridges(mesh.V, clean, options.bridges);
    Edges glued(clean.rows() + bridges.rows(), 2);
    glued << clean, bridges;
    {
      std::ostringstream where;
      for (Index k = 0; k < bridges.rows(); ++k)
        where << " (" << bridges(k, 0) << "," << bridges(k, 1) << ": "
              << significant((mesh.V.row(bridges(k, 0)) - mesh.V.row(bridges(k, 1))).norm()) << ")";
      say(options.note, shape + ": " + std::to_string(bridges.rows()) +
                            " bridges glued between vertices (i,j: length)" + where.str() + "; mean edge " +
                            significant(edge_lengths(mesh.V, clean).mean()));
    }
    for (const CoulombParamsConfig& config : configs) {
      CoulombCanonOptions o;
      o.max_iterations = options.max_iterations;
      config.apply(o);
      const CoulombCanonResult a = coulomb_canonical_form(mesh.V, clean, o);
      const CoulombCanonResult b = coulomb_canonical_form(mesh.V, glued, o);
      CoulombParamsRow row;
      row.shape = shape;
      row.config = config.name;
      row.iterations = a.iterations;
      row.seconds = a.seconds;
      row.converged = a.converged;
      row.energy = a.energy;
      row.mean_violation = a.violation.mean_relative;
      row.max_violation = a.violation.max_relative;
      row.glued_iterations = b.iterations;
      row.glued_seconds = b.seconds;
      row.bridges = static_cast<int>(bridges.rows());
      for (Index t = 0; t < b.torn_edges.rows(); ++t)
        for (Index k = 0; k < bridges.rows(); ++k)
          if (b.torn_edges.row(t) == bridges.row(k)) ++row.bridges_torn;
      row.glued_rms_to_clean = rigid_rms_distance(b.X, a.X) / bbox_diagonal(a.X);
      if (!partners.empty()) {
        const CoulombCanonResult c = coulomb_canonical_form(partner.V, mesh_edges(partner.F), o);
        row.pose_rms = pose_distance(a.X, corr, c.X, partner_corr);
      }
      row.input_pose_rms = input_pose;
      rows.push_back(row);
      say(options.note, shape + " / " + config.name + ": " + std::to_string(row.iterations) +
                            " it, violation " + format(row.mean_violation, 3) + ", bridges torn " +
                            std::to_string(row.bridges_torn) + "/" + std::to_string(row.bridges) +
                            ", glued vs clean RMS " + format(row.glued_rms_to_clean, 3) + ", pose RMS " +
                            format(row.pose_rms, 3) + " (input " + format(input_pose, 3) + ")");
    }
  }
  return rows;
}

std::string write_coulomb_params(const std::string& out, const std::vector<CoulombParamsRow>& rows) {
  std::vector<std::vector<std::string>> text;
  for (const CoulombParamsRow& r : rows)
    text.push_back({r.shape, r.config, std::to_string(r.iterations), format(r.seconds, 3),
                    r.converged ? "yes" : "no", format(r.energy, 6), format(r.mean_violation, 3),
                    format(r.max_violation, 3), std::to_string(r.glued_iterations),
                    format(r.glued_seconds, 3), std::to_string(r.bridges), std::to_string(r.bridges_torn),
                    format(r.glued_rms_to_clean, 3), format(r.pose_rms, 3), format(r.input_pose_rms, 3)});
  const std::vector<std::string> columns = {
      "shape",   "config",         "iterations",         "seconds",          "converged",
      "energy",  "mean_violation", "max_violation",      "glued_iterations", "glued_seconds",
      "bridges", "bridges_torn",   "glued_rms_to_clean", "pose_rms",         "input_pose_rms"};
  write_file_atomically(out + "/coulomb_params.csv", [&](std::ostream& csv) {
    for (size_t c = 0; c < columns.size(); ++c) csv << (c ? "," : "") << columns[c];
    csv << '\n';
    for (const auto& row : text) {
      for (size_t c = 0; c < row.size(); ++c) csv << (c ? "," : "") << row[c];
      csv << '\n';
    }
  });
  std::ostringstream md;
  md << "| shape | config | iterations | s | converged | energy | mean viol. | max viol. | glued it. | glued "
        "s "
        "| bridges torn | glued vs clean RMS | pose RMS (input) "
        "|\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : text)
    md << "| " << r[0] << " | " << r[1] << " | " << r[2] << " | " << r[3] << " | " << r[4] << " | " << r[5]
       << " | " << r[6] << " | " << r[7] << " | " << r[8] << " | " << r[9] << " | " << r[11] << "/" << r[10]
       << " | " << r[12] << " | " << r[13] << " (" << r[14] << ") |\n";
  write_file_atomically(out + "/coulomb_params.md", [&](std::ostream& f) { f << md.str(); });
  return md.str();
}

nlohmann::json coulomb_params_json(const std::vector<CoulombParamsRow>& rows) {
  auto optional = [](double v) { return v >= 0 ? nlohmann::json(v) : nlohmann::json(nullptr); };
  nlohmann::json out = nlohmann::json::array();
  for (const CoulombParamsRow& r : rows)
    out.push_back({{"shape", r.shape},
                   {"config", r.config},
                   {"iterations", r.iterations},
                   {"seconds", r.seconds},
                   {"converged", r.converged},
                   {"energy", r.energy},
                   {"mean_violation", r.mean_violation},
                   {"max_violation", r.max_violation},
                   {"glued_iterations", r.glued_iterations},
                   {"glued_seconds", r.glued_seconds},
                   {"bridges", r.bridges},
                   {"bridges_torn", r.bridges_torn},
                   {"glued_rms_to_clean", r.glued_rms_to_clean},
                   {"pose_rms", optional(r.pose_rms)},
                   {"input_pose_rms", optional(r.input_pose_rms)}});
  return {{"rows", out}};
}

}  // namespace cshapes
