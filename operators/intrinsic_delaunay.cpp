#include "cshapes/operators/intrinsic_delaunay.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "cshapes/operators/cotangent_operator.h"
#include "cshapes/support/error.h"

namespace cshapes {

namespace {

// min(b + c - a, a + c - b, a + b - c): how far the lengths are from a degenerate triangle.
double margin_of(double a, double b, double c) {
  return std::min({b + c - a, a + c - b, a + b - c});
}

// Twin of each half-edge 3f+k: the half-edge in the neighbouring face that runs the other way between the
// same two vertices; -1 on boundary edges, non-manifold edges (three or more faces) and edges whose two faces
// run the same way (inconsistent orientation), none of which may be flipped.
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
      const int h = keyed[i].second, t = keyed[i + 1].second;
      const bool opposite = F(h / 3, h % 3) == F(t / 3, (t % 3 + 1) % 3);
      const bool loop = F(h / 3, h % 3) == F(h / 3, (h % 3 + 1) % 3);
      if (opposite && !loop) {
        twin[h] = t;
        twin[t] = h;
      }
    }
    i = j;
  }
  return twin;
}

}  // namespace

double intrinsic_face_area(const IntrinsicTriangulation& T, Index f) {
  return heron_area(T.length(f, 0), T.length(f, 1), T.length(f, 2));
}

double triangle_inequality_margin(const IntrinsicTriangulation& T, Index f) {
  return margin_of(T.length(f, 0), T.length(f, 1), T.length(f, 2));
}

IntrinsicTriangulation intrinsic_triangulation(const Mesh& mesh, double mollify_factor) {
  CSHAPES_REQUIRE(mollify_factor >= 0 && std::isfinite(mollify_factor),
                  "intrinsic triangulation: mollify_factor must be finite and >= 0, got ", mollify_factor);
  IntrinsicTriangulation T;
  T.F = mesh.F;
  T.length.resize(mesh.F.rows(), 3);
  double length_sum = 0;
  for (Index f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      int a = mesh.F(f, k), b = mesh.F(f, (k + 1) % 3);
      CSHAPES_REQUIRE(a >= 0 && a < mesh.num_vertices() && b >= 0 && b < mesh.num_vertices(), "face ", f,
                      " has a vertex index outside 0..", mesh.num_vertices() - 1);
      T.length(f, k) = (mesh.V.row(a) - mesh.V.row(b)).norm();
      CSHAPES_REQUIRE(std::isfinite(T.length(f, k)), "face ", f, " has a vertex with a non-finite coordinate");
      length_sum += T.length(f, k);
    }
  T.twin = twins(T.F);
  const Index m = mesh.F.rows();
  if (m == 0 || mollify_factor == 0) return T;
  // Sharp & Crane (2020) §4.5: δ = max_f max(0, ε − margin_f), added to every edge, raises every margin to ε
  // (adding δ to all three sides raises each a + b − c by exactly δ).
  T.margin = mollify_factor * length_sum / (3.0 * m);
  double delta = 0;
  for (Index f = 0; f < m; ++f) delta = std::max(delta, T.margin - triangle_inequality_margin(T, f));
  if (delta > 0) {
    T.mollification = delta;
    T.length.array() += delta;
  }
  return T;
}

Index non_delaunay_edges(const IntrinsicTriangulation& T, double tolerance) {
  const std::vector<int> twin = T.twin.size() == static_cast<size_t>(3 * T.F.rows()) ? T.twin : twins(T.F);
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
  IntrinsicTriangulation T = intrinsic_triangulation(mesh, options.mollify_factor);
  Faces& F = T.F;
  Eigen::MatrixX3d& len = T.length;
  std::vector<int>& twin = T.twin;
  const Index m = F.rows();
  const Index max_flips = options.max_flips > 0 ? options.max_flips : 100 * 3 * m;
  // New triangles must keep half the mollification margin (all of it is kept where none was asked for).
  const double keep = T.margin > 0 ? 0.5 * T.margin : 0.0;

  // Stack of edges to check, each by its smaller half-edge; an edge enters once per change of its faces.
  std::vector<int> stack;
  std::vector<char> queued(3 * m, 0);
  for (Index h = 0; h < 3 * m; ++h)
    if (twin[h] > h) stack.push_back(static_cast<int>(h)), queued[h] = 1;
  auto push = [&](int h) {
    if (twin[h] < 0) return;
    const int canonical = std::min(h, twin[h]);
    if (!queued[canonical]) queued[canonical] = 1, stack.push_back(canonical);
  };

  while (!stack.empty() && T.flips < max_flips) {
    const int h = stack.back();
    stack.pop_back();
    queued[h] = 0;
    const int t = twin[h];
    if (t < 0) continue;
    const int f = h / 3, g = t / 3, k = h % 3, kk = t % 3;
    if (f == g) continue;  // an edge inside a self-folded triangle: nothing to flip it to
    const int k1 = (k + 1) % 3, k2 = (k + 2) % 3, kk1 = (kk + 1) % 3, kk2 = (kk + 2) % 3;
    // f = (a, b, c) with h = a→b; g = (b, a, d) with t = b→a.
    const double l_ab = len(f, k), l_bc = len(f, k1), l_ca = len(f, k2), l_ad = len(g, kk1),
                 l_db = len(g, kk2);
    const double cot_c = cotangent(l_ab, l_bc, l_ca), cot_d = cotangent(l_ab, l_ad, l_db);
    if (cot_c + cot_d >= -options.tolerance) continue;
    // Unfold the two triangles into the plane: a at the origin, b on the x axis, c above, d below.
    const double cx = (l_ab * l_ab + l_ca * l_ca - l_bc * l_bc) / (2 * l_ab);
    const double cy = std::sqrt(std::max(0.0, l_ca * l_ca - cx * cx));
    const double dx = (l_ab * l_ab + l_ad * l_ad - l_db * l_db) / (2 * l_ab);
    const double dy = -std::sqrt(std::max(0.0, l_ad * l_ad - dx * dx));
    const double l_cd = std::hypot(cx - dx, cy - dy);
    // The quadrilateral a, d, b, c must be strictly convex at a and at b (then the new edge cd crosses ab and
    // both new triangles keep the orientation), and the new triangles must keep the margin. In exact
    // arithmetic every non-Delaunay edge passes (Bobenko & Springborn); in floating point a nearly degenerate
    // quadrilateral may not, and then the edge stays.
    const double turn_a = dx * cy - dy * cx;                             // 2·area(a, d, c)
    const double turn_b = (l_ab - dx) * (cy - dy) + dy * (cx - dx);      // 2·area(d, b, c)
    if (!(turn_a > 0 && turn_b > 0 && std::isfinite(l_cd) && margin_of(l_ad, l_cd, l_ca) > keep &&
          margin_of(l_db, l_bc, l_cd) > keep)) {
      ++T.skipped_flips;
      continue;
    }
    const int a = F(f, k), b = F(f, k1), c = F(f, k2), d = F(g, kk2);
    // The four outer half-edges move to new slots; their twins are carried by identity, and a twin that is
    // itself one of the six slots (the two faces share another edge) is mapped to its new slot too.
    // Old slot → new slot: a→d (g,kk1) → (f,0); c→a (f,k2) → (f,2); d→b (g,kk2) → (g,0); b→c (f,k1) → (g,1).
    const int old_slot[4] = {3 * g + kk1, 3 * f + k2, 3 * g + kk2, 3 * f + k1};
    const int new_slot[4] = {3 * f + 0, 3 * f + 2, 3 * g + 0, 3 * g + 1};
    auto moved = [&](int x) {
      for (int i = 0; i < 4; ++i)
        if (old_slot[i] == x) return new_slot[i];
      return x;  // a half-edge of another face
    };
    int outer_twin[4];
    for (int i = 0; i < 4; ++i) outer_twin[i] = twin[old_slot[i]] < 0 ? -1 : moved(twin[old_slot[i]]);
    // New f = (a, d, c): a→d, d→c, c→a.  New g = (d, b, c): d→b, b→c, c→d.
    F.row(f) << a, d, c;
    len.row(f) << l_ad, l_cd, l_ca;
    F.row(g) << d, b, c;
    len.row(g) << l_db, l_bc, l_cd;
    for (int i = 0; i < 4; ++i) {
      twin[new_slot[i]] = outer_twin[i];
      if (outer_twin[i] >= 0) twin[outer_twin[i]] = new_slot[i];
    }
    twin[3 * f + 1] = 3 * g + 2;
    twin[3 * g + 2] = 3 * f + 1;
    // queued[] is indexed by the smaller half-edge of a pair; the pairs changed, so re-mark the six slots.
    for (int x : {3 * f, 3 * f + 1, 3 * f + 2, 3 * g, 3 * g + 1, 3 * g + 2}) queued[x] = 0;
    ++T.flips;
    for (int x : new_slot) push(x);
  }
  return T;
}

std::string intrinsic_triangulation_defect(const Mesh& mesh, const IntrinsicTriangulation& T) {
  const Index m = T.F.rows();
  if (T.length.rows() != m) return "length has " + std::to_string(T.length.rows()) + " rows for " +
                                    std::to_string(m) + " faces";
  if (T.twin.size() != static_cast<size_t>(3 * m)) return "twin has the wrong size";
  for (Index h = 0; h < 3 * m; ++h) {
    const int t = T.twin[h];
    if (t < 0) continue;
    if (t >= 3 * m || T.twin[t] != h) return "half-edge " + std::to_string(h) + ": twin not mutual";
    const int a = T.F(h / 3, h % 3), b = T.F(h / 3, (h % 3 + 1) % 3);
    const int ta = T.F(t / 3, t % 3), tb = T.F(t / 3, (t % 3 + 1) % 3);
    if (a != tb || b != ta) return "half-edge " + std::to_string(h) + ": twin joins other vertices";
    if (T.length(h / 3, h % 3) != T.length(t / 3, t % 3))
      return "half-edge " + std::to_string(h) + ": twin has another length";
  }
  for (Index f = 0; f < m; ++f) {
    const double margin = triangle_inequality_margin(T, f);
    if (!(margin > 0) || !std::isfinite(margin) || !(intrinsic_face_area(T, f) > 0))
      return "face " + std::to_string(f) + " is degenerate (margin " + std::to_string(margin) + ")";
  }
  std::vector<char> in_input(mesh.num_vertices(), 0), in_result(mesh.num_vertices(), 0);
  for (Index f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) in_input[mesh.F(f, k)] = 1;
  for (Index f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) {
      const int v = T.F(f, k);
      if (v < 0 || v >= mesh.num_vertices()) return "face " + std::to_string(f) + " has a bad vertex index";
      in_result[v] = 1;
    }
  for (Index v = 0; v < mesh.num_vertices(); ++v)
    if (in_input[v] && !in_result[v]) return "vertex " + std::to_string(v) + " lost every face";
  return "";
}

}  // namespace cshapes
