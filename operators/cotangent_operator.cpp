#include "cshapes/operators/cotangent_operator.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace cshapes {

double heron_area(double a, double b, double c) {
  if (a < b) std::swap(a, b);
  if (a < c) std::swap(a, c);
  if (b < c) std::swap(b, c);
  const double p = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c));
  return p > 0 ? 0.25 * std::sqrt(p) : 0.0;
}

double cotangent(double opposite, double x, double y) {
  const double area = heron_area(opposite, x, y);
  return (x * x + y * y - opposite * opposite) / (4 * std::max(area, 1e-300));
}

CotangentOperator cotangent_operator(const IntrinsicTriangulation& T, Index num_vertices) {
  const Index m = T.F.rows();
  CotangentOperator out;
  out.mass = Eigen::VectorXd::Zero(num_vertices);
  std::vector<Eigen::Triplet<double>> stiffness;
  stiffness.reserve(12 * m);
  for (Index f = 0; f < m; ++f) {
    const int v[3] = {T.F(f, 0), T.F(f, 1), T.F(f, 2)};
    // length(f, k) is the edge from corner k to k+1, so the edge opposite corner c is length(f, (c+1) % 3).
    double opposite[3];
    for (int c = 0; c < 3; ++c) opposite[c] = T.length(f, (c + 1) % 3);
    const double area = heron_area(opposite[0], opposite[1], opposite[2]);
    for (int c = 0; c < 3; ++c) {
      out.mass[v[c]] += area / 3;
      // The edge (a, b) facing corner c gets half its cotangent; the sides at c are those opposite a and b.
      const int a = (c + 1) % 3, b = (c + 2) % 3;
      const double w = cotangent(opposite[c], opposite[a], opposite[b]) / 2;
      stiffness.emplace_back(v[a], v[b], -w);
      stiffness.emplace_back(v[b], v[a], -w);
      stiffness.emplace_back(v[a], v[a], w);
      stiffness.emplace_back(v[b], v[b], w);
    }
  }
  out.L.resize(num_vertices, num_vertices);
  out.L.setFromTriplets(stiffness.begin(), stiffness.end());
  return out;
}

Eigen::VectorXd lumped_mass(const Mesh& mesh) {
  Eigen::VectorXd mass = Eigen::VectorXd::Zero(mesh.num_vertices());
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)),
                          c = mesh.V.row(mesh.F(f, 2));
    const double third = (b - a).cross(c - a).norm() / 6.0;
    for (int k = 0; k < 3; ++k) mass[mesh.F(f, k)] += third;
  }
  return mass;
}

}  // namespace cshapes
