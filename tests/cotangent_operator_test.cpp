#include "cshapes/operators/cotangent_operator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "cshapes/geodesics/heat_method.h"
#include "cshapes/operators/intrinsic_delaunay.h"
#include "cshapes/operators/laplace_beltrami.h"
#include "cshapes/data/synthetic.h"
#include "tests/test_support.h"

namespace cshapes {
namespace cotangent_operator_test {

// Vertices on no boundary edge (an edge of one face).
std::vector<Index> interior_vertices(const Mesh& mesh) {
  std::map<std::pair<int, int>, int> faces_at;
  for (Index f = 0; f < mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.F(f, k), b = mesh.F(f, (k + 1) % 3);
      ++faces_at[{std::min(a, b), std::max(a, b)}];
    }
  std::vector<char> boundary(mesh.num_vertices(), 0);
  for (const auto& [edge, count] : faces_at)
    if (count == 1) boundary[edge.first] = boundary[edge.second] = 1;
  std::vector<Index> interior;
  for (Index i = 0; i < mesh.num_vertices(); ++i)
    if (!boundary[i]) interior.push_back(i);
  return interior;
}

TEST(CotangentOperator, CotangentAndAreaOfKnownTriangles) {
  // The 3-4-5 right triangle: area 6, the right angle's cotangent 0, the others 4/3 and 3/4.
  EXPECT_DOUBLE_EQ(heron_area(3, 4, 5), 6);
  EXPECT_DOUBLE_EQ(heron_area(5, 3, 4), 6);  // any order of the sides
  EXPECT_NEAR(cotangent(5, 3, 4), 0, 1e-15);
  EXPECT_DOUBLE_EQ(cotangent(3, 4, 5), 4.0 / 3);
  EXPECT_DOUBLE_EQ(cotangent(4, 3, 5), 3.0 / 4);
  // Equilateral: cot 60° = 1/√3 at any scale; a degenerate triangle has no area.
  EXPECT_NEAR(cotangent(1, 1, 1), 1 / std::sqrt(3.0), 1e-15);
  EXPECT_NEAR(cotangent(1e-8, 1e-8, 1e-8), 1 / std::sqrt(3.0), 1e-15);
  EXPECT_EQ(heron_area(1, 2, 3), 0);
  EXPECT_EQ(heron_area(1, 2, 4), 0);
}

// On a flat mesh the cotangent Laplacian is zero on linear functions at every interior vertex, the masses
// sum to the area, and L·1 = 0: on the grid's own triangles and on obtuse ones, with and without the
// intrinsic Delaunay flips.
TEST(CotangentOperator, FlatGridKnownAnswers) {
  const std::vector<Mesh> meshes = {grid(13, 9, 2.0, 1.5), test::obtuse_grid(13, 9)};
  const double areas[2] = {2.0 * 1.5, -1};
  for (int obtuse = 0; obtuse < 2; ++obtuse) {
    const Mesh& mesh = meshes[obtuse];
    const std::vector<Index> interior = interior_vertices(mesh);
    ASSERT_GT(interior.size(), 50u);
    for (bool delaunay : {false, true}) {
      const IntrinsicTriangulation T = delaunay ? intrinsic_delaunay(mesh) : intrinsic_triangulation(mesh);
      const CotangentOperator op = cotangent_operator(T, mesh.num_vertices());
      if (areas[obtuse] > 0)
        EXPECT_NEAR(op.mass.sum(), areas[obtuse], 1e-12) << "delaunay " << delaunay;
      else  // the flips keep the surface: the same total area as the mesh's own triangles
        EXPECT_NEAR(op.mass.sum(), lumped_mass(mesh).sum(), 1e-12) << "delaunay " << delaunay;
      const Eigen::VectorXd ones = Eigen::VectorXd::Ones(mesh.num_vertices());
      EXPECT_LT((op.L * ones).cwiseAbs().maxCoeff(), 1e-12);
      const Eigen::VectorXd linear = 0.7 * mesh.V.col(0) - 1.3 * mesh.V.col(1);
      const Eigen::VectorXd Lu = op.L * linear;
      for (Index i : interior) EXPECT_NEAR(Lu[i], 0, 1e-11) << "vertex " << i << ", obtuse " << obtuse;
      EXPECT_TRUE(op.L.isApprox(Eigen::SparseMatrix<double>(op.L.transpose())));
    }
  }
}

// On the unit sphere the coordinate functions are eigenfunctions of −Δ with eigenvalue 2: L x ≈ 2 M x, and
// the masses sum to about 4π.
TEST(CotangentOperator, UnitSphereKnownAnswers) {
  const Mesh sphere = icosphere(4);
  const CotangentOperator op = cotangent_operator(intrinsic_delaunay(sphere), sphere.num_vertices());
  EXPECT_NEAR(op.mass.sum(), 4 * M_PI, 0.01 * 4 * M_PI);
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd x = sphere.V.col(c);
    const Eigen::VectorXd residual = op.L * x - 2 * op.mass.asDiagonal() * x;
    EXPECT_LT(residual.norm() / (2 * op.mass.asDiagonal() * x).norm(), 0.02) << "coordinate " << c;
  }
}

// One operator: the heat method's L and M are the Laplace–Beltrami eigensolver's, bit for bit, on the
// intrinsic Delaunay triangulation and on the mesh's own triangles.
TEST(CotangentOperator, HeatMethodAndEigensolverUseTheSameMatrices) {
  const Mesh mesh = test::obtuse_grid(11, 7);
  for (bool delaunay : {true, false}) {
    HeatMethodOptions options;
    options.intrinsic_delaunay = delaunay;
    const HeatMethod heat(mesh, options);
    const LaplacianMatrices lb = cotangent_laplacian(mesh, delaunay);
    const Eigen::SparseMatrix<double> difference = heat.laplacian() - lb.L;
    EXPECT_EQ(difference.norm(), 0) << "delaunay " << delaunay;
    EXPECT_EQ(heat.laplacian().nonZeros(), lb.L.nonZeros());
    EXPECT_TRUE(heat.mass() == lb.mass) << "delaunay " << delaunay;
  }
}

// The extrinsic lumped mass (from coordinates) is the intrinsic one of the mesh's own triangles.
TEST(CotangentOperator, ExtrinsicAndIntrinsicMassAgree) {
  const Mesh mesh = icosphere(3);
  const Eigen::VectorXd extrinsic = lumped_mass(mesh);
  const Eigen::VectorXd intrinsic =
      cotangent_operator(intrinsic_triangulation(mesh, 0), mesh.num_vertices()).mass;
  EXPECT_LT((extrinsic - intrinsic).cwiseAbs().maxCoeff(), 1e-12 * extrinsic.maxCoeff());
}

}  // namespace cotangent_operator_test
}  // namespace cshapes
