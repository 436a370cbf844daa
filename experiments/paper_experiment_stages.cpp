#include "cshapes/experiments/paper_experiment_detail.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>
#include <sstream>

#include "cshapes/data/dataset.h"
#include "cshapes/data/topological_noise.h"
#include "cshapes/eval/correspondence_error.h"
#include "cshapes/eval/distance_csv.h"
#include "cshapes/eval/pairwise_distances.h"
#include "cshapes/eval/retrieval.h"
#include "cshapes/eval/retrieval_report.h"
#include "cshapes/experiments/figures.h"
#include "cshapes/experiments/paper_figures.h"
#include "cshapes/experiments/paper_report.h"
#include "cshapes/matching/icp.h"
#include "cshapes/matching/shape_distance.h"
#include "cshapes/mesh/io.h"
#include "cshapes/mesh/mesh_defects.h"
#include "cshapes/mesh/mesh_repair.h"
#include "cshapes/mesh/rigid_transform.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/distributed.h"
#include "cshapes/pipeline/experiment_kit.h"
#include "cshapes/pipeline/glued_meshes.h"
#include "cshapes/pipeline/shape_failures.h"
#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/support/timing.h"

namespace cshapes::paper_detail {

namespace fs = std::filesystem;
using nlohmann::json;

// 3. Distances between canonical forms (ICP, cached), retrieval measures under each distance kind:
// distances/*.csv (Hausdorff), distances/{chamfer,rmse}/*.csv, metrics.json.
void retrieval_stage(ExperimentRun& run) {
  const PaperExperimentOptions& o = run.o;
  const std::vector<Shape>& shapes = run.shapes;
  const std::vector<int>& retrieval = run.retrieval;
  std::map<std::string, MethodForms>& forms = run.forms;
  PaperReport& report = run.report;
  const std::vector<std::string>& names = run.names;
  const std::vector<std::string>& classes = run.classes;
  const std::vector<int>& labels = run.labels;
  say(o.note, "== ICP distances between all pairs");
  const auto t = WallClock::now();
  json metrics;
  metrics["shapes"] = names;
  metrics["classes"] = classes;
  // One class: every shape is relevant to every query, so there is no retrieval to measure
  // (evaluate_retrieval refuses it); the matrices are written and report.md says why no measure is given.
  const bool several_classes =
      std::any_of(labels.begin(), labels.end(), [&](int label) { return label != labels.front(); });
  if (!several_classes) metrics["retrieval"] = "none: one class, every shape relevant to every query";
  for (const std::string& m : o.methods) {
    std::vector<Points> X;
    std::vector<std::string> keys;
    for (int i : retrieval) {
      X.push_back(forms[m].forms[i].X);
      keys.push_back(forms[m].keys[i]);
    }
    PairwiseDistanceOptions po;
    po.cache_dir = (fs::path(o.out) / "cache" / "pairs").string();
    po.progress = renamed_stage(o.progress, "distances, " + method_title(m));
    po.communicator = &run.comm;
    PairwiseDistanceResult pd = pairwise_distances(X, keys, po);
    run.summary.pairs_computed += pd.computed;
    run.summary.pairs_cached += pd.cached;
    if (!run.comm.is_root()) continue;  // the matrices are on rank 0
    // The paper's distance (Hausdorff) in distances/METHOD.csv and metrics.json's top level, as before; all
    // three kinds under "by_distance" (Chamfer and RMSE matrices in distances/chamfer/ and distances/rmse/).
    write_distance_csv((fs::path(o.out) / "distances" / (m + ".csv")).string(), names, pd.hausdorff);
    json jm;
    for (const auto& [kind, D] : {std::pair<std::string, const Eigen::MatrixXd*>{"hausdorff", &pd.hausdorff},
                                  {"chamfer", &pd.chamfer},
                                  {"rmse", &pd.rmse}}) {
      if (kind != "hausdorff")
        write_distance_csv((fs::path(o.out) / "distances" / kind / (m + ".csv")).string(), names, *D);
      if (!several_classes) continue;
      RetrievalResult rr = evaluate_retrieval(*D, labels);
      json jk{{"map", rr.mean.ap},
              {"nn", rr.mean.nn},
              {"ft", rr.mean.ft},
              {"st", rr.mean.st},
              {"e", rr.mean.e},
              {"dcg", rr.mean.dcg},
              {"pr", {{"recall", rr.pr.recall}, {"precision", rr.pr.precision}}}};
      jk["nn_confusion"] = confusion_json(rr.confusion);
      // Noisy shapes as queries: are they still retrieved with their class?
      double noisy_nn = 0;
      int noisy_queries = 0;
      for (const QueryResult& q : rr.queries)
        if (shapes[retrieval[q.query]].noisy) {
          noisy_nn += q.scores.nn;
          ++noisy_queries;
        }
      if (noisy_queries) jk["noisy_query_nn"] = noisy_nn / noisy_queries;
      const PaperReport::Retrieval measures{rr.mean.ap,
                                            rr.mean.nn,
                                            rr.mean.ft,
                                            rr.mean.st,
                                            rr.mean.e,
                                            rr.mean.dcg,
                                            noisy_queries ? noisy_nn / noisy_queries : -1.0};
      report.retrieval_by_distance[m][kind] = measures;
      if (kind == "hausdorff") {
        jm = jk;
        report.retrieval[m] = measures;
      }
      jm["by_distance"][kind] = jk;
    }
    metrics["methods"][m] = several_classes ? jm : json::object();
  }
  if (!run.comm.is_root()) return;
  metrics["class_names"] = run.class_names;
  metrics["build"] = build_json();
  if (!run.summary.failures.empty()) metrics["failures"] = shape_failures_json(run.summary.failures);
  write_file_atomically((fs::path(o.out) / "metrics.json").string(),
                        [&](std::ostream& out) { out << metrics.dump(2) << '\n'; });
  report.stage_seconds["distances and retrieval"] = seconds_since(t);
}

// 4. Topological noise: each noisy shape against its clean source, per method; noise_effect.csv.
void noise_stage(ExperimentRun& run) {
  const PaperExperimentOptions& o = run.o;
  const std::vector<Shape>& shapes = run.shapes;
  const std::vector<int>& retrieval = run.retrieval;
  std::map<std::string, MethodForms>& forms = run.forms;
  PaperReport& report = run.report;
  say(o.note, "== effect of topological noise");
  const auto t = WallClock::now();
  {
    for (size_t i = 0; i < shapes.size(); ++i) {
      const Shape& noisy = shapes[i];
      if (noisy.source_name.empty()) continue;
      size_t j = std::find_if(shapes.begin(), shapes.end(),
                              [&](const Shape& s) { return s.name == noisy.source_name; }) -
                 shapes.begin();
      for (const std::string& m : o.methods) {
        const Points& A = forms[m].forms[i].X;
        const Points& B = forms[m].forms[j].X;
        const double scale = bbox_diagonal(finite_rows(B));
        ShapeDistance sd = aligned_shape_distance(A, B);
        PaperReport::NoiseRow row{noisy.name, m, aligned_rms(A, B, true) / scale, sd.hausdorff / scale,
                                  sd.rmse / scale};
        report.noise.push_back(row);
      }
    }
    // Pose variation, for scale: ICP RMS between clean poses of one class, relative to the bbox diagonal.
    for (const std::string& m : o.methods) {
      std::vector<double> within;
      for (size_t a = 0; a < retrieval.size(); ++a)
        for (size_t b = a + 1; b < retrieval.size(); ++b) {
          const Shape& sa = shapes[retrieval[a]];
          const Shape& sb = shapes[retrieval[b]];
          if (sa.noisy || sb.noisy || sa.class_name != sb.class_name) continue;
          const Points& B = forms[m].forms[retrieval[b]].X;
          within.push_back(aligned_shape_distance(forms[m].forms[retrieval[a]].X, B).rmse /
                           bbox_diagonal(finite_rows(B)));
        }
      report.pose_variation[m] = median(within);
    }
    write_file_atomically((fs::path(o.out) / "noise_effect.csv").string(), [&](std::ostream& out) {
      // In % of the bounding-box diagonal, as report.md gives them.
      out << "shape,method,vertexwise_rms_percent,hausdorff_percent,icp_rmse_percent\n";
      out.precision(10);
      for (const auto& r : report.noise)
        out << r.shape << ',' << r.method << ',' << 100 * r.vertexwise_rms << ',' << 100 * r.hausdorff << ','
            << 100 * r.icp_rmse << '\n';
    });
  }
  report.stage_seconds["noise effect"] = seconds_since(t);
}

// 5. Point maps induced by aligning canonical forms, against ground-truth correspondences (cached);
// correspondence_error.csv (each method's mean curve) and point_map_pairs.csv (each pair's mean error, so that
// a change in the mean can be traced to the pairs that moved).
void point_map_stage(ExperimentRun& run) {
  const PaperExperimentOptions& o = run.o;
  const std::vector<Shape>& shapes = run.shapes;
  const std::vector<int>& retrieval = run.retrieval;
  std::map<std::string, MethodForms>& forms = run.forms;
  PaperReport& report = run.report;
  const DiskCache& misc_cache = run.misc_cache;
  const auto t = WallClock::now();
  if (o.correspondence_samples > 0) {
    std::map<std::string, std::vector<Eigen::VectorXd>> curves;
    struct PairError {
      std::string method, source, target;
      double mean_error;
    };
    std::vector<PairError> pair_errors;
    Eigen::VectorXd thresholds;
    int pairs = 0;
    for (size_t b = 0; b < retrieval.size(); ++b) {
      const Shape& sb = shapes[retrieval[b]];
      // Point maps index the input's vertices: only shapes used as read (no repair) take part.
      if (sb.vts.empty() || sb.noisy || !sb.untouched) continue;
      std::vector<size_t> sources;
      for (size_t a = 0; a < retrieval.size(); ++a) {
        const Shape& sa = shapes[retrieval[a]];
        if (a != b && !sa.vts.empty() && !sa.noisy && sa.untouched && sa.class_name == sb.class_name)
          sources.push_back(a);
      }
      if (sources.empty()) continue;
      if (pairs == 0) say(o.note, "== point-map errors against ground-truth correspondences");
      // Each (pair, method) result is cached; B's geodesic matrix is computed only if one of them is missing.
      const GeodesicOptions go = o.canon.geodesics;
      std::optional<DistanceMatrix> G;
      const std::string truth_b_key = file_content_hash(sb.vts);
      std::vector<int> truth_b;
      for (size_t a : sources) {
        const Shape& sa = shapes[retrieval[a]];
        const std::string truth_a_key = file_content_hash(sa.vts);
        for (const std::string& m : o.methods) {
          std::ostringstream key;
          key.precision(17);
          key << "point-map;" << forms[m].keys[retrieval[a]] << ";" << forms[m].keys[retrieval[b]]
              << ";vts=" << truth_a_key << "," << truth_b_key << ";samples=" << o.correspondence_samples
              << ";geodesics=" << to_string(go.method) << "," << static_cast<int>(go.heat_mode) << ","
              << go.heat_time_factor << ";icp=" << to_key_string(IcpOptions{});
          const std::string entry = cache_key({key.str(), "json"});
          const json value = misc_cache.get_or_compute_json(entry, [&] {
            if (!G) {
              G = all_pairs_geodesics(sb.mesh, go);
              truth_b = read_vts(sb.vts, sb.mesh.num_vertices());
            }
            std::vector<int> truth_a = read_vts(sa.vts, sa.mesh.num_vertices());
            IcpResult align = icp(forms[m].forms[retrieval[a]].X, forms[m].forms[retrieval[b]].X);
            CorrespondenceErrorOptions ce;
            ce.max_samples = o.correspondence_samples;
            CorrespondenceErrorResult r =
                correspondence_error(sb.mesh, align.source_to_target, truth_a, truth_b, ce, &*G);
            return json{
                {"mean_error", r.mean_error},
                {"thresholds",
                 std::vector<double>(r.thresholds.data(), r.thresholds.data() + r.thresholds.size())},
                {"fraction", std::vector<double>(r.fraction.data(), r.fraction.data() + r.fraction.size())}};
          });
          const double mean_error = value.at("mean_error").get<double>();
          std::vector<double> tk = value.at("thresholds").get<std::vector<double>>();
          std::vector<double> fk = value.at("fraction").get<std::vector<double>>();
          CSHAPES_REQUIRE(!tk.empty() && tk.size() == fk.size(), misc_cache.entry_path(entry),
                          ": a damaged point-map cache entry (delete it to recompute)");
          curves[m].push_back(Eigen::Map<Eigen::VectorXd>(fk.data(), static_cast<Index>(fk.size())));
          thresholds = Eigen::Map<Eigen::VectorXd>(tk.data(), static_cast<Index>(tk.size()));
          report.correspondence_mean_error[m].push_back(mean_error);
          pair_errors.push_back({m, sa.name, sb.name, mean_error});
        }
        ++pairs;
      }
    }
    if (pairs > 0) {
      write_file_atomically((fs::path(o.out) / "correspondence_error.csv").string(), [&](std::ostream& out) {
        out << "method,error,fraction\n";
        for (const auto& [m, list] : curves) {
          Eigen::VectorXd mean = Eigen::VectorXd::Zero(thresholds.size());
          for (const auto& c : list) mean += c;
          mean /= static_cast<double>(list.size());
          for (Index k = 0; k < thresholds.size(); ++k)
            out << m << ',' << thresholds[k] << ',' << mean[k] << '\n';
        }
      });
      write_file_atomically((fs::path(o.out) / "point_map_pairs.csv").string(), [&](std::ostream& out) {
        out << "method,source,target,mean_error\n";
        out.precision(9);
        for (const PairError& e : pair_errors)
          out << e.method << ',' << e.source << ',' << e.target << ',' << e.mean_error << '\n';
      });
      report.correspondence_pairs = pairs;
    }
  }
  report.stage_seconds["correspondence"] = seconds_since(t);
}

// 6. The figures' data: the meshes of Figures 2-6 unless o.figures is off, and figures.json, which names
// the figures of this run (drawn by paper_figures.py, linked by report.md) and its methods: a figure or a
// method of an earlier run into the same folder is neither drawn nor linked.
void figure_stage(ExperimentRun& run) {
  const PaperExperimentOptions& o = run.o;
  const std::vector<Shape>& shapes = run.shapes;
  PaperReport& report = run.report;
  const DiskCache& misc_cache = run.misc_cache;
  const DiskCache& form_cache = run.form_cache;
  const bool has_coulomb = std::find(o.methods.begin(), o.methods.end(), "coulomb") != o.methods.end();
  json grids = json::object();
  if (o.figures) {
    say(o.note, "== data for the figures");
    const auto t = WallClock::now();
    write_figure_data(o, report, misc_cache, form_cache);
    grids = report.figure_grids;
    // Fig. 6 / Fig. 4: clean pose beside its noisy version, per class.
    json fig6{
        {"title",
         "Fig. 6: shapes (top) and canonical forms; glued (shape, MDS) and torn (Coulomb) vertices red"}};
    json fig4{
        {"title", "Fig. 4: shapes with point-wise connectivity artifacts (top) and their coulombization"}};
    std::vector<std::string> row_titles = {"shape"};
    for (const std::string& m : o.methods) row_titles.push_back(method_title(m));
    json cells = json::array();
    for (size_t r = 0; r < row_titles.size(); ++r) cells.push_back(json::array());
    json fig4_cells = json::array({json::array(), json::array()});
    std::set<std::string> classes_shown;
    for (size_t i = 0; i < shapes.size(); ++i) {
      const Shape& noisy = shapes[i];
      if (noisy.source_name.empty() || classes_shown.count(noisy.class_name)) continue;
      classes_shown.insert(noisy.class_name);
      json red{{"property", "glued"}};
      cells[0].push_back(
          {{"mesh", "canon/input/" + noisy.source_name + ".ply"}, {"title", noisy.source_name}});
      cells[0].push_back(
          {{"mesh", "canon/input/" + noisy.name + ".ply"}, {"title", noisy.name}, {"red", red}});
      for (size_t k = 0; k < o.methods.size(); ++k) {
        const std::string& m = o.methods[k];
        json noisy_red = canonical_form_method(m).marks_torn ? json{{"property", "torn"}} : red;
        cells[k + 1].push_back({{"mesh", "canon/" + m + "/" + noisy.source_name + ".ply"}});
        cells[k + 1].push_back({{"mesh", "canon/" + m + "/" + noisy.name + ".ply"}, {"red", noisy_red}});
      }
      fig4_cells[0].push_back(
          {{"mesh", "canon/input/" + noisy.name + ".ply"}, {"title", noisy.name}, {"red", red}});
      if (std::find(o.methods.begin(), o.methods.end(), "coulomb") != o.methods.end())
        fig4_cells[1].push_back(
            {{"mesh", "canon/coulomb/" + noisy.name + ".ply"}, {"red", {{"property", "torn"}}}});
    }
    // The inputs, as PLY with the glued flag, for the figure scripts.
    for (const Shape& s : shapes) {
      WriteOptions wo;
      if (!s.glued.empty()) {
        Eigen::VectorXd glued = Eigen::VectorXd::Zero(s.mesh.num_vertices());
        for (int v : s.glued) glued[v] = 1;
        wo.scalars.push_back({"glued", glued});
      }
      write_mesh((fs::path(o.out) / "canon" / "input" / (s.name + ".ply")).string(), s.mesh, wo);
    }
    fig6["rows"] = row_titles;
    fig6["cells"] = cells;
    fig4["rows"] = json::array({"shape", "Coulomb"});
    fig4["cells"] = fig4_cells;
    if (!classes_shown.empty()) {
      grids["fig6_noisy_shapes"] = fig6;
      if (has_coulomb) grids["fig4_tearing"] = fig4;  // Coulomb's tears: nothing to show without it
    }
    report.stage_seconds["figures"] = seconds_since(t);
  }
  std::vector<std::string>& figures = report.figures;
  figures.clear();
  for (const char* grid : {"fig2_hand", "fig3_iterations", "fig4_tearing"})
    if (grids.contains(grid)) figures.push_back(grid);
  if (o.figures && !report.convergence.empty()) figures.push_back("fig5_convergence");
  if (grids.contains("fig6_noisy_shapes")) figures.push_back("fig6_noisy_shapes");
  std::vector<std::string> methods;  // the methods with a distance matrix (not left out as a whole)
  for (const std::string& m : o.methods)
    if (report.retrieval.count(m)) methods.push_back(m);
  if (!methods.empty()) {
    figures.push_back("fig7_distance_matrices");
    figures.push_back("fig8_pr");
  }
  if (report.correspondence_pairs > 0) figures.push_back("fig9_correspondence");
  const json spec{{"methods", methods}, {"draw", figures}, {"grids", grids}, {"data", dataset_name(o.data)}};
  write_file_atomically((fs::path(o.out) / "figures.json").string(),
                        [&](std::ostream& out) { out << spec.dump(2) << '\n'; });
}

}  // namespace cshapes::paper_detail
