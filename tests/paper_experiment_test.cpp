// experiments/paper_experiment.h: no shape ends the experiment. On a small generated dataset with one shape that
// every method fails on (a readable mesh whose numbers leave the floating-point range), the run completes with the others, names the shape with its reason in the summary,
// report.md and metrics.json, and leaves it out of every method's matrices; --strict stops at it. A run
// where nothing fails has no failures section.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/support/output_folder.h"
#include "cshapes/mesh/io.h"
#include "cshapes/data/dataset.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/eval/distance_csv.h"
#include "cshapes/experiments/figures.h"
#include "cshapes/experiments/paper_experiment.h"
#include "cshapes/experiments/paper_report.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/shape_failures.h"
#include "test_support.h"

namespace cshapes {
namespace paper_experiment_test {

namespace fs = std::filesystem;

// Readable, one component, and every method's repair lets it through; but it cannot be used: scaled to
// 1e150 with one vertex at 1e300, its forms lie beyond the sizes ICP's squared distances hold.
Mesh unusable_mesh() {
  Mesh m = icosphere(2);
  m.V *= 1e150;
  m.V.row(0).setConstant(1e300);
  return m;
}

// 2 classes × 3 clean poses of 400 vertices (generate dataset), plus the unusable shape as a fourth pose of
// the first class, in the manifest.
std::string dataset_with_an_unusable_shape(const std::string& tag, bool with_unusable = true) {
  const std::string dir = test::scratch_dir(tag);
  test::CliResult r = test::run_cli("-q generate dataset --out '" + dir +
                                    "/data' --classes 2 --poses 3 --noisy 0 --vertices 400");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  if (!with_unusable) return dir;
  const std::string manifest = dir + "/data/manifest.csv";
  std::istringstream in(read_file(manifest));
  std::string header, first;
  std::getline(in, header);
  std::getline(in, first);
  // The new line: the same columns as the header, in the class of the first line.
  std::vector<std::string> columns, values;
  for (std::stringstream h(header), v(first); h.good();) {
    std::string c, x;
    std::getline(h, c, ',');
    std::getline(v, x, ',');
    columns.push_back(c);
    values.push_back(x);
  }
  std::string line;
  for (size_t k = 0; k < columns.size(); ++k) {
    const std::string value = columns[k] == "file"    ? "broken9.off"
                              : columns[k] == "pose"  ? "9"
                              : columns[k] == "noisy" ? "0"
                                                      : values[k];
    line += (k ? "," : "") + value;
  }
  write_mesh(dir + "/data/broken9.off", unusable_mesh());
  std::ofstream(manifest, std::ios::app) << line << "\n";
  return dir;
}

PaperExperimentOptions small_run(const std::string& dir, const std::string& out) {
  PaperExperimentOptions o;
  o.data = dir + "/data/manifest.csv";
  o.out = dir + "/" + out;
  o.methods = {"coulomb", "cmds"};
  o.poses_per_class = 0;  // all
  o.noisy_per_class = 0;
  o.table1 = false;
  o.figures = false;
  o.draw = false;
  o.correspondence_samples = 0;
  o.canon.geodesics.method = GeodesicMethod::Heat;  // as the CLI: the fallback to fast marching is tried
  return o;  // Coulomb to convergence: a form stopped at the iteration cap fails its quality check
}

// `experiment paper` draws its own figures: with a Python that has matplotlib, Fig. 7 and Fig. 8 land beside
// report.md, with methods.json naming each method of the run as the tables do; without the scripts, the report
// says the figures were not drawn, why, and the run still succeeds.
TEST(PaperExperiment, DrawsItsFiguresOrSaysWhyNot) {
  const std::string dir = dataset_with_an_unusable_shape("paper_draws", false);
  PaperExperimentOptions o = small_run(dir, "drawn");
  o.draw = true;
  PaperReport r = run_paper_experiment(o);
  draw_paper_figures(r);
  const nlohmann::ordered_json titles = nlohmann::ordered_json::parse(read_file(o.out + "/methods.json"));
  // The run's methods, in its order, and no other (a report of two methods does not name six).
  EXPECT_EQ(titles.dump(), R"({"coulomb":"Coulomb","cmds":"classical MDS"})");
  if (find_python("matplotlib, numpy").empty()) {
    EXPECT_FALSE(r.figures_drawn);
    EXPECT_NE(r.figures_note.find("matplotlib"), std::string::npos) << r.figures_note;
  } else {
    EXPECT_TRUE(r.figures_drawn) << r.figures_note;
    EXPECT_GT(fs::file_size(o.out + "/fig7_distance_matrices.png"), 1000u);
    EXPECT_GT(fs::file_size(o.out + "/fig8_pr.png"), 1000u);
  }

  const std::string empty = test::scratch_dir("paper_draws_no_scripts");
  setenv("CSHAPES_PLOTS", empty.c_str(), 1);
  PaperExperimentOptions again = small_run(dir, "not_drawn");
  again.draw = true;
  const PaperExperimentSummary s = paper_experiment(again);
  unsetenv("CSHAPES_PLOTS");
  EXPECT_FALSE(s.figures_drawn);
  EXPECT_FALSE(fs::exists(dir + "/not_drawn/fig7_distance_matrices.png"));
  const std::string report = read_file(dir + "/not_drawn/report.md");
  EXPECT_NE(report.find("**The figures were not drawn**: the figure script paper_figures.py was not found"),
            std::string::npos)
      << report;
}

// report.md describes the run it comes from: every link resolves to a file beside it, no table is empty (a
// sentence says why instead), and no method that did not run is named (the paper's title on the first line
// aside). `ran`: the methods of the run.
void expect_report_fits_the_run(const std::string& out, const std::vector<std::string>& ran) {
  const std::string report = read_file(out + "/report.md");
  std::vector<std::string> lines;
  for (std::istringstream in(report); in.good();) {
    std::string line;
    std::getline(in, line);
    lines.push_back(line);
  }
  for (size_t k = 0; k < lines.size(); ++k) {
    const std::string& line = lines[k];
    for (size_t at = line.find("]("); at != std::string::npos; at = line.find("](", at + 2)) {
      const size_t end = line.find(')', at);
      const std::string target = line.substr(at + 2, end - at - 2);
      EXPECT_TRUE(fs::exists(fs::path(out) / target)) << out << ": report.md:" << k + 1 << " links " << target
                                                        << ", which is not there";
    }
    const bool separator = line.rfind("| ---", 0) == 0;
    if (separator) {
      EXPECT_TRUE(k + 1 < lines.size() && lines[k + 1].rfind("|", 0) == 0)
          << out << ": report.md:" << k << " is a table without rows: " << lines[k - 1];
    }
    if (k == 0) continue;  // "# Coulomb shapes: …", the paper's title
    for (const CanonicalFormMethod& m : canonical_form_method_registry()) {
      if (std::find(ran.begin(), ran.end(), m.name) != ran.end()) continue;
      EXPECT_EQ(line.find(m.title), std::string::npos)
          << out << ": report.md:" << k + 1 << " names " << m.title << ", which did not run: " << line;
    }
  }
}

TEST(PaperExperiment, TheReportFitsTheRun) {
  const std::string dir = test::scratch_dir("paper_fits");
  test::CliResult g = test::run_cli("-q generate dataset --out '" + dir +
                                    "/data' --classes 2 --poses 3 --noisy 1 --vertices 400");
  ASSERT_EQ(g.exit_code, 0) << g.err;
  const bool can_draw = !find_python("matplotlib, numpy").empty();
  auto run = [&](const std::vector<std::string>& methods, bool figures, bool draw) {
    PaperExperimentOptions o = small_run(dir, "out");
    o.methods = methods;
    o.noisy_per_class = 1;
    o.figures = figures;
    o.draw = draw;
    o.fig3_iterations = {10, 20};
    o.fig5_iterations = 20;
    paper_experiment(o);
    return nlohmann::json::parse(read_file(o.out + "/figures.json"));
  };
  // Every figure's data, not drawn: no link at all.
  nlohmann::json spec = run({"coulomb", "cmds"}, true, false);
  EXPECT_EQ(spec.at("draw"), nlohmann::json({"fig2_hand", "fig3_iterations", "fig4_tearing", "fig5_convergence",
                                              "fig6_noisy_shapes", "fig7_distance_matrices", "fig8_pr"}));
  expect_report_fits_the_run(dir + "/out", {"coulomb", "cmds"});
  EXPECT_EQ(read_file(dir + "/out/report.md").find(".png)"), std::string::npos);

  // A subset without Coulomb and without the figures' data, drawn, in a folder that holds an earlier run's
  // Fig. 4: Fig. 7 and 8 only, no Coulomb settings, no empty claims table, the old figure not linked.
  write_file_atomically(dir + "/out/fig4_tearing.png", [](std::ostream& out) { out << "an earlier run's"; });
  write_file_atomically(dir + "/out/" + kOutputRecordName, [&](std::ostream& out) {  // as that run recorded it
    out << read_file(dir + "/out/" + kOutputRecordName) << "file fig4_tearing.png\n";
  });
  spec = run({"cmds", "diffusion"}, false, true);
  EXPECT_EQ(spec.at("draw"), nlohmann::json({"fig7_distance_matrices", "fig8_pr"}));
  EXPECT_EQ(spec.at("methods"), nlohmann::json({"cmds", "diffusion"}));
  expect_report_fits_the_run(dir + "/out", {"cmds", "diffusion"});
  const std::string report = read_file(dir + "/out/report.md");
  EXPECT_NE(report.find("No claim of the paper can be checked by this run"), std::string::npos) << report;
  if (can_draw) {
    EXPECT_NE(report.find("](fig8_pr.png)"), std::string::npos) << report;
  }
  EXPECT_EQ(report.find("fig4_tearing.png"), std::string::npos) << report;

  // The figures' data without Coulomb: no Fig. 3, 4, 5 (Coulomb's iterations and tears).
  spec = run({"lbo"}, true, false);
  EXPECT_EQ(spec.at("draw"),
            nlohmann::json({"fig2_hand", "fig6_noisy_shapes", "fig7_distance_matrices", "fig8_pr"}));
  expect_report_fits_the_run(dir + "/out", {"lbo"});
}

// With ground-truth correspondences (corres/NAME.vts beside the manifest), every ordered pair of clean poses
// of one class is mapped: point_map_pairs.csv holds one row per method and pair, of one class and two poses,
// and its errors are the ones the report averages.
TEST(PaperExperiment, PointMapsAreWrittenPerPair) {
  const std::string dir = dataset_with_an_unusable_shape("paper_point_maps", false);
  fs::create_directories(dir + "/data/corres");
  int shapes = 0;
  for (const auto& entry : fs::directory_iterator(dir + "/data")) {
    if (entry.path().extension() != ".off") continue;
    ASSERT_GE(read_mesh(entry.path().string()).num_vertices(), 40);
    write_file_atomically(dir + "/data/corres/" + entry.path().stem().string() + ".vts", [](std::ostream& out) {
      for (int k = 1; k <= 40; ++k) out << k << "\n";
    });
    ++shapes;
  }
  ASSERT_EQ(shapes, 6);
  PaperExperimentOptions o = small_run(dir, "out");
  o.correspondence_samples = 40;
  const PaperReport r = run_paper_experiment(o);
  EXPECT_EQ(r.correspondence_pairs, 12);  // 2 classes × 3 poses × 2 others
  std::istringstream in(read_file(o.out + "/point_map_pairs.csv"));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "method,source,target,mean_error");
  std::map<std::string, std::vector<double>> errors;
  std::set<std::pair<std::string, std::string>> pairs;
  while (std::getline(in, line)) {
    std::stringstream fields(line);
    std::string method, source, target, error;
    std::getline(fields, method, ',');
    std::getline(fields, source, ',');
    std::getline(fields, target, ',');
    std::getline(fields, error, ',');
    EXPECT_NE(source, target) << line;
    EXPECT_EQ(class_from_name(source), class_from_name(target)) << line << ": not one class";
    errors[method].push_back(std::stod(error));
    pairs.insert({source, target});
  }
  EXPECT_EQ(pairs.size(), 12u);
  ASSERT_EQ(errors.size(), 2u);
  for (const auto& [method, list] : errors) {
    const std::vector<double>& reported = r.correspondence_mean_error.at(method);
    ASSERT_EQ(list.size(), reported.size()) << method;
    for (size_t k = 0; k < list.size(); ++k)
      EXPECT_NEAR(list[k], reported[k], 1e-8 * (1 + reported[k])) << method << " row " << k;
  }
}

TEST(PaperExperiment, AnUnusableShapeIsLeftOutAndNamed) {
  const std::string dir = dataset_with_an_unusable_shape("paper_unusable");
  const PaperExperimentOptions o = small_run(dir, "out");
  const PaperExperimentSummary s = paper_experiment(o);
  EXPECT_EQ(s.shapes, 6);  // the 6 usable poses
  ASSERT_EQ(count_left_out(s.failures), 1) << shape_failures_json(s.failures).dump(2);
  const ShapeFailure* f = nullptr;
  for (const ShapeFailure& x : s.failures)
    if (x.left_out()) f = &x;
  EXPECT_EQ(f->name, "broken9");
  EXPECT_NE(f->path.find("broken9.off"), std::string::npos);
  // Its forms are computed (on copies scaled to unit size), but reach 1e300 (coulomb) and 1e150 (cmds, on
  // the mesh its repair keeps): ICP cannot take them. The first method's record; the shape is dropped for
  // every method.
  EXPECT_EQ(f->stage, "alignment");
  EXPECT_EQ(f->method, "coulomb");
  EXPECT_FALSE(f->reason.empty());

  // Every method's matrix holds the same 6 shapes, without the unusable one.
  for (const char* m : {"coulomb", "cmds"}) {
    const NamedDistances D = read_distance_csv(o.out + "/distances/" + m + ".csv");
    EXPECT_EQ(D.names.size(), 6u) << m;
    EXPECT_EQ(std::find(D.names.begin(), D.names.end(), "broken9"), D.names.end()) << m;
  }
  EXPECT_EQ(read_file(o.out + "/labels.csv").find("broken9"), std::string::npos);
  const std::string report = read_file(o.out + "/report.md");
  EXPECT_NE(report.find("## Shapes left out and fallbacks"), std::string::npos) << report;
  EXPECT_NE(report.find("| broken9 |"), std::string::npos) << report;
  EXPECT_NE(report.find("exit code 3"), std::string::npos) << report;
  const nlohmann::json metrics = nlohmann::json::parse(read_file(o.out + "/metrics.json"));
  ASSERT_TRUE(metrics.contains("failures"));
  bool named = false;
  for (const auto& x : metrics["failures"])
    named = named || (x["name"] == "broken9" && x["left_out"] == true);
  EXPECT_TRUE(named) << metrics["failures"].dump(2);

  // --strict: the same shape stops the run.
  PaperExperimentOptions strict = small_run(dir, "strict");
  strict.canon.strict = true;
  try {
    paper_experiment(strict);
    ADD_FAILURE() << "strict run completed";
  } catch (const Error& e) {
    EXPECT_EQ(dynamic_cast<const IoError*>(&e), nullptr);
  }
}

TEST(PaperExperiment, NothingFailedMeansNoFailuresAnywhere) {
  const std::string dir = dataset_with_an_unusable_shape("paper_clean", false);
  const PaperExperimentOptions o = small_run(dir, "out");
  const PaperExperimentSummary s = paper_experiment(o);
  EXPECT_EQ(s.shapes, 6);
  EXPECT_TRUE(s.failures.empty()) << shape_failures_json(s.failures).dump(2);
  EXPECT_EQ(read_file(o.out + "/report.md").find("## Shapes left out"), std::string::npos);
  EXPECT_FALSE(nlohmann::json::parse(read_file(o.out + "/metrics.json")).contains("failures"));
}

// The driver returns the report's data and writes its data files, never report.md: the writer does that
// from the returned report alone.
TEST(PaperExperiment, TheRunReturnsTheReportsDataAndTheWriterWritesIt) {
  const std::string dir = test::scratch_dir("paper-run-data");
  PaperExperimentOptions o;
  o.data = test::generated_dataset(dir, 2, 3, 400);
  o.out = dir + "/out";
  o.methods = {"coulomb"};
  o.table1 = false;
  o.figures = false;
  const PaperReport r = run_paper_experiment(o);
  EXPECT_TRUE(fs::exists(o.out + "/metrics.json"));
  EXPECT_TRUE(fs::exists(o.out + "/distances/coulomb.csv"));
  EXPECT_FALSE(fs::exists(o.out + "/report.md")) << "the run writes data, not the report";
  EXPECT_EQ(r.summary.shapes, 8);  // 2 classes × (3 poses + 1 glued here)
  ASSERT_TRUE(r.retrieval.count("coulomb"));
  EXPECT_GE(r.retrieval.at("coulomb").map, 0.0);
  EXPECT_LE(r.retrieval.at("coulomb").map, 1.0);
  EXPECT_EQ(r.noise.size(), 2u);  // each glued shape against its clean pose
  write_paper_report(r, o.out);
  std::ifstream in(o.out + "/report.md");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_NE(text.str().find("| Coulomb | Hausdorff |"), std::string::npos);
}

// The report writer on a hand-made report, without a run: the retrieval table under every distance, "—" where
// nothing was measured (no noisy query), the shape left out named with its reason, the options it states.
TEST(PaperReport, WriterSaysWhatTheReportHolds) {
  PaperReport r;
  r.options.data = "DATA";
  r.options.methods = {"coulomb", "cmds"};
  r.shapes = {{"cat0", "cat", false, true, 100, "", "none", {}}, {"dog0", "dog", false, true, 100, "", "none", {}}};
  for (const std::string m : {"coulomb", "cmds"}) {
    PaperReport::Retrieval x{m == "coulomb" ? 0.75 : 0.5, 1, 0.5, 1, 0.25, 0.875, -1};
    r.retrieval[m] = x;
    for (const char* kind : {"hausdorff", "chamfer", "rmse"}) r.retrieval_by_distance[m][kind] = x;
  }
  r.summary.shapes = 2;
  r.summary.failures.push_back(read_failure("bad3", "bad3.off", Error("bad3.off: line 4: expected 3 numbers")));
  r.options.table1 = false;
  r.options.figures = false;
  const std::string dir = test::scratch_dir("paper-report");
  write_paper_report(r, dir);
  std::ifstream in(dir + "/report.md");
  std::stringstream text;
  text << in.rdbuf();
  const std::string report = text.str();
  EXPECT_NE(report.find("| Coulomb | Hausdorff | 0.750 | 1.000 | 0.500 | 1.000 | 0.250 | 0.875 | — |"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("| classical MDS | RMSE | 0.500 |"), std::string::npos);
  EXPECT_NE(report.find("Coulomb > classical MDS"), std::string::npos) << "the methods ordered by mAP";
  EXPECT_NE(report.find("bad3"), std::string::npos) << "the shape left out is named";
  EXPECT_NE(report.find("line 4: expected 3 numbers"), std::string::npos) << "with its reason";
  EXPECT_NE(report.find("`DATA`"), std::string::npos);
}

// The report's sentences fit the methods run: with one MDS method, no "better MDS" and no range over one
// method; with two, "the better of the two" and a range with each end named; the claims not checked are named
// with what they would need; Table 1's times read with their units.
TEST(PaperReport, SentencesFitTheMethodsRun) {
  const auto report_of = [](const std::vector<std::string>& methods, const std::string& name) {
    PaperReport r;
    r.options.data = "DATA";
    r.options.methods = methods;
    r.options.table1 = false;
    r.options.figures = false;
    r.shapes = {{"cat0", "cat", false, true, 100, "", "none", {}}, {"dog0", "dog", false, true, 100, "", "none", {}}};
    double rms = 0.01;
    for (const std::string& m : methods) {
      PaperReport::Retrieval x{m == "coulomb" ? 0.75 : m == "cmds" ? 0.5 : 0.625, 1, 0.5, 1, 0.25, 0.875, -1};
      r.retrieval[m] = x;
      for (const char* kind : {"hausdorff", "chamfer", "rmse"}) r.retrieval_by_distance[m][kind] = x;
      r.noise.push_back({"cat0_noisy", m, rms, 2 * rms, rms});
      r.pose_variation[m] = 0.02;
      rms += 0.01;
    }
    r.summary.shapes = 2;
    r.table1.push_back({"swissroll", 561, 0.0879, 0.000135, 0.00013, 0.000325, true});
    const std::string dir = test::scratch_dir(name);
    write_paper_report(r, dir);
    std::ifstream in(dir + "/report.md");
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  };
  const std::string one = report_of({"coulomb", "cmds"}, "paper-report-one-mds");
  EXPECT_NE(one.find("vs 0.500 (classical MDS) under the paper's Hausdorff distance"), std::string::npos) << one;
  EXPECT_EQ(one.find("better"), std::string::npos) << one;
  EXPECT_NE(one.find("vs 2.00% (classical MDS);"), std::string::npos) << one;
  EXPECT_EQ(one.find("2.00%–2.00%"), std::string::npos) << one;
  EXPECT_NE(one.find("Not checked by this run:\n\n- the cost per iteration and the pre-computation (Table 1): "
                     "would need Table 1"),
            std::string::npos)
      << one;
  EXPECT_NE(one.find("- more projection steps, less metric distortion (Fig. 5): would need"), std::string::npos)
      << one;
  EXPECT_NE(one.find("Ours: median of 5 runs"), std::string::npos) << one;
  EXPECT_NE(one.find("| swissroll | 561 | 87.9 ms (140 ms) | 135 µs (30 ms) | 130 µs (3 ms) | 325 µs (10 ms) |"),
            std::string::npos)
      << one;

  const std::string two = report_of({"coulomb", "cmds", "smacof"}, "paper-report-two-mds");
  EXPECT_NE(two.find("vs 0.625 (SMACOF, the better of the two MDS methods run)"), std::string::npos) << two;
  EXPECT_NE(two.find("vs 2.00% (classical MDS) to 3.00% (SMACOF);"), std::string::npos) << two;

  const std::string none = report_of({"lbo"}, "paper-report-no-claims");
  EXPECT_NE(none.find("- retrieval against MDS (Fig. 8) and robustness to topological noise (Fig. 2, 6): would "
                      "need the paper's method (`--methods` with `coulomb`) and an MDS method"),
            std::string::npos)
      << none;
}

}  // namespace paper_experiment_test
}  // namespace cshapes
