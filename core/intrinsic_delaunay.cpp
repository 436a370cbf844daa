#include "core/intrinsic_delaunay.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/error.h"

namespace cshapes {

namespace {

// Heron's formula with the sides sorted (Kahan's stable form); 0 for a degenerate or impossible triangle.
double heron(double a, double b, double c) {
  if (a < b) std::swap(a, b);
  if (a < c) std::swap(a, c);
  if (b < c) std::swap(b, c);
  double p = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c));
  return p > 0 ? 0.25 * std::sqrt(p) : 0.0;
}

// Cotangent of the angle facing the side of length `opposite` in a triangle with sides `x`, `y` beside it.
double cotangent(double opposite, double x, double y) {
  double area = heron(opposite, x, y);
  return (x * x + y * y - opposite * opposite) / (4 * std::max(area, 1e-300));
}

// Twin of each half-edge 3f+k (the same edge in the neighbouring face), -1 on boundary or non-manifold edges.
std::vector<int> twins(const Faces& F) {
  const Index m = F.rows();
  std::vector<std::pair<uint64_t, int>> keyed;
  keyed.reserve(3 * m);
  for (Index f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) {
      uint64_t a = F(f, k), b = F(f, (k + 1) % 3);
      if (a > b) std::swap(a, b);
      keyed.emplace_back((a << 32) | b, static_cast<int>(3 * f + k));
    }
  std::sort(keyed.begin(), keyed.end());
  std::vector<int> twin(3 * m, -1);
  for (size_t i = 0; i < keyed.size();) {
    size_t j = i;
    while (j < keyed.size() && keyed[j].first == keyed[i].first) ++j;
    if (j - i == 2) {
      twin[keyed[i].second] = keyed[i + 1].second;
      twin[keyed[i + 1].second] = keyed[i].second;
    }
    i = j;
  }
  return twin;
}

}  // namespace

double intrinsic_face_area(const IntrinsicTriangulation& T, Index f) {
  return heron(T.length(f, 0), T.length(f, 1), T.length(f, 2));
}

IntrinsicTriangulation intrinsic_triangulation(const Mesh& mesh) {
  IntrinsicTriangulation T;
  T.F = mesh.F;
  T.length.resize(mesh.F.rows(), 3);
  for (Index f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      int a = mesh.F(f, k), b = mesh.F(f, (k + 1) % 3);
      CSHAPES_REQUIRE(a >= 0 && a < mesh.num_vertices() && b >= 0 && b < mesh.num_vertices(), "face ", f,
                      " has a vertex index outside 0..", mesh.num_vertices() - 1);
      T.length(f, k) = (mesh.V.row(a) - mesh.V.row(b)).norm();
    }
  return T;
}

Index non_delaunay_edges(const IntrinsicTriangulation& T, double tolerance) {
  std::vector<int> twin = twins(T.F);
  Index count = 0;
  for (Index h = 0; h < static_cast<Index>(twin.size()); ++h) {
    const int t = twin[h];
    if (t < 0 || t < h) continue;
    const Index f = h / 3, g = t / 3;
    const int k = h % 3, kk = t % 3;
    double cot_f = cotangent(T.length(f, k), T.length(f, (k + 1) % 3), T.length(f, (k + 2) % 3));
    double cot_g = cotangent(T.length(g, kk), T.length(g, (kk + 1) % 3), T.length(g, (kk + 2) % 3));
    if (cot_f + cot_g < -tolerance) ++count;
  }
  return count;
}

IntrinsicTriangulation intrinsic_delaunay(const Mesh& mesh, const IntrinsicDelaunayOptions& options) {
  IntrinsicTriangulation T = intrinsic_triangulation(mesh);
  Faces& F = T.F;
  Eigen::MatrixX3d& len = T.length;
  const Index m = F.rows();
  std::vector<int> twin = twins(F);
  const Index max_flips = options.max_flips > 0 ? options.max_flips : 100 * 3 * m;

  // Stack of half-edges to check; each interior edge enters once per modification of its triangles.
  std::vector<int> stack;
  std::vector<char> queued(3 * m, 0);
  for (Index h = 0; h < 3 * m; ++h)
    if (twin[h] > h) stack.push_back(static_cast<int>(h)), queued[h] = 1;
  auto push = [&](int h) {
    if (twin[h] < 0) return;
    int canonical = std::min(h, twin[h]);
    if (!queued[canonical]) queued[canonical] = 1, stack.push_back(canonical);
  };

  while (!stack.empty() && T.flips < max_flips) {
    const int h = stack.back();
    stack.pop_back();
    queued[h] = 0;
    const int t = twin[h];
    if (t < 0) continue;
    const int f = h / 3, g = t / 3, k = h % 3, kk = t % 3;
    if (f == g) continue;
    const int k1 = (k + 1) % 3, k2 = (k + 2) % 3, kk1 = (kk + 1) % 3, kk2 = (kk + 2) % 3;
    // f = (a, b, c) with h = a→b; g = (b, a, d) with t = b→a.
    const double l_ab = len(f, k), l_bc = len(f, k1), l_ca = len(f, k2), l_ad = len(g, kk1),
                 l_db = len(g, kk2);
    const double cot_c = cotangent(l_ab, l_bc, l_ca), cot_d = cotangent(l_ab, l_ad, l_db);
    if (cot_c + cot_d >= -options.tolerance) continue;
    const int a = F(f, k), b = F(f, k1), c = F(f, k2), d = F(g, kk2);
    // Unfold the two triangles into the plane: a at the origin, b on the x axis, c above, d below.
    const double cx = (l_ab * l_ab + l_ca * l_ca - l_bc * l_bc) / (2 * l_ab);
    const double cy = std::sqrt(std::max(0.0, l_ca * l_ca - cx * cx));
    const double dx = (l_ab * l_ab + l_ad * l_ad - l_db * l_db) / (2 * l_ab);
    const double dy = -std::sqrt(std::max(0.0, l_ad * l_ad - dx * dx));
    const double l_cd = std::hypot(cx - dx, cy - dy);
    // Outer half-edges and their twins before the faces are rewritten.
    const int o_bc = twin[3 * f + k1], o_ca = twin[3 * f + k2], o_ad = twin[3 * g + kk1],
              o_db = twin[3 * g + kk2];
    // New f = (a, d, c): a→d, d→c, c→a.  New g = (d, b, c): d→b, b→c, c→d.
    F.row(f) << a, d, c;
    len.row(f) << l_ad, l_cd, l_ca;
    F.row(g) << d, b, c;
    len.row(g) << l_db, l_bc, l_cd;
    auto link = [&](int x, int y) {
      twin[x] = y;
      if (y >= 0) twin[y] = x;
    };
    link(3 * f + 0, o_ad);
    link(3 * f + 1, 3 * g + 2);
    link(3 * f + 2, o_ca);
    link(3 * g + 0, o_db);
    link(3 * g + 1, o_bc);
    // queued[] is indexed by the smaller half-edge of a pair; the pairs changed, so re-mark the outer edges.
    for (int x : {3 * f, 3 * f + 1, 3 * f + 2, 3 * g, 3 * g + 1, 3 * g + 2}) queued[x] = 0;
    ++T.flips;
    for (int x : {3 * f + 0, 3 * f + 2, 3 * g + 0, 3 * g + 1}) push(x);
  }
  return T;
}

}  // namespace cshapes
