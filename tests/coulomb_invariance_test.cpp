// The Coulomb form is a function of the shape (issue 59): renumbering the vertices (and the faces), moving the
// shape rigidly, scaling by a factor that is not a power of two, or moving every vertex by 1e-12 of the
// diagonal moves the form by at most 0.05% of its bounding-box diagonal (RMS over corresponding vertices
// after the best rigid motion, reflections allowed), and a run either converges or says it did not in its
// quality verdict.
//
// Before the fix a renumbered tosca5k dog0 at 1,000 vertices ended 5.45% (align's RMSE) from its form: the
// start's landmarks were sampled from vertex 0; michael0 at 1,000 vertices never converged and ended 1–2.7%
// away under renumbering, ×10 and jitter: the ends of its short edges rattled (docs/coulomb-defaults.md, "A
// function of the shape").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "cshapes/canon/coulomb.h"
#include "cshapes/data/articulated.h"
#include "cshapes/mesh/io.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/mesh/remesh.h"
#include "cshapes/mesh/rigid_transform.h"
#include "tests/test_support.h"

namespace cshapes {
namespace coulomb_invariance_test {

// The stated tolerance: % of the form's bbox diagonal (the goal of issue 59).
constexpr double kTolerancePercent = 0.05;

// The mesh renumbered: vertex k of the result is vertex order[k] of `mesh`; faces remapped and shuffled.
struct Renumbered {
  Mesh mesh;
  std::vector<Index> order;
};

Renumbered renumbered(const Mesh& mesh, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  Renumbered r;
  r.order.resize(static_cast<size_t>(mesh.num_vertices()));
  std::iota(r.order.begin(), r.order.end(), Index(0));
  std::shuffle(r.order.begin(), r.order.end(), random);
  std::vector<int> new_index(r.order.size());
  r.mesh.V.resize(mesh.num_vertices(), 3);
  for (size_t k = 0; k < r.order.size(); ++k) {
    r.mesh.V.row(static_cast<Index>(k)) = mesh.V.row(r.order[k]);
    new_index[static_cast<size_t>(r.order[k])] = static_cast<int>(k);
  }
  std::vector<Index> faces(static_cast<size_t>(mesh.F.rows()));
  std::iota(faces.begin(), faces.end(), Index(0));
  std::shuffle(faces.begin(), faces.end(), random);
  r.mesh.F.resize(mesh.F.rows(), 3);
  for (size_t f = 0; f < faces.size(); ++f)
    for (int c = 0; c < 3; ++c)
      r.mesh.F(static_cast<Index>(f), c) = new_index[static_cast<size_t>(mesh.F(faces[f], c))];
  return r;
}

CoulombCanonResult form_of(const Mesh& mesh) {
  return coulomb_canonical_form(mesh.V, mesh_edges(mesh.F), CoulombCanonOptions{});
}

// RMS distance of X (rows in the order of `reference`) from the reference form, in % of its bbox diagonal.
double percent_apart(const Points& X, const Points& reference) {
  return 100 * aligned_rms(X, reference, /*allow_reflection=*/true) / bbox_diagonal(reference);
}

// The form of `mesh` against its forms renumbered (one run per seed), scaled (one per factor) and jittered
// by 1e-12 of the diagonal; the run converged or failed its quality check saying so.
void expect_a_function_of_the_shape(const Mesh& mesh, const std::string& name,
                                    const std::vector<std::uint64_t>& seeds,
                                    const std::vector<double>& scales) {
  const CoulombCanonResult base = form_of(mesh);
  EXPECT_EQ(base.converged, base.not_converged.empty()) << name;
  if (!base.converged) {
    EXPECT_FALSE(base.quality.ok) << name << ": " << base.quality.description;
  }
  std::printf("[ info ] %s: %d iterations (%s)\n", name.c_str(), base.iterations, base.stop_reason.c_str());
  for (std::uint64_t seed : seeds) {
    const Renumbered r = renumbered(mesh, seed);
    const CoulombCanonResult form = form_of(r.mesh);
    Points back(form.X.rows(), 3);
    for (size_t k = 0; k < r.order.size(); ++k) back.row(r.order[k]) = form.X.row(static_cast<Index>(k));
    const double apart = percent_apart(back, base.X);
    std::printf("[ info ] %s renumbered (seed %d): %.2e%%\n", name.c_str(), static_cast<int>(seed), apart);
    EXPECT_LE(apart, kTolerancePercent) << name << " renumbered with seed " << seed;
  }
  for (double scale : scales) {
    const CoulombCanonResult form = form_of(Mesh{mesh.V * scale, mesh.F});
    const double apart = percent_apart(form.X / scale, base.X);
    std::printf("[ info ] %s ×%g: %.2e%%\n", name.c_str(), scale, apart);
    EXPECT_LE(apart, kTolerancePercent) << name << " scaled by " << scale;
  }
  // A rigid motion of the input (rotation and a translation of about the diagonal): the landmark MDS start
  // lies in its own frame, so the iteration's sums do not follow the input's orientation.
  const RigidTransform motion = random_rigid_transform(11, bbox_diagonal(mesh.V));
  const CoulombCanonResult moved = form_of(Mesh{motion.apply(mesh.V), mesh.F});
  const double moved_apart = percent_apart(moved.X, base.X);
  std::printf("[ info ] %s moved rigidly: %.2e%%\n", name.c_str(), moved_apart);
  EXPECT_LE(moved_apart, kTolerancePercent) << name << " moved rigidly";
  // The finished form is turned onto its input: no rigid motion brings it closer.
  const double unmoved = std::sqrt((moved.X - motion.apply(mesh.V)).rowwise().squaredNorm().mean());
  EXPECT_LE(unmoved, aligned_rms(moved.X, motion.apply(mesh.V), /*allow_reflection=*/true) * (1 + 1e-9) +
                         1e-12 * bbox_diagonal(mesh.V))
      << name;
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(-1, 1);
  Mesh jittered = mesh;
  const double amplitude = 1e-12 * bbox_diagonal(mesh.V);
  for (Index i = 0; i < jittered.V.size(); ++i) jittered.V.data()[i] += amplitude * unit(random);
  const double apart = percent_apart(form_of(jittered).X, base.X);
  std::printf("[ info ] %s jittered by 1e-12: %.2e%%\n", name.c_str(), apart);
  EXPECT_LE(apart, kTolerancePercent) << name << " jittered";
}

TEST(CoulombInvariance, RenumberingScaleAndJitterLeaveTheFormOfAGeneratedBiped) {
  ArticulatedOptions ao;
  ao.poses = 1;
  ao.seed = 5;
  ao.rest.target_vertices = 1000;
  const Mesh biped = generate_articulated("biped", ao).poses.front();
  expect_a_function_of_the_shape(biped, "biped", {1, 2}, {10.0, 1e-3});
}

// The tosca5k shapes of the table at 1,000 vertices (remeshed here: the remesher is deterministic).
TEST(CoulombInvariance, ToscaShapesThatFailedAtAThousandVertices) {
  CSHAPES_REQUIRE_DATA();
  for (const char* name : {"dog0", "michael0"}) {
    RemeshOptions ro;
    ro.target_vertices = 1000;
    const Mesh mesh = remesh(read_mesh(test::tosca5k(name)), ro).mesh;
    expect_a_function_of_the_shape(mesh, name, {1}, {10.0});
  }
}

}  // namespace coulomb_invariance_test
}  // namespace cshapes
