#include "cshapes/experiments/topkids_experiment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cshapes/data/articulated.h"
#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/mesh/rigid_transform.h"
#include "cshapes/pipeline/canonical_forms.h"
#include "tests/test_support.h"

namespace cshapes {
namespace topkids_experiment_test {

namespace fs = std::filesystem;

// Identity ground truth "v v" for every vertex, SHREC'16 style.
std::string identity_pairs(Index n) {
  std::ostringstream s;
  for (Index v = 1; v <= n; ++v) s << "     " << v << "      " << v << " \n";
  return s.str();
}

// A small TOPKIDS-like folder: ref.off (a generated biped, ~600 vertices), moved.off (the same mesh rigidly
// moved) and posed.off (another pose of it), both with identity ground truth; moved has a mirrored truth
// file too (every vertex to itself, so it changes nothing).
struct SyntheticKids {
  std::string dir;
  Mesh reference, moved, posed;
};

SyntheticKids make_kids(const std::string& tag) {
  ArticulatedOptions ao;
  ao.poses = 2;
  ao.seed = 3;
  ao.rest.target_vertices = 600;
  ArticulatedClass c = generate_articulated("biped", ao);
  SyntheticKids k;
  k.dir = test::scratch_dir(tag);
  k.reference = c.poses[0];
  k.moved = c.poses[0];
  k.moved.V = random_rigid_transform(7, 2.0, false).apply(c.poses[0].V);
  k.posed = c.poses[1];
  write_mesh(k.dir + "/ref.off", k.reference);
  write_mesh(k.dir + "/moved.off", k.moved);
  write_mesh(k.dir + "/posed.off", k.posed);
  const std::string truth = identity_pairs(k.reference.num_vertices());
  test::write_text(k.dir + "/moved_ref.txt", truth);
  test::write_text(k.dir + "/moved_sym.txt", truth);
  test::write_text(k.dir + "/posed_ref.txt", truth);
  return k;
}

TopkidsExperimentOptions options_for(const SyntheticKids& k, const std::string& out) {
  TopkidsExperimentOptions o;
  o.data = k.dir;
  o.out = out;
  o.reference = "ref";
  o.methods = {"coulomb"};
  o.samples = 200;
  return o;
}

const TopkidsRow& row_of(const TopkidsExperimentResult& r, const std::string& pose,
                         const std::string& method) {
  for (const TopkidsRow& row : r.rows)
    if (row.pose == pose && row.method == method) return row;
  throw Error("no row " + pose + " " + method);
}

// Clears the geodesics test hook whatever the test's outcome.
struct HookGuard {
  explicit HookGuard(std::function<void(GeodesicMethod, const std::string&)> hook) {
    set_geodesics_test_hook(std::move(hook));
  }
  ~HookGuard() { set_geodesics_test_hook({}); }
};

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(TopkidsExperiment, IdenticalPairMapsWithoutErrorAndRerunsFromCache) {
  SyntheticKids k = make_kids("topkids_synthetic");
  const std::string out = k.dir + "/out";
  TopkidsExperimentOptions o = options_for(k, out);
  TopkidsExperimentResult r = run_topkids_experiment(o);

  EXPECT_EQ(r.poses, (std::vector<std::string>{"moved", "posed"}));  // every NAME_ref.txt, by name
  EXPECT_EQ(r.methods, (std::vector<std::string>{"inputs", "coulomb"}));
  ASSERT_EQ(r.rows.size(), 4u);
  // The rigidly moved copy: ICP finds the motion, every vertex maps onto itself, in both the inputs and the
  // Coulomb forms (a form of a moved mesh is the moved form).
  for (const std::string m : {"inputs", "coulomb"}) {
    const TopkidsRow& row = row_of(r, "moved", m);
    EXPECT_EQ(row.samples, 200) << m;
    EXPECT_EQ(row.unmapped, 0) << m;
    EXPECT_NEAR(row.mean_error, 0.0, 1e-12) << m;
    EXPECT_EQ(row.under_0_1, 1.0) << m;
    EXPECT_NEAR(row.whole_map_mean_error, 0.0, 1e-12) << m;
    EXPECT_FALSE(row.reflected) << m;
  }
  EXPECT_GE(row_of(r, "moved", "coulomb").torn_edges, 0);
  EXPECT_EQ(row_of(r, "moved", "inputs").torn_edges, -1);
  // Another pose: errors are finite fractions of the shape's size, and the Coulomb forms, which undo
  // articulation, map better than the posed input aligned rigidly.
  const TopkidsRow& posed_inputs = row_of(r, "posed", "inputs");
  const TopkidsRow& posed_coulomb = row_of(r, "posed", "coulomb");
  EXPECT_GT(posed_inputs.mean_error, 0.0);
  EXPECT_LT(posed_inputs.mean_error, 1.0);
  EXPECT_LT(posed_coulomb.mean_error, 1.0);
  // Pooled summaries: 400 samples per method, curves non-decreasing up to the fractions in the table.
  ASSERT_EQ(r.summaries.size(), 2u);
  for (const TopkidsSummary& s : r.summaries) {
    EXPECT_EQ(s.samples, 400);
    for (Index t = 1; t < s.fraction.size(); ++t) EXPECT_GE(s.fraction[t], s.fraction[t - 1]);
    EXPECT_GE(s.under_0_25, s.under_0_1);
    EXPECT_GE(s.under_0_1, 0.5);  // the moved pose alone is half the samples, all exact
    // Forgiving the flip per vertex is the more lenient reading.
    EXPECT_LE(s.mean_error, s.whole_map_mean_error + 1e-12);
    EXPECT_GE(s.whole_map_under_0_1, 0.5);
  }
  EXPECT_EQ(r.thresholds.size(), 101);
  EXPECT_DOUBLE_EQ(r.thresholds[r.thresholds.size() - 1], 0.5);
  EXPECT_EQ(r.forms_computed, 3);
  EXPECT_EQ(r.scorings_computed, 2);
  // The run writes its data files only: no figure, no report.
  for (const char* file : {"topkids.csv", "curves.csv", "topkids.json"})
    EXPECT_TRUE(fs::exists(fs::path(out) / file)) << file;
  for (const char* file : {"report.md", "topkids.png"})
    EXPECT_FALSE(fs::exists(fs::path(out) / file)) << file;
  const nlohmann::json j = nlohmann::json::parse(read_file(out + "/topkids.json"));
  EXPECT_EQ(j.at("rows").size(), 4u);
  EXPECT_EQ(j.at("figure"), "");
  EXPECT_FALSE(j.contains("failures"));

  // A rerun computes nothing and writes the same table.
  const std::string csv = read_file(out + "/topkids.csv");
  TopkidsExperimentResult again = run_topkids_experiment(o);
  EXPECT_EQ(again.forms_computed, 0);
  EXPECT_EQ(again.forms_cached, 3);
  EXPECT_EQ(again.scorings_computed, 0);
  EXPECT_EQ(again.scorings_cached, 2);
  EXPECT_EQ(read_file(out + "/topkids.csv"), csv);
  fs::remove_all(k.dir);
}

// A pose that is the reference itself, with a ground truth that sends vertex v to π(v) = v + n/2 (mod n),
// and a mirror file that pairs v with σ(v) = π⁻¹(v) on the pose: the identity map ICP finds is far from the
// truth and exactly on the mirrored truth ref(σ(v)) = v. Read the other way (σ(v) a vertex of the
// reference) the mirrored truth would be v − n/2, as far as the truth: the map would not be mirrored.
TEST(TopkidsExperiment, MirrorFilePairsPoseVerticesAndAMirroredMapIsCounted) {
  SyntheticKids k = make_kids("topkids_mirrored");
  const Index n = k.reference.num_vertices();
  write_mesh(k.dir + "/swapped.off", k.reference);
  std::ostringstream truth, mirror;
  for (Index v = 0; v < n; ++v) {
    truth << v + 1 << " " << (v + n / 2) % n + 1 << "\n";
    mirror << v + 1 << " " << (v - n / 2 + n) % n + 1 << "\n";
  }
  test::write_text(k.dir + "/swapped_ref.txt", truth.str());
  test::write_text(k.dir + "/swapped_sym.txt", mirror.str());
  TopkidsExperimentOptions o = options_for(k, k.dir + "/out");
  o.methods = {};  // the inputs alone
  o.poses = {"moved", "swapped"};
  const TopkidsExperimentResult r = run_topkids_experiment(o);
  const TopkidsRow& swapped = row_of(r, "swapped", "inputs");
  EXPECT_GT(swapped.direct_mean_error, 0.1);
  EXPECT_NEAR(swapped.mirrored_mean_error, 0.0, 1e-12);
  EXPECT_NEAR(swapped.mean_error, 0.0, 1e-12);  // forgiven per vertex
  EXPECT_TRUE(swapped.mirrored);
  EXPECT_TRUE(swapped.whole_map_mirrored);
  const TopkidsRow& moved = row_of(r, "moved", "inputs");  // exact, its mirror file the identity
  EXPECT_FALSE(moved.mirrored);
  EXPECT_FALSE(moved.whole_map_mirrored);
  ASSERT_EQ(r.summaries.size(), 1u);
  EXPECT_EQ(r.summaries[0].poses, 2);
  EXPECT_EQ(r.summaries[0].mirrored_poses, 1);
  EXPECT_NEAR(r.summaries[0].median_pose_mean_error, 0.0, 1e-12);
  EXPECT_NEAR(r.summaries[0].median_pose_direct_error, swapped.direct_mean_error / 2, 1e-12);
  // The CSV documents the new columns.
  const std::string csv = read_file(o.out + "/topkids.csv");
  EXPECT_TRUE(contains(csv, "direct_mean_error,mirrored_mean_error,mirror_ratio,mirrored,")) << csv;
  const nlohmann::json j = nlohmann::json::parse(read_file(o.out + "/topkids.json"));
  EXPECT_EQ(j["summary"][0]["mirrored_poses"], 1);
  fs::remove_all(k.dir);
}

TEST(TopkidsExperiment, MissingOrMalformedFilesAreNamed) {
  SyntheticKids k = make_kids("topkids_bad");
  TopkidsExperimentOptions o = options_for(k, k.dir + "/out");
  auto message = [&] {
    try {
      run_topkids_experiment(o);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  // A malformed line in a ground-truth file: file and line, before any canonical form is computed.
  test::write_text(k.dir + "/posed_ref.txt", "1 1\n2 2 2\n");
  EXPECT_EQ(message(),
            k.dir + "/posed_ref.txt:2: expected two 1-based vertex indices, got 3 fields ('2 2 2')");
  EXPECT_FALSE(fs::exists(k.dir + "/out/cache"));
  // A ground-truth file without its mesh.
  test::write_text(k.dir + "/posed_ref.txt", identity_pairs(k.reference.num_vertices()));
  test::write_text(k.dir + "/lost_ref.txt", "1 1\n");
  EXPECT_EQ(message(), k.dir + "/lost: no mesh file (looked for .off .ply .obj .stl .vert)");
  fs::remove(k.dir + "/lost_ref.txt");
  // No reference mesh.
  o.reference = "nobody";
  EXPECT_EQ(message(), k.dir + "/nobody: no mesh file (looked for .off .ply .obj .stl .vert)");
  // A folder without query poses.
  o.data = k.dir + "/out";
  fs::create_directories(o.data);
  EXPECT_EQ(message(), o.data + ": no query pose (no NAME_ref.txt besides nobody's)");
  fs::remove_all(k.dir);
}

TEST(TopkidsExperiment, APoseWhoseFormFailsIsLeftOutAndNamed) {
  SyntheticKids k = make_kids("topkids_left_out");
  TopkidsExperimentOptions o = options_for(k, k.dir + "/out");
  o.methods = {"cmds"};
  o.samples = 50;
  // The geodesics of posed.off fail (no fallback from fast marching): posed is left out, moved is measured.
  HookGuard guard([](GeodesicMethod, const std::string& name) {
    if (contains(name, "posed")) fail(name, ": injected failure");
  });
  const TopkidsExperimentResult r = run_topkids_experiment(o);
  EXPECT_EQ(r.poses, (std::vector<std::string>{"moved"}));
  ASSERT_EQ(r.failures.size(), 1u);
  EXPECT_EQ(r.failures[0].name, "posed");
  EXPECT_EQ(r.failures[0].method, "cmds");
  EXPECT_TRUE(r.failures[0].left_out());
  EXPECT_TRUE(contains(r.failures[0].reason, "injected failure")) << r.failures[0].reason;
  ASSERT_EQ(r.rows.size(), 2u);  // moved: inputs and cmds
  for (const TopkidsRow& row : r.rows) EXPECT_EQ(row.pose, "moved");
  for (const TopkidsSummary& s : r.summaries) EXPECT_EQ(s.samples, 50) << s.method;
  const nlohmann::json j = nlohmann::json::parse(read_file(o.out + "/topkids.json"));
  ASSERT_EQ(j.at("failures").size(), 1u);
  EXPECT_EQ(j.at("failures")[0].at("name"), "posed");

  // Without the reference's forms there is nothing to measure: the run stops, naming it (a new folder: the
  // reference's form is cached in the first).
  o.out = k.dir + "/out2";
  HookGuard reference_fails([](GeodesicMethod, const std::string& name) {
    if (contains(name, "ref.off")) fail(name, ": injected failure");
  });
  try {
    run_topkids_experiment(o);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_TRUE(contains(e.what(), "ref left out: the cmds canonical form failed")) << e.what();
  }
  fs::remove_all(k.dir);
}

TEST(TopkidsExperiment, FigureOutcomeIsRecordedInTheResultAndTheJson) {
  const std::string out = test::scratch_dir("topkids_figure");
  TopkidsExperimentOptions o;
  o.data = "DATA";
  o.out = out;
  TopkidsExperimentResult r;
  r.poses = {"kid07"};
  r.methods = {"inputs"};
  r.thresholds = Eigen::VectorXd::LinSpaced(3, 0.0, 0.5);

  o.figure = false;
  draw_topkids_figure(r, o);
  EXPECT_EQ(r.figure, "");
  EXPECT_EQ(r.figure_problem, "not requested (--no-draw)");
  nlohmann::json j = nlohmann::json::parse(read_file(out + "/topkids.json"));
  EXPECT_EQ(j.at("figure_problem"), "not requested (--no-draw)");
  EXPECT_EQ(j.at("data"), "DATA");

  // Asked for, but its script is not where $CSHAPES_PLOTS says: not drawn, and why, never an error.
  const std::string empty = test::scratch_dir("topkids_figure_no_scripts");
  setenv("CSHAPES_PLOTS", empty.c_str(), 1);
  o.figure = true;
  draw_topkids_figure(r, o);
  unsetenv("CSHAPES_PLOTS");
  EXPECT_EQ(r.figure, "");
  EXPECT_TRUE(contains(r.figure_problem, "topkids_figure.py was not found")) << r.figure_problem;
  j = nlohmann::json::parse(read_file(out + "/topkids.json"));
  EXPECT_EQ(j.at("figure_problem"), r.figure_problem);
  EXPECT_FALSE(fs::exists(out + "/topkids.png"));
  fs::remove_all(out);
  fs::remove_all(empty);
}

// A result as run_topkids_experiment returns it, made by hand: two poses, the inputs and Coulomb, one pose
// left out, the inputs' pooled mean not measured (every sample unmapped).
TopkidsExperimentResult hand_made_result() {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  TopkidsExperimentResult r;
  r.poses = {"kid07", "kid08"};
  r.methods = {"inputs", "coulomb"};
  auto row = [](const std::string& pose, const std::string& method, double mean, double under, long torn) {
    TopkidsRow x;
    x.pose = pose;
    x.method = method;
    x.samples = 100;
    x.mean_error = mean;
    x.median_error = mean;
    x.under_0_25 = under;
    x.whole_map_mean_error = 2 * mean;
    x.whole_map_under_0_25 = under / 2;
    x.torn_edges = torn;
    return x;
  };
  r.rows = {row("kid07", "inputs", 0.3, 0.5, -1), row("kid07", "coulomb", 0.1, 0.9, 3),
            row("kid08", "inputs", 0.35, 0.4, -1), row("kid08", "coulomb", 0.12, 0.8, 5)};
  r.rows[1].whole_map_mirrored = true;
  r.rows[1].mirrored = true;
  r.rows[1].reflected = true;
  r.rows[3].whole_map_mirrored = true;  // nearer the mirrored truth, not clearly: "m"
  r.rows[3].mirrored = false;
  r.rows[3].repair = "removed 2 duplicate faces";
  TopkidsSummary inputs;
  inputs.method = "inputs";
  inputs.samples = 200;
  inputs.mean_error = inputs.median_error = inputs.whole_map_mean_error = nan;
  TopkidsSummary coulomb;
  coulomb.method = "coulomb";
  coulomb.samples = 200;
  coulomb.mean_error = 0.11;
  coulomb.median_error = 0.1;
  coulomb.under_0_1 = 0.6;
  coulomb.under_0_25 = 0.85;
  coulomb.whole_map_mean_error = 0.22;
  coulomb.whole_map_under_0_1 = 0.3;
  coulomb.whole_map_under_0_25 = 0.425;
  coulomb.poses = 2;
  coulomb.mirrored_poses = 1;
  coulomb.median_pose_mean_error = 0.11;
  inputs.poses = 2;
  inputs.median_pose_mean_error = nan;
  r.summaries = {inputs, coulomb};
  r.reference_repair = {{"coulomb", "split 1 non-manifold edge"}};
  r.reference_sqrt_area = 97.94;
  r.figure_problem = "not requested (--no-draw)";
  r.failures.push_back({"kid09", "DATA/kid09.off", "coulomb", "canonical form", "it diverged", ""});
  return r;
}

TEST(TopkidsExperiment, ReportSaysTheTablesTheFailuresAndWhatWasNotMeasured) {
  const std::string out = test::scratch_dir("topkids_report");
  TopkidsExperimentOptions o;
  o.data = "DATA";
  o.out = out;
  o.reference = "kid00";
  o.methods = {"coulomb"};
  o.samples = 100;
  TopkidsExperimentResult r = hand_made_result();
  write_topkids_report(r, o, out);
  const std::string report = read_file(out + "/report.md");
  EXPECT_TRUE(contains(report, "Reference `kid00`; 2 query poses (kid07, kid08)")) << report;
  EXPECT_TRUE(contains(report, "over √area of the reference (97.94)")) << report;
  EXPECT_TRUE(contains(report, "100 ground-truth vertices per pose")) << report;
  // The pooled table: a row per method, "—" where nothing was measured.
  // Mean, median, median of the pose means and the mirrored poses side by side.
  EXPECT_TRUE(contains(
      report, "| Coulomb | 200 | 0.110 | 0.100 | 0.110 | 1 of 2 | 0.600 | 0.850 | 0.220 | 0.300 | 0.425 |"))
      << report;
  EXPECT_TRUE(contains(
      report,
      "| inputs (no canonical form) | 200 | — | — | — | 0 of 2 | 0.000 | 0.000 | — | 0.000 | 0.000 |"))
      << report;
  EXPECT_TRUE(contains(report, "is at most 0.50 of its mean error against the truth alone")) << report;
  EXPECT_FALSE(contains(report, "nan")) << report;
  EXPECT_TRUE(contains(report,
                       "No figure (not requested (--no-draw)); draw it with "
                       "`scripts/python.sh experiments/plots/topkids_figure.py " +
                           out + "`"))
      << report;
  // The pose left out, named with its method and reason.
  EXPECT_TRUE(contains(report, "## Shapes left out and fallbacks")) << report;
  EXPECT_TRUE(
      contains(report, "| kid09 | `DATA/kid09.off` | coulomb | canonical form | left out: it diverged |"))
      << report;
  // Per pose: mean (≤ 0.25) per vertex | per whole map, M and R marks.
  EXPECT_TRUE(contains(report, "| kid07 | 0.300 (0.50) | 0.600 (0.25) | 0.100 (0.90) | 0.200 (0.45) M R |"))
      << report;
  EXPECT_TRUE(contains(report, "| kid08 | 0.350 (0.40) | 0.700 (0.20) | 0.120 (0.80) | 0.240 (0.40) m |"))
      << report;
  EXPECT_TRUE(contains(report, "- Coulomb, reference: split 1 non-manifold edge\n")) << report;
  EXPECT_TRUE(contains(report, "- Coulomb: removed 2 duplicate faces\n")) << report;
  EXPECT_TRUE(contains(report, "- Coulomb torn edges per pose: kid07 3 kid08 5\n")) << report;
  EXPECT_TRUE(contains(
      report, "`cshapes experiment topkids --data DATA --out " + out + " --methods coulomb --samples 100`"))
      << report;

  // Drawn: the figure instead of the hint; no failure section when nothing failed.
  r.figure = "topkids.png";
  r.figure_problem = "";
  r.failures.clear();
  write_topkids_report(r, o, out);
  const std::string drawn = read_file(out + "/report.md");
  EXPECT_TRUE(contains(drawn, "![cumulative error curves and per-pose errors](topkids.png)")) << drawn;
  EXPECT_FALSE(contains(drawn, "No figure")) << drawn;
  EXPECT_FALSE(contains(drawn, "Shapes left out")) << drawn;
  fs::remove_all(out);
}

TEST(TopkidsExperiment, CliRunsAndRefusesBadOptions) {
  SyntheticKids k = make_kids("topkids_cli");
  const std::string out = k.dir + "/out";
  test::CliResult r = test::run_cli("experiment topkids --data '" + k.dir + "' --out '" + out +
                                    "' --reference ref --poses moved --methods coulomb --samples 50 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"scorings_computed\": 1"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(out + "/report.md"));
  r = test::run_cli("experiment topkids --data '" + k.dir + "' --out '" + out + "' --methods coulomb,pca");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--methods: unknown canonization method 'pca'; known: coulomb, cmds, smacof"),
            std::string::npos)
      << r.err;
  r = test::run_cli("experiment topkids --data '" + k.dir + "/none' --out '" + out + "' --reference ref");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("none: not a folder"), std::string::npos) << r.err;
  fs::remove_all(k.dir);
}

// --resample: the reference and the poses remeshed independently, the truth carried through the remeshes.
// The rigid copy no longer maps exactly: each ground-truth vertex moves to its remesh, to the nearest remesh
// vertex of the reference and back to an input vertex, each step within about a remesh edge.
TEST(TopkidsExperiment, ResampledRunCarriesTheTruthThroughTheRemeshes) {
  SyntheticKids k = make_kids("topkids_resampled");
  TopkidsExperimentOptions o = options_for(k, k.dir + "/out");
  o.methods = {"cmds"};
  o.resample.vertices = 400;
  const TopkidsExperimentResult r = run_topkids_experiment(o);
  write_topkids_report(r, o, o.out);
  ASSERT_TRUE(r.resampled);
  ASSERT_EQ(r.resampling.shapes.size(), 3u);  // ref, moved, posed
  double edge = 0;
  for (const ResampledShape& s : r.resampling.shapes) {
    ASSERT_TRUE(s.remeshed) << s.name << ": " << s.note;
    EXPECT_NEAR(static_cast<double>(s.vertices), 400.0, 4.0) << s.name;
    edge = std::max(edge, mesh_info(read_mesh(s.file)).mean_edge_length);
  }
  ASSERT_EQ(r.carried.size(), 2u);
  for (const TopkidsCarriedRow& c : r.carried) {
    EXPECT_EQ(c.vertices, k.reference.num_vertices()) << c.pose;  // identity truth: every vertex
    EXPECT_GT(c.max_distance, 0.0) << c.pose;
    EXPECT_EQ(c.off_part, 0) << c.pose;
    EXPECT_EQ(c.relocated, 0) << c.pose;
  }
  EXPECT_GT(r.reference_back_distance, 0.0);
  ASSERT_EQ(r.rows.size(), 4u);
  for (const TopkidsRow& row : r.rows) {
    EXPECT_EQ(row.samples, 200) << row.pose << " " << row.method;
    EXPECT_EQ(row.unmapped, 0) << row.pose << " " << row.method;
  }
  // The rigid copy's inputs: errors of a fraction of a remesh edge on average (not 0 as at full resolution).
  const TopkidsRow& moved = row_of(r, "moved", "inputs");
  EXPECT_GT(moved.mean_error, 0.0);
  EXPECT_LT(moved.mean_error, edge / r.reference_sqrt_area);
  EXPECT_EQ(moved.under_0_1, 1.0);
  EXPECT_LT(row_of(r, "posed", "cmds").mean_error, 1.0);

  const std::string report = read_file(o.out + "/report.md");
  EXPECT_TRUE(contains(report, "Resampled: the reference and every pose were remeshed to about 400"))
      << report;
  EXPECT_TRUE(contains(report, "## Resampling")) << report;
  EXPECT_TRUE(contains(report, "| moved | ")) << report;
  EXPECT_TRUE(contains(report, "--resample 400")) << report;
  const nlohmann::json j = nlohmann::json::parse(read_file(o.out + "/topkids.json"));
  EXPECT_EQ(j.at("resample").at("vertices"), 400);
  EXPECT_EQ(j.at("resample").at("carried").size(), 2u);
  fs::remove_all(k.dir);
}

TEST(TopkidsExperiment, RealNoiseOnePoseInputs) {
  // kid07 onto kid00 (non-manifold edge, duplicate face), the inputs alone (a canonical form of these
  // 12,000-vertex meshes takes 10 s to minutes: that is the CLI run's), 100 ground-truth vertices: the
  // reference's repair for the geodesics is reported, every vertex is mapped, and the errors are fractions of
  // the body's size; with the mirrored truth some vertices are forgiven a flip.
  CSHAPES_REQUIRE_DATA();
  const std::string data = test::data_dir() + "/topkids";
  if (!fs::exists(data + "/kid00.off")) GTEST_SKIP() << data << " not found";
  TopkidsExperimentOptions o;
  o.data = data;
  o.out = test::scratch_dir("topkids_data");
  o.poses = {"kid07"};
  o.methods = {};
  o.samples = 100;
  TopkidsExperimentResult r = run_topkids_experiment(o);
  ASSERT_EQ(r.rows.size(), 1u);
  EXPECT_NE(r.scoring_repair.find("non-manifold"), std::string::npos) << r.scoring_repair;
  EXPECT_NEAR(r.reference_sqrt_area, std::sqrt(9591.71), 0.1);  // `cshapes info`: area 9,591.71
  const TopkidsRow& row = r.rows[0];
  EXPECT_EQ(row.method, "inputs");
  EXPECT_EQ(row.samples, 100);
  EXPECT_EQ(row.unmapped, 0);
  EXPECT_GT(row.mean_error, 0.0);
  EXPECT_LT(row.mean_error, 1.5);
  fs::remove_all(o.out);
}

}  // namespace topkids_experiment_test
}  // namespace cshapes
