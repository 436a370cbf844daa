// The pose-invariance measure (experiments/pose_invariance.h): known answers on generated shapes with known
// correspondences, and the TOPKIDS correspondence reader's errors.
#include "cshapes/experiments/pose_invariance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <sstream>

#include "cshapes/support/atomic_file.h"
#include "cshapes/data/dataset.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/mesh/rigid_transform.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/experiments/figures.h"
#include "cshapes/pipeline/canonical_forms.h"
#include "tests/test_support.h"

namespace cshapes {
namespace pose_invariance_test {

namespace fs = std::filesystem;

// Writes NAME.off and corres/NAME.vts (1-based: sample s is vertex order[s]).
void write_pose(const std::string& dir, const std::string& name, const Mesh& m,
                const std::vector<int>& order) {
  write_mesh(dir + "/" + name + ".off", m);
  std::ostringstream vts;
  for (int v : order) vts << v + 1 << "\n";
  test::write_text(dir + "/corres/" + name + ".vts", vts.str());
}

// The mesh with its vertices renumbered by a random permutation: new vertex k is old vertex perm[k].
Mesh permuted(const Mesh& m, std::vector<int>& perm, unsigned seed) {
  perm.resize(m.num_vertices());
  std::iota(perm.begin(), perm.end(), 0);
  std::mt19937 rng(seed);
  std::shuffle(perm.begin(), perm.end(), rng);
  std::vector<int> inverse(perm.size());
  for (size_t k = 0; k < perm.size(); ++k) inverse[perm[k]] = static_cast<int>(k);
  Mesh out;
  out.V.resize(m.V.rows(), 3);
  for (Index k = 0; k < m.V.rows(); ++k) out.V.row(k) = m.V.row(perm[k]);
  out.F = m.F;
  for (Index f = 0; f < m.F.rows(); ++f)
    for (int c = 0; c < 3; ++c) out.F(f, c) = inverse[m.F(f, c)];
  return out;
}

const PosePairRow& pair_row(const PoseInvarianceResult& r, const std::string& b, const std::string& form) {
  for (const PosePairRow& p : r.pairs)
    if (p.b == b && p.form == form) return p;
  throw Error("no pair row " + b + " " + form);
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// Clears the geodesics test hook whatever the test's outcome.
struct HookGuard {
  explicit HookGuard(std::function<void(GeodesicMethod, const std::string&)> hook) {
    set_geodesics_test_hook(std::move(hook));
  }
  ~HookGuard() { set_geodesics_test_hook({}); }
};

TEST(PoseInvariance, RigidCopiesHaveZeroPoseDistanceAndScalingHasTheKnownOne) {
  const std::string dir = test::scratch_dir("pose_rigid");
  const Mesh a = torus(24, 12, 1.0, 0.35);
  const Index n = a.num_vertices();
  std::vector<int> identity(n);
  std::iota(identity.begin(), identity.end(), 0);
  write_pose(dir, "ring0", a, identity);
  // ring1: moved by a rigid motion with a reflection, vertices renumbered; sample s is still a's vertex s.
  std::vector<int> perm;
  Mesh b = permuted(a, perm, 7);
  b.V = random_rigid_transform(3, 2.0, true).apply(b.V);
  std::vector<int> where(n);
  for (Index k = 0; k < n; ++k) where[perm[k]] = static_cast<int>(k);
  write_pose(dir, "ring1", b, where);
  // ring2: scaled by s about the centroid. The best rigid fit of a onto s·a is the identity, so the RMS is
  // (s − 1)·sqrt(mean ‖a − ā‖²), over the mean diagonal (1 + s)/2 · diag(a).
  const double s = 1.25;
  Mesh c = a;
  const Eigen::RowVector3d centroid = a.V.colwise().mean();
  c.V = ((a.V.rowwise() - centroid) * s).rowwise() + centroid;
  write_pose(dir, "ring2", c, identity);
  // Another class: not paired with the rings.
  write_pose(dir, "ball0", icosphere(2), [] {
    std::vector<int> v(162);
    std::iota(v.begin(), v.end(), 0);
    return v;
  }());

  PoseInvarianceOptions o;
  o.data = dir;
  o.out = dir + "/out";
  o.methods = {"cmds"};
  o.samples = 0;
  o.stress_sources = 4;
  o.label = "a,b";  // issue 22: a label with a comma broke the CSVs' columns
  const PoseInvarianceResult r = run_pose_invariance(o);
  // Pairs ring0-ring1, ring0-ring2, ring1-ring2 (not ball0), each for the input and cmds.
  EXPECT_EQ(r.pairs.size(), 6u);
  for (const char* csv : {"pose_pairs.csv", "pose_shapes.csv", "pose_summary.csv"}) {
    std::istringstream lines(read_file(o.out + "/" + csv));
    std::string header, first;
    std::getline(lines, header);
    std::getline(lines, first);
    EXPECT_EQ(first.rfind("\"a,b\",", 0), 0u) << csv << ": " << first;
  }
  const double diag = bbox_diagonal(a.V);
  EXPECT_LT(pair_row(r, "ring1", "input").rms, 1e-9);
  EXPECT_LT(pair_row(r, "ring1", "cmds").rms, 1e-6);  // classical MDS is blind to rigid motion and order
  const double spread = std::sqrt((a.V.rowwise() - centroid).rowwise().squaredNorm().mean());
  const double expected = (s - 1) * spread / ((1 + s) / 2 * diag);
  EXPECT_NEAR(pair_row(r, "ring2", "input").rms, expected, 1e-9 * expected);
  EXPECT_EQ(pair_row(r, "ring2", "input").samples, n);
  // The summary's "removed" share is 1 − form / input.
  for (const PoseSummaryRow& row : r.summary)
    if (row.form == "cmds" && row.class_name == "ring") {
      EXPECT_NEAR(row.removed, 1 - row.median_rms / row.median_input_rms, 1e-12);
    }
  // The run writes its data; the report is write_pose_invariance_report's.
  for (const char* f : {"pose_pairs.csv", "pose_shapes.csv", "pose_summary.csv"})
    EXPECT_TRUE(fs::exists(o.out + "/" + f)) << f;
  EXPECT_FALSE(fs::exists(o.out + "/pose.md"));
}

TEST(PoseInvariance, GeodesicStressIsSmallOnAPlaneAndLargeOnARoll) {
  // The input's own stress: Euclidean against fast-marching distances. A flat grid has equal ones (up to
  // fast marching's discretisation); a Swiss roll's Euclidean distances cut across the roll.
  const std::string dir = test::scratch_dir("pose_stress");
  const Mesh flat = grid(21, 21, 1.0, 1.0);
  const Mesh roll = swiss_roll();
  std::vector<int> flat_ids(flat.num_vertices()), roll_ids(roll.num_vertices());
  std::iota(flat_ids.begin(), flat_ids.end(), 0);
  std::iota(roll_ids.begin(), roll_ids.end(), 0);
  // Each second pose moved aside (stress does not see it): a file listed twice is refused.
  auto moved = [](Mesh m) {
    m.V.col(0).array() += 5.0;
    return m;
  };
  write_pose(dir, "flat0", flat, flat_ids);
  write_pose(dir, "flat1", moved(flat), flat_ids);
  write_pose(dir, "roll0", roll, roll_ids);
  write_pose(dir, "roll1", moved(roll), roll_ids);
  PoseInvarianceOptions o;
  o.data = dir;
  o.out = dir + "/out";
  o.methods = {"cmds"};
  o.stress_sources = 8;
  const PoseInvarianceResult r = run_pose_invariance(o);
  for (const PoseShapeRow& row : r.shapes) {
    if (row.form != "input") continue;
    if (row.shape.rfind("flat", 0) == 0) {
      EXPECT_LT(row.stress, 0.03) << row.shape;
    } else {
      EXPECT_GT(row.stress, 0.2) << row.shape;
    }
  }
  // Classical MDS unrolls the roll: its stress is far below the input's.
  double input_stress = 0, cmds_stress = 0;
  for (const PoseShapeRow& row : r.shapes)
    if (row.shape == "roll0") (row.form == "input" ? input_stress : cmds_stress) = row.stress;
  EXPECT_LT(cmds_stress, 0.5 * input_stress);
}

TEST(PoseInvariance, TopkidsReferenceFileErrorsNameFileAndLine) {
  const std::string dir = test::scratch_dir("pose_topkids");
  const Mesh m = icosphere(1);
  Mesh moved = m;  // a rigid copy, not the same file: a file listed twice is refused
  moved.V.col(0).array() += 3.0;
  write_mesh(dir + "/kid00.off", m);
  write_mesh(dir + "/kid01.off", moved);
  test::write_text(dir + "/kid01_ref.txt", "1 1\n2 2\n3 x\n");
  PoseInvarianceOptions o;
  o.data = dir;
  o.out = dir + "/out";
  o.methods = {"cmds"};
  try {
    run_pose_invariance(o);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("kid01_ref.txt:3"), std::string::npos) << what;
  }
  test::write_text(dir + "/kid01_ref.txt", "1 1\n2 500\n");
  try {
    run_pose_invariance(o);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("kid01_ref.txt:2"), std::string::npos) << e.what();
  }
  // A good file: rigid copies with identity correspondences have zero pose distance.
  std::ostringstream ref;
  for (Index v = 0; v < m.num_vertices(); ++v) ref << v + 1 << " " << v + 1 << "\n";
  test::write_text(dir + "/kid01_ref.txt", ref.str());
  const PoseInvarianceResult r = run_pose_invariance(o);
  ASSERT_EQ(r.pairs.size(), 2u);
  EXPECT_EQ(r.pairs[0].a, "kid01");
  EXPECT_EQ(r.pairs[0].b, "kid00");
  EXPECT_LT(r.pairs[0].rms, 1e-12);
}

TEST(PoseInvariance, DatasetWithSharedFacesPairsVertexIWithVertexI) {
  // As `generate dataset` writes them: poses of a class share faces, so vertex i corresponds to vertex i.
  const std::string dir = test::scratch_dir("pose_shared");
  const Mesh a = torus(24, 12, 1.0, 0.35);
  Mesh b = a;  // a rigid copy with a reflection: zero pose distance
  b.V = random_rigid_transform(5, 3.0, true).apply(a.V);
  Mesh c = a;  // scaled by s about the centroid: the known RMS of the first test
  const double s = 1.5;
  const Eigen::RowVector3d centroid = a.V.colwise().mean();
  c.V = ((a.V.rowwise() - centroid) * s).rowwise() + centroid;
  Mesh glued = a;  // a noisy entry (different faces): left out, not refused
  glued.F.conservativeResize(a.F.rows() - 1, 3);
  write_mesh(dir + "/ring_a.off", a);
  write_mesh(dir + "/ring_b.off", b);
  write_mesh(dir + "/ring_c.off", c);
  write_mesh(dir + "/ring_noisy.off", glued);
  write_mesh(dir + "/ball_a.off", icosphere(2));
  std::vector<DatasetEntry> entries = {{dir + "/ring_a.off", "ring_a", "ring", 0, false},
                                       {dir + "/ring_b.off", "ring_b", "ring", 1, false},
                                       {dir + "/ring_c.off", "ring_c", "ring", 2, false},
                                       {dir + "/ring_noisy.off", "ring_noisy", "ring", 3, true},
                                       {dir + "/ball_a.off", "ball_a", "ball", 0, false}};
  write_manifest(dir + "/manifest.csv", entries);

  PoseInvarianceOptions o;
  o.data = dir + "/manifest.csv";
  o.out = dir + "/out";
  o.methods = {"cmds"};
  o.samples = 0;
  o.stress_sources = 0;
  const PoseInvarianceResult r = run_pose_invariance(o);
  EXPECT_EQ(r.pairs.size(), 6u);  // ring a-b, a-c, b-c; input and cmds each; no ball pair, no noisy one
  for (const PosePairRow& p : r.pairs) {
    EXPECT_NE(p.a, "ring_noisy");
    EXPECT_NE(p.b, "ring_noisy");
    EXPECT_EQ(p.samples, a.num_vertices());
  }
  EXPECT_LT(pair_row(r, "ring_b", "input").rms, 1e-9);
  EXPECT_LT(pair_row(r, "ring_b", "cmds").rms, 1e-6);
  const double spread = std::sqrt((a.V.rowwise() - centroid).rowwise().squaredNorm().mean());
  const double expected = (s - 1) * spread / ((1 + s) / 2 * bbox_diagonal(a.V));
  for (const PosePairRow& p : r.pairs)
    if (p.a == "ring_a" && p.b == "ring_c" && p.form == "input") {
      EXPECT_NEAR(p.rms, expected, 1e-9 * expected);
    }
  // The folder itself (no corres/, no kid00.off) is read through its manifest the same way.
  o.data = dir;
  EXPECT_EQ(run_pose_invariance(o).pairs.size(), 6u);

  // Two clean poses of a class with different faces: refused, naming both files.
  entries[3].noisy = false;
  write_manifest(dir + "/manifest.csv", entries);
  try {
    run_pose_invariance(o);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("ring_noisy.off"), std::string::npos) << what;
    EXPECT_NE(what.find("do not share their faces"), std::string::npos) << what;
  }
}

// Per part on generated bipeds: the parts of the first pose (head, hands, feet and the core) carried to the
// others by the shared vertex order; the parts' residuals, weighted by their samples, recombine to the pose
// RMS of the same whole-shape fit; the figure's pair is the one with the median Coulomb RMS.
TEST(PoseInvariance, PartsOfGeneratedBipedsRecombineToTheWholeRms) {
  const std::string dir = test::scratch_dir("pose_parts");
  PoseInvarianceOptions o;
  o.data = test::generated_dataset(dir + "/gen", 1, 3, 1200);
  o.out = dir + "/out";
  o.methods = {"coulomb", "cmds"};
  o.samples = 400;
  o.stress_sources = 0;
  const PoseInvarianceResult r = run_pose_invariance(o);
  ASSERT_EQ(r.classes.size(), 1u);
  const PoseClassParts& c = r.classes[0];
  EXPECT_EQ(c.class_name, "biped");
  EXPECT_EQ(c.shape, "biped0");
  EXPECT_TRUE(c.problem.empty()) << c.problem;
  EXPECT_EQ(c.extremities.size(), 5u);
  ASSERT_EQ(r.pairs.size(), 9u);  // 3 pairs × (input, coulomb, cmds)
  for (const PosePairRow& p : r.pairs) {
    double squares = 0;
    int samples = 0;
    std::set<int> parts;
    for (const PosePartRow& q : r.parts)
      if (q.a == p.a && q.b == p.b && q.form == p.form) {
        squares += q.samples * q.rms * q.rms;
        samples += q.samples;
        parts.insert(q.part);
      }
    EXPECT_EQ(samples, p.samples) << p.a << "-" << p.b << " " << p.form;  // every sample in one part
    EXPECT_EQ(parts, (std::set<int>{0, 1, 2, 3, 4, 5})) << p.a << "-" << p.b << " " << p.form;
    EXPECT_NEAR(std::sqrt(squares / samples), p.rms, 1e-9 * p.rms) << p.a << "-" << p.b << " " << p.form;
  }
  // Medians per part and form, and the data files.
  EXPECT_EQ(r.part_summary.size(), 6u * 3u);
  const std::string csv = read_file(o.out + "/pose_parts.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "config,a,b,class,form,part,parts_shape,extremity_vertex,samples,rms");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), static_cast<long>(r.parts.size()) + 1);
  // The figure's pair: the median of the three Coulomb RMS, its residuals those of the same fit.
  std::vector<double> coulomb;
  for (const PosePairRow& p : r.pairs)
    if (p.form == "coulomb") coulomb.push_back(p.rms);
  std::sort(coulomb.begin(), coulomb.end());
  const PoseFigurePair& fig = r.figure_pair;
  ASSERT_EQ(fig.forms, (std::vector<std::string>{"input", "coulomb", "cmds"}));
  EXPECT_DOUBLE_EQ(fig.rms[1], coulomb[1]);
  EXPECT_TRUE(contains(fig.chosen_by, "median Coulomb pose RMS (2 of 3")) << fig.chosen_by;
  ASSERT_EQ(fig.residuals.rows(), 400);
  EXPECT_NEAR(std::sqrt(fig.residuals.col(1).squaredNorm() / 400), fig.rms[1], 1e-9 * fig.rms[1]);
  EXPECT_TRUE(fs::exists(o.out + "/pose_residuals.csv"));
  EXPECT_TRUE(fs::exists(o.out + "/pose_residuals.json"));

  // The report: the per-part table, named by extremity vertex; the figure or why not.
  PoseInvarianceResult drawn = r;
  o.figure = false;
  draw_pose_figure(drawn, o);
  EXPECT_EQ(drawn.figure_problem, "not requested (--no-draw)");
  const std::string md = pose_invariance_markdown(drawn, o);
  EXPECT_TRUE(contains(md, "## Where the pose stays: per part")) << md;
  EXPECT_TRUE(
      contains(md, "| part 1 (extremity at vertex " + std::to_string(c.extremities[0]) + " of biped0) |"))
      << md;
  EXPECT_TRUE(contains(md, "No figure (not requested (--no-draw))")) << md;

  // Without parts: no part rows, no pose_parts.csv section.
  o.parts = false;
  o.out = dir + "/no_parts";
  const PoseInvarianceResult none = run_pose_invariance(o);
  EXPECT_TRUE(none.parts.empty());
  EXPECT_TRUE(none.classes.empty());
  EXPECT_FALSE(contains(pose_invariance_markdown(none, o), "per part"));
  fs::remove_all(dir);
}

// The figure script draws pose_residuals.png from a small generated run (skipped without matplotlib).
TEST(PoseInvariance, FigureScriptDrawsTheResidualsOfTheChosenPair) {
  if (find_python("matplotlib, numpy").empty()) GTEST_SKIP() << "no Python with matplotlib and numpy";
  const std::string dir = test::scratch_dir("pose_figure");
  PoseInvarianceOptions o;
  o.data = test::generated_dataset(dir + "/gen", 1, 2, 800);
  o.out = dir + "/out";
  o.methods = {"cmds"};
  o.samples = 200;
  o.stress_sources = 0;
  const PoseInvarianceResult r = pose_experiment(o);
  EXPECT_EQ(r.figure, "pose_residuals.png") << r.figure_problem;
  EXPECT_TRUE(fs::exists(o.out + "/pose_residuals.png"));
  EXPECT_TRUE(contains(r.figure_pair.chosen_by, "median classical MDS pose RMS (1 of 1"))
      << r.figure_pair.chosen_by;
  const std::string md = read_file(o.out + "/pose.md");
  EXPECT_TRUE(contains(md, "![residuals of biped0-biped1](pose_residuals.png)")) << md;
  EXPECT_TRUE(contains(md, "experiments/plots/pose_figure.py " + o.out)) << md;
  fs::remove_all(dir);
}

TEST(PoseInvariance, AShapeWhoseFormFailsIsLeftOutWithItsPairsAndNamed) {
  const std::string dir = test::scratch_dir("pose_left_out");
  const Mesh a = torus(24, 12, 1.0, 0.35);
  std::vector<int> identity(a.num_vertices());
  std::iota(identity.begin(), identity.end(), 0);
  for (int k = 0; k < 3; ++k) {
    Mesh moved = a;  // rigid copies, each another file
    moved.V.col(0).array() += 3.0 * k;
    write_pose(dir, "ring" + std::to_string(k), moved, identity);
  }
  PoseInvarianceOptions o;
  o.data = dir;
  o.out = dir + "/out";
  o.methods = {"cmds"};
  o.stress_sources = 0;
  HookGuard guard([](GeodesicMethod, const std::string& name) {
    if (contains(name, "ring2")) fail(name, ": injected failure");
  });
  const PoseInvarianceResult r = run_pose_invariance(o);
  ASSERT_EQ(r.failures.size(), 1u);
  EXPECT_EQ(r.failures[0].name, "ring2");
  EXPECT_EQ(r.failures[0].method, "cmds");
  EXPECT_TRUE(r.failures[0].left_out());
  // ring0-ring1 alone, for the input and cmds; no shape row of ring2.
  ASSERT_EQ(r.pairs.size(), 2u);
  for (const PosePairRow& p : r.pairs) {
    EXPECT_EQ(p.a, "ring0");
    EXPECT_EQ(p.b, "ring1");
    EXPECT_LT(p.rms, 1e-6) << p.form;
  }
  EXPECT_EQ(r.shapes.size(), 4u);
  for (const PoseShapeRow& s : r.shapes) {
    EXPECT_NE(s.shape, "ring2");
    EXPECT_EQ(s.stress, -1) << "no stress sources: not measured";
  }
  ASSERT_EQ(r.summary.size(), 2u);  // input and cmds, one class: "all" only
  EXPECT_EQ(r.summary[1].form, "cmds");
  EXPECT_EQ(r.summary[1].class_name, "all");
  EXPECT_EQ(r.summary[1].pairs, 1);
}

// --resample on poses that share their faces (as `generate dataset` writes them): each remeshed on its own,
// the samples (vertex i of each input) carried to the remeshes. The surfaces are the same, so the inputs'
// pose RMS moves only by what locating moved the samples.
TEST(PoseInvariance, ResampledPosesCarryTheirSamplesToTheRemeshes) {
  const std::string dir = test::scratch_dir("pose_resampled");
  PoseInvarianceOptions o;
  o.data = test::generated_dataset(dir + "/gen", 1, 3, 1200);
  o.methods = {"cmds"};
  o.samples = 200;
  o.stress_sources = 4;
  o.out = dir + "/plain";
  const PoseInvarianceResult plain = run_pose_invariance(o);
  o.out = dir + "/resampled";
  o.resample.vertices = 800;
  const PoseInvarianceResult r = run_pose_invariance(o);

  ASSERT_TRUE(r.resampled);
  EXPECT_FALSE(plain.resampled);
  EXPECT_TRUE(plain.located.empty());
  ASSERT_EQ(r.resampling.shapes.size(), 3u);
  ASSERT_EQ(r.located.size(), 3u);
  std::map<std::string, const PoseLocatedRow*> located;
  std::map<std::string, double> input_diagonal, remesh_diagonal;
  for (size_t i = 0; i < 3; ++i) {
    const ResampledShape& s = r.resampling.shapes[i];
    const PoseLocatedRow& l = r.located[i];
    EXPECT_EQ(l.shape, s.name);
    ASSERT_TRUE(s.remeshed) << s.note;
    EXPECT_NEAR(static_cast<double>(s.vertices), 800.0, 8.0);
    EXPECT_TRUE(fs::exists(s.file)) << s.file;
    EXPECT_EQ(l.samples, 200);
    EXPECT_TRUE(l.remeshed);
    // The located points are the input vertices' projections onto the remesh, which the Hausdorff measure
    // samples too: no farther than it (both over the input's diagonal).
    EXPECT_GT(l.max_distance, 0.0);
    EXPECT_LE(l.max_distance, s.hausdorff * (1 + 1e-9)) << s.name;
    EXPECT_LE(l.mean_distance, l.max_distance);
    EXPECT_EQ(l.off_part, 0) << s.name;
    EXPECT_EQ(l.relocated, 0) << s.name;
    located[s.name] = &l;
    input_diagonal[s.name] = bbox_diagonal(read_mesh(s.source).V);
    remesh_diagonal[s.name] = bbox_diagonal(read_mesh(s.file).V);
  }
  // Per pair the same samples and forms. Unnormalised, the inputs' RMS after the best rigid fit (the optimum
  // of both runs) moves by at most the two shapes' largest sample displacements (triangle inequality); the
  // normalisation is by the mean diagonal of the inputs, then of the remeshes.
  ASSERT_EQ(r.pairs.size(), plain.pairs.size());
  ASSERT_EQ(r.pairs.size(), 6u);  // 3 pairs, input and cmds
  for (size_t k = 0; k < r.pairs.size(); ++k) {
    const PosePairRow& p = r.pairs[k];
    const PosePairRow& q = plain.pairs[k];
    EXPECT_EQ(p.a, q.a);
    EXPECT_EQ(p.b, q.b);
    EXPECT_EQ(p.form, q.form);
    EXPECT_EQ(p.samples, 200);
    EXPECT_TRUE(std::isfinite(p.rms)) << p.a << "-" << p.b << " " << p.form;
    if (p.form != "input") continue;
    const double moved =
        located[p.a]->max_distance * input_diagonal[p.a] + located[p.b]->max_distance * input_diagonal[p.b];
    const double input_scale = (input_diagonal[p.a] + input_diagonal[p.b]) / 2;
    const double remesh_scale = (remesh_diagonal[p.a] + remesh_diagonal[p.b]) / 2;
    EXPECT_NEAR(p.rms * remesh_scale, q.rms * input_scale, moved) << p.a << "-" << p.b;
    EXPECT_GT(q.rms * input_scale, 3 * moved) << "poses far enough apart for the comparison to say something";
  }
  // The shape rows are measured on the remeshes.
  for (const PoseShapeRow& row : r.shapes) EXPECT_GE(row.stress, 0) << row.shape << " " << row.form;

  const std::string report = pose_invariance_markdown(r, o);
  EXPECT_TRUE(contains(report, "every shape remeshed to about 800 vertices first")) << report;
  EXPECT_TRUE(contains(report, "## Resampling")) << report;
  EXPECT_TRUE(contains(report, "Every shape was remeshed to about 800 vertices"))
      << report;  // the kit's table
  EXPECT_TRUE(contains(report, "carried to its shape's remesh")) << report;
  EXPECT_TRUE(
      contains(report, "| shape | samples | mean distance | max distance | relocated | off their part |"))
      << report;
  EXPECT_FALSE(contains(pose_invariance_markdown(plain, o), "## Resampling"));
  EXPECT_TRUE(fs::exists(o.out + "/resampled/manifest.csv"));
}

// A result as run_pose_invariance returns it, made by hand: two classes, one shape left out.
PoseInvarianceResult hand_made_result() {
  PoseInvarianceResult r;
  auto pair = [](const std::string& a, const std::string& b, const std::string& form, double rms) {
    return PosePairRow{a, b, a.substr(0, 3), form, rms, 0.2, 100};
  };
  r.pairs = {pair("cat0", "cat1", "input", 0.2), pair("cat0", "cat1", "coulomb", 0.05),
             pair("dog0", "dog1", "input", 0.2), pair("dog0", "dog1", "coulomb", 0.3)};
  for (const char* shape : {"cat0", "cat1", "dog0", "dog1"})
    for (const char* form : {"input", "coulomb"}) {
      PoseShapeRow row;
      row.shape = shape;
      row.form = form;
      r.shapes.push_back(row);
    }
  auto summary = [](const std::string& form, const std::string& class_name, double median, double removed,
                    double stress) {
    PoseSummaryRow row;
    row.form = form;
    row.class_name = class_name;
    row.pairs = 1;
    row.median_rms = row.mean_rms = median;
    row.median_input_rms = 0.2;
    row.removed = removed;
    row.mean_abs_stretch = 0.125;
    row.max_stretch = 2.5;
    row.stress = stress;
    return row;
  };
  r.summary = {summary("input", "cat", 0.2, 0, 0.21), summary("coulomb", "cat", 0.05, 0.75, 0.3),
               summary("coulomb", "dog", 0.3, -0.5, -1)};
  r.summary[2].mean_rms = std::numeric_limits<double>::quiet_NaN();
  r.failures.push_back({"dog2", "DATA/dog2.off", "coulomb", "canonical form", "it diverged", ""});
  return r;
}

TEST(PoseInvariance, ReportSaysTheTableTheFailuresAndWhatWasNotMeasured) {
  const std::string out = test::scratch_dir("pose_report");
  PoseInvarianceOptions o;
  o.data = "DATA";
  o.samples = 100;
  o.stress_sources = 8;
  o.label = "tuned";
  const PoseInvarianceResult r = hand_made_result();
  write_pose_invariance_report(r, o, out);
  const std::string report = read_file(out + "/pose.md");
  EXPECT_EQ(report, pose_invariance_markdown(r, o));
  EXPECT_TRUE(contains(report, "# Pose invariance (tuned)\n")) << report;
  // Counted from the result: the shapes and pairs measured (dog2, left out, is not).
  EXPECT_TRUE(contains(report, "Data: `DATA`, 4 shapes, 2 pairs of poses, up to 100 ground-truth")) << report;
  EXPECT_TRUE(contains(report, "fast marching from 8 sources per shape")) << report;
  // The input has no stretch ("—"); a stress not measured (−1) and a mean over no pair (NaN) are "—"; a
  // form worse than the input removes a negative share.
  EXPECT_TRUE(contains(report, "| input | cat | 1 | 20.00% | 20.00% | 20.00% | 0% | — | — | 0.210 |"))
      << report;
  EXPECT_TRUE(contains(report, "| coulomb | cat | 1 | 5.00% | 5.00% | 20.00% | 75% | 0.125 | 2.50 | 0.300 |"))
      << report;
  EXPECT_TRUE(contains(report, "| coulomb | dog | 1 | 30.00% | — | 20.00% | -50% | 0.125 | 2.50 | — |"))
      << report;
  EXPECT_FALSE(contains(report, "nan")) << report;
  EXPECT_FALSE(contains(report, "-1.000")) << report;
  EXPECT_TRUE(
      contains(report, "| dog2 | `DATA/dog2.off` | coulomb | canonical form | left out: it diverged |"))
      << report;
  fs::remove_all(out);
}

}  // namespace pose_invariance_test
}  // namespace cshapes
