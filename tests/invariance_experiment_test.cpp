// The invariance experiment (experiments/invariance_experiment.h) and its transformations
// (experiments/invariance_transforms.h): the transformations keep the surface and say where each vertex went;
// a form that is its mesh passes every exact transformation to rounding; on a generated pair of poses, an
// eigenmap passes, an order-dependent method from outside fails on the renumberings, and a method that fails
// on a transformed mesh fails its verdict while the run goes on; the files hold the rows expected; the CLI
// names a method that fails and ends with exit code 3.
#include "cshapes/experiments/invariance_experiment.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <set>
#include <sstream>

#include "cshapes/data/synthetic.h"
#include "cshapes/experiments/invariance_transforms.h"
#include "cshapes/mesh/io.h"
#include "cshapes/pipeline/outside_methods.h"
#include "cshapes/support/atomic_file.h"
#include "tests/test_support.h"

namespace cshapes {
namespace invariance_experiment_test {

namespace fs = std::filesystem;

// The faces as sets of reference vertices, each turned to start at its smallest vertex (orientation kept).
std::multiset<std::array<int, 3>> oriented_faces(const Faces& F, const std::vector<int>& reference_vertex) {
  std::multiset<std::array<int, 3>> out;
  for (Index f = 0; f < F.rows(); ++f) {
    std::array<int, 3> c;
    for (int k = 0; k < 3; ++k)
      c[k] = reference_vertex.empty() ? F(f, k) : reference_vertex[static_cast<size_t>(F(f, k))];
    std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
    out.insert(c);
  }
  return out;
}

TEST(InvarianceTransforms, KeepTheSurfaceAndSayWhereEachVertexWent) {
  const Mesh m = torus(20, 10, 1.0, 0.35);
  const double diagonal = bbox_diagonal(m.V);
  for (ExactTransform t : exact_transforms()) {
    SCOPED_TRACE(to_string(t));
    const TransformedMesh a = transform_mesh(m, t, 5), b = transform_mesh(m, t, 5),
                          c = transform_mesh(m, t, 6);
    EXPECT_EQ(a.mesh.V, b.mesh.V);  // deterministic for a seed
    EXPECT_EQ(a.mesh.F, b.mesh.F);
    if (is_seeded(t)) {
      EXPECT_TRUE(a.mesh.V != c.mesh.V || a.mesh.F != c.mesh.F);
    }
    ASSERT_EQ(a.mesh.num_vertices(), m.num_vertices());
    EXPECT_EQ(oriented_faces(a.mesh.F, a.reference_vertex), oriented_faces(m.F, {}));
    // The mesh as its own form: every exact transformation leaves it where it was, up to a rigid motion and
    // the scale; the jitter moves it by at most its amplitude.
    const FormChange change = exact_form_change(m.V, a.mesh.V, a);
    EXPECT_EQ(change.rows, m.num_vertices());
    const double bound = t == ExactTransform::Jitter ? std::sqrt(3.0) * kInvarianceJitter * diagonal : 1e-12;
    EXPECT_LE(change.rmse * diagonal, bound);
    EXPECT_LE(change.hausdorff * diagonal, t == ExactTransform::Jitter ? 4 * bound : 1e-11);
    if (t == ExactTransform::Jitter) {
      EXPECT_GT(change.rmse, 0);
    }
  }
  const std::vector<int> p = random_permutation(1000, 3);
  EXPECT_EQ(std::set<int>(p.begin(), p.end()).size(), 1000u);
  EXPECT_NE(p, random_permutation(1000, 4));
}

TEST(InvarianceTransforms, AFormThatFollowsTheVertexNumbersIsCaught) {
  const Mesh m = torus(20, 10, 1.0, 0.35);
  const TransformedMesh t = transform_mesh(m, ExactTransform::Renumber, 1);
  auto sloppy = [](const Points& V) {  // moves vertex i by an amount set by its index
    Points X = V;
    for (Index i = 0; i < X.rows(); ++i) X(i, 0) += 0.02 * static_cast<double>(i % 5);
    return X;
  };
  EXPECT_GT(exact_form_change(sloppy(m.V), sloppy(t.mesh.V), t).rmse, 5e-3);
  // The same form of a remesh has no correspondence: ICP finds the mesh again.
  EXPECT_LT(aligned_form_change(m.V, transform_mesh(m, ExactTransform::Rigid, 2).mesh.V).rmse, 1e-9);
}

// A function door (pipeline/outside_methods.h), as Python's (name, fn) builds one.
OutsideDoor function_door(std::function<Points(const Mesh&, const std::string&)> fn) {
  OutsideDoor door;
  door.kind = OutsideDoor::Kind::Function;
  door.text = "test function";
  door.function = std::move(fn);
  door.function_key = door.text;
  return door;
}

size_t lines_of(const std::string& path) {
  std::istringstream in(read_file(path));
  size_t n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}

TEST(InvarianceExperiment, AnEigenmapPassesAndAnOrderDependentMethodFails) {
  const std::string dir = test::scratch_dir("invariance");
  const std::string manifest = test::generated_dataset(dir + "/data", 1, 2, 300);
  // Moves vertex i by 2% of the diagonal times (i mod 5): follows the numbering, not the surface.
  OutsideMethod sloppy("sloppy", function_door([](const Mesh& mesh, const std::string&) {
                         Points X = mesh.V;
                         const double step = 0.02 * bbox_diagonal(mesh.V);
                         for (Index i = 0; i < X.rows(); ++i) X(i, 0) += step * static_cast<double>(i % 5);
                         return X;
                       }));
  // The mesh itself, but it refuses meshes smaller than a thousandth: fails on the ×1e-6 scale only.
  OutsideMethod fragile("fragile", function_door([](const Mesh& mesh, const std::string& name) {
                          if (bbox_diagonal(mesh.V) < 1e-3) fail(name, ": too small for me");
                          return Points(mesh.V);
                        }));
  // Forms computed beforehand for the shapes as given (the meshes themselves), none for the meshes the
  // experiment makes: not measured, and listed in OUT/forms-needed.
  fs::create_directories(dir + "/forms");
  for (const char* shape : {"biped0", "biped1"})
    fs::copy_file(dir + "/data/" + shape + ".off", dir + "/forms/" + shape + ".off");
  OutsideDoor folder;
  folder.kind = OutsideDoor::Kind::Forms;
  folder.text = dir + "/forms";
  OutsideMethod given("given", folder);
  InvarianceOptions o;
  o.data = manifest;
  o.out = dir + "/out";
  o.methods = {"lbo", "sloppy", "fragile", "given"};
  o.seeds = 2;
  o.figure = false;
  const InvarianceResult r = invariance_experiment(o);

  // Per shape and method: 2 renumberings + 5 other exact transformations + 2 remeshes; fragile lacks the
  // ×1e-6 scale.
  const size_t per_method = 2 + 5 + 2;
  EXPECT_EQ(r.rows.size(), 2 * (3 * per_method - 1));
  EXPECT_EQ(lines_of(o.out + "/invariance.csv"), 1 + r.rows.size());
  EXPECT_EQ(lines_of(o.out + "/invariance_summary.csv"), 1 + 4 * (exact_transforms().size() + 2));
  EXPECT_EQ(r.pose_pairs.size(), 4u);  // one pair of poses, by each method
  auto verdict = [&](const std::string& method) {
    for (const InvarianceVerdict& v : r.verdicts)
      if (v.method == method && v.resolution == -1) return v;
    throw Error("no verdict for " + method);
  };
  EXPECT_EQ(verdict("lbo").verdict, "pass") << verdict("lbo").reason;
  EXPECT_LT(verdict("lbo").worst_rmse, 1e-6);
  EXPECT_EQ(verdict("sloppy").verdict, "fail");
  EXPECT_NE(verdict("sloppy").worst.find("renumber"), std::string::npos) << verdict("sloppy").worst;
  EXPECT_EQ(verdict("fragile").verdict, "fail");
  EXPECT_EQ(verdict("fragile").failed_forms, 2);
  EXPECT_LT(verdict("fragile").worst_rmse,
            2 * kInvarianceJitter);  // the mesh itself: the jitter alone moves it
  EXPECT_EQ(verdict("given").verdict, "not measured");
  EXPECT_EQ(verdict("given").missing_forms, 2 * 7);
  EXPECT_TRUE(fs::exists(o.out + "/forms-needed/given.csv"));
  // The failures name the shape, the case and the method; the others' forms of that case are kept.
  int named = 0;
  for (const ShapeFailure& f : r.failures)
    named += f.method == "fragile" && f.name.find("scale-1e-6") != std::string::npos;
  EXPECT_EQ(named, 2);
  for (const InvarianceRow& row : r.rows)
    if (row.method == "lbo") {
      EXPECT_EQ(row.converged, -1);  // no convergence test
    }
  const std::string md = read_file(o.out + "/invariance.md");
  EXPECT_NE(md.find("| sloppy | **fail**"), std::string::npos) << md;
  EXPECT_NE(md.find("Remeshed (reported apart"), std::string::npos);
}

TEST(InvarianceExperiment, TheCliNamesAFailingMethodAndEndsWithExitCode3) {
  const std::string dir = test::scratch_dir("invariance_cli");
  const std::string manifest = test::generated_dataset(dir + "/data", 1, 2, 200);
  const test::CliResult r = test::run_cli("experiment invariance --data " + manifest + " --out " + dir +
                                          "/out --methods 'cmds,broken=cmd:cat {mesh} {form} "
                                          ">/dev/null; exit 1' --seeds 1 --no-draw --json");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("broken"), std::string::npos) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  bool cmds_passes = false;
  for (const auto& v : j.at("verdicts"))
    if (v.at("method") == "cmds" && v.at("resolution") == "all") cmds_passes = v.at("verdict") == "pass";
  EXPECT_TRUE(cmds_passes) << j.at("verdicts").dump(1);
  EXPECT_TRUE(fs::exists(dir + "/out/invariance_pose.csv"));
  EXPECT_EQ(test::run_cli("experiment invariance --data " + manifest + " --out " + dir + "/out2 --vertices 5")
                .exit_code,
            2);
}

}  // namespace invariance_experiment_test
}  // namespace cshapes
