#include "cshapes/experiments/invariance_transforms.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "cshapes/matching/shape_distance.h"
#include "cshapes/mesh/rigid_transform.h"
#include "cshapes/support/error.h"

namespace cshapes {

const std::vector<ExactTransform>& exact_transforms() {
  static const std::vector<ExactTransform> all = {ExactTransform::Renumber, ExactTransform::FaceOrder,
                                                  ExactTransform::Rigid,    ExactTransform::ScaleDown,
                                                  ExactTransform::ScaleUp,  ExactTransform::Jitter};
  return all;
}

std::string to_string(ExactTransform transform) {
  switch (transform) {
    case ExactTransform::Renumber:
      return "renumber";
    case ExactTransform::FaceOrder:
      return "face-order";
    case ExactTransform::Rigid:
      return "rigid";
    case ExactTransform::ScaleDown:
      return "scale-1e-6";
    case ExactTransform::ScaleUp:
      return "scale-1e3";
    case ExactTransform::Jitter:
      return "jitter";
  }
  return "";
}

bool is_seeded(ExactTransform transform) {
  return transform != ExactTransform::ScaleDown && transform != ExactTransform::ScaleUp;
}

namespace {

// An integer in [0, n) from the generator (the modulo's bias, below 2^-40 for any mesh, does not matter).
Index below(std::mt19937_64& rng, Index n) {
  return static_cast<Index>(rng() % static_cast<std::uint64_t>(n));
}

// A number in [−1, 1) from the generator's top 53 bits.
double symmetric_unit(std::mt19937_64& rng) {
  return 2.0 * std::ldexp(static_cast<double>(rng() >> 11), -53) - 1.0;
}

TransformedMesh renumbered(const Mesh& m, std::uint64_t seed) {
  TransformedMesh t;
  t.reference_vertex = random_permutation(m.num_vertices(), seed);
  std::vector<int> new_index(t.reference_vertex.size());
  for (size_t k = 0; k < new_index.size(); ++k)
    new_index[static_cast<size_t>(t.reference_vertex[k])] = static_cast<int>(k);
  t.mesh.V.resize(m.V.rows(), 3);
  for (Index k = 0; k < m.V.rows(); ++k)
    t.mesh.V.row(k) = m.V.row(t.reference_vertex[static_cast<size_t>(k)]);
  t.mesh.F = m.F;
  for (Index f = 0; f < m.F.rows(); ++f)
    for (int c = 0; c < 3; ++c) t.mesh.F(f, c) = new_index[static_cast<size_t>(m.F(f, c))];
  return t;
}

TransformedMesh faces_reordered(const Mesh& m, std::uint64_t seed) {
  TransformedMesh t;
  const std::vector<int> order = random_permutation(m.F.rows(), seed);
  std::mt19937_64 rng(seed ^ 0x9e3779b97f4a7c15ULL);  // the corners' turns: a stream apart from the order's
  t.mesh.V = m.V;
  t.mesh.F.resize(m.F.rows(), 3);
  for (Index f = 0; f < m.F.rows(); ++f) {
    const Index turn = below(rng, 3);
    for (int c = 0; c < 3; ++c)
      t.mesh.F(f, c) = m.F(order[static_cast<size_t>(f)], static_cast<int>((c + turn) % 3));
  }
  return t;
}

TransformedMesh moved(const Mesh& m, std::uint64_t seed) {
  TransformedMesh t;
  t.mesh.F = m.F;
  t.mesh.V = random_rigid_transform(seed, finite_bbox_diagonal(m.V), false).apply(m.V);
  return t;
}

TransformedMesh scaled(const Mesh& m, double scale) {
  TransformedMesh t;
  t.mesh.F = m.F;
  t.mesh.V = m.V * scale;
  t.scale = scale;
  return t;
}

TransformedMesh jittered(const Mesh& m, std::uint64_t seed) {
  TransformedMesh t;
  t.mesh.F = m.F;
  t.mesh.V = m.V;
  const double amplitude = kInvarianceJitter * finite_bbox_diagonal(m.V);
  std::mt19937_64 rng(seed);
  for (Index i = 0; i < t.mesh.V.rows(); ++i)
    for (int c = 0; c < 3; ++c) t.mesh.V(i, c) += amplitude * symmetric_unit(rng);
  return t;
}

}  // namespace

std::vector<int> random_permutation(Index n, std::uint64_t seed) {
  std::vector<int> p(static_cast<size_t>(n));
  std::iota(p.begin(), p.end(), 0);
  std::mt19937_64 rng(seed);
  for (Index k = n - 1; k > 0; --k)
    std::swap(p[static_cast<size_t>(k)], p[static_cast<size_t>(below(rng, k + 1))]);
  return p;
}

TransformedMesh transform_mesh(const Mesh& reference, ExactTransform transform, std::uint64_t seed) {
  switch (transform) {
    case ExactTransform::Renumber:
      return renumbered(reference, seed);
    case ExactTransform::FaceOrder:
      return faces_reordered(reference, seed);
    case ExactTransform::Rigid:
      return moved(reference, seed);
    case ExactTransform::ScaleDown:
      return scaled(reference, kInvarianceSmallScale);
    case ExactTransform::ScaleUp:
      return scaled(reference, kInvarianceLargeScale);
    case ExactTransform::Jitter:
      return jittered(reference, seed);
  }
  fail("transform_mesh: unknown transformation");
}

FormChange exact_form_change(const Points& reference, const Points& transformed, const TransformedMesh& how) {
  CSHAPES_REQUIRE(reference.rows() == transformed.rows(), "the transformed form has ", transformed.rows(),
                  " rows, the reference form ", reference.rows());
  // The transformed form's rows in the reference's vertex order, back at the reference's scale.
  Points back(reference.rows(), 3);
  for (Index k = 0; k < transformed.rows(); ++k) {
    const Index at = how.reference_vertex.empty() ? k : how.reference_vertex[static_cast<size_t>(k)];
    back.row(at) = transformed.row(k) / how.scale;
  }
  Index usable = 0;
  for (Index i = 0; i < reference.rows(); ++i)
    usable += reference.row(i).allFinite() && back.row(i).allFinite();
  CSHAPES_REQUIRE(usable >= 4, "only ", usable, " vertices are finite in both forms (at least 4 needed)");
  RigidFitOptions fit;
  fit.determinant = 0;
  fit.skip_nonfinite_rows = true;
  const RigidFitResult r = fit_rigid_transform(back, reference, fit);
  const double diagonal = finite_bbox_diagonal(reference);
  FormChange change;
  change.rows = r.rows_used;
  change.rmse = r.rms / diagonal;
  change.hausdorff = shape_distance(r.transform.apply(back), reference).hausdorff / diagonal;
  return change;
}

FormChange aligned_form_change(const Points& reference, const Points& other, const IcpOptions& icp) {
  const ShapeDistance d = aligned_shape_distance(other, reference, icp);
  const double diagonal = finite_bbox_diagonal(reference);
  FormChange change;
  change.rows = std::min(finite_rows(reference).rows(), finite_rows(other).rows());
  change.rmse = d.rmse / diagonal;
  change.hausdorff = d.hausdorff / diagonal;
  return change;
}

}  // namespace cshapes
