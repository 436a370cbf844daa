#include "cshapes/mesh/mesh_defects.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <tuple>

#include "cshapes/support/error.h"

namespace cshapes {

namespace {

template <typename T>
void keep_example(std::vector<T>& examples, const T& example) {
  if (examples.size() < MeshDefects::max_examples) examples.push_back(example);
}

// "3 non-manifold edges (1-2, 4 faces; ...)": count, a plural, and the examples with "..." when more.
template <typename T, typename Show>
void describe(std::vector<std::string>& parts, Index count, const char* singular, const char* plural,
              const std::vector<T>& examples, Show show) {
  if (count == 0) return;
  std::string text = detail::concat(count, " ", count == 1 ? singular : plural, " (");
  for (size_t k = 0; k < examples.size(); ++k) text += (k ? "; " : "") + show(examples[k]);
  if (static_cast<Index>(examples.size()) < count) text += "; ...";
  parts.push_back(text + ")");
}

}  // namespace

bool face_repeats_vertex(const Faces& F, Index f) {
  return F(f, 0) == F(f, 1) || F(f, 1) == F(f, 2) || F(f, 0) == F(f, 2);
}

bool face_has_zero_area(const Points& V, const Faces& F, Index f) {
  const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
  Eigen::Vector3d u = b - a, w = c - a;
  // The test is a ratio: the edges are brought to unit size by an exact power of two first, as squares and
  // cross products of a face scaled by 1e155 overflow (every face "zero-area") and by 1e-155 underflow.
  const double largest = std::max(u.cwiseAbs().maxCoeff(), w.cwiseAbs().maxCoeff());
  if (!(largest > 0)) return true;  // all three corners at one point
  if (std::isfinite(largest)) {
    int exponent = 0;
    std::frexp(largest, &exponent);
    u = u * std::ldexp(1.0, -exponent);
    w = w * std::ldexp(1.0, -exponent);
  }
  const double scale = u.squaredNorm() + (w - u).squaredNorm() + w.squaredNorm();
  return u.cross(w).norm() <= 1e-12 * scale;
}

std::array<int, 3> sorted_face(const Faces& F, Index f) {
  std::array<int, 3> s = {F(f, 0), F(f, 1), F(f, 2)};
  std::sort(s.begin(), s.end());
  return s;
}

EdgeFaceCount edge_face_count(const Faces& F) {
  EdgeFaceCount r;
  r.E = mesh_edges(F);
  r.faces = edge_face_counts(F, r.E);
  return r;
}

CornerFans corner_fans(Index num_vertices, const Faces& F) {
  const Index m = F.rows();
  // (edge, face, position of the edge's first corner in the face) for every edge of every face.
  struct HalfEdge {
    int a, b, face;
    bool operator<(const HalfEdge& o) const { return std::tie(a, b, face) < std::tie(o.a, o.b, o.face); }
  };
  std::vector<HalfEdge> half;
  half.reserve(3 * m);
  for (Index f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) {
      int a = F(f, k), b = F(f, (k + 1) % 3);
      half.push_back({std::min(a, b), std::max(a, b), static_cast<int>(f)});
    }
  std::sort(half.begin(), half.end());
  std::vector<int> parent(3 * m);
  std::iota(parent.begin(), parent.end(), 0);
  auto corner = [&](int face, int vertex) {
    for (int c = 0; c < 3; ++c)
      if (F(face, c) == vertex) return 3 * face + c;
    return -1;  // unreachable: the face holds the vertex
  };
  for (size_t i = 0; i < half.size();) {
    size_t j = i;
    while (j < half.size() && half[j].a == half[i].a && half[j].b == half[i].b) ++j;
    if (j - i == 2) {  // a manifold edge joins the two faces' corners at both of its ends
      for (int v : {half[i].a, half[i].b}) {
        int x = union_find_root(parent, corner(half[i].face, v)),
            y = union_find_root(parent, corner(half[i + 1].face, v));
        if (x != y) parent[std::max(x, y)] = std::min(x, y);
      }
    }
    i = j;
  }
  CornerFans fans;
  fans.corner_fan.assign(3 * m, -1);
  fans.fan_count.assign(num_vertices, 0);
  std::vector<int> fan_of_root(3 * m, -1);
  for (Index k = 0; k < 3 * m; ++k) {
    int root = union_find_root(parent, static_cast<int>(k));
    if (fan_of_root[root] < 0) fan_of_root[root] = fans.fan_count[F(k / 3, k % 3)]++;
    fans.corner_fan[k] = fan_of_root[root];
  }
  return fans;
}

bool MeshDefects::any() const {
  return repeated_vertex_faces || duplicate_faces || zero_area_faces || zero_length_edges ||
         nonmanifold_edges || nonmanifold_vertices || isolated_vertices || components > 1;
}

std::string MeshDefects::summary() const {
  std::vector<std::string> parts;
  auto pair = [](const std::array<int, 2>& p) { return detail::concat(p[0], "-", p[1]); };
  auto one = [](int i) { return std::to_string(i); };
  describe(parts, nonmanifold_edges, "non-manifold edge", "non-manifold edges", nonmanifold_edge_examples,
           [](const std::array<int, 3>& e) { return detail::concat(e[0], "-", e[1], ", ", e[2], " faces"); });
  describe(parts, nonmanifold_vertices, "non-manifold vertex", "non-manifold vertices",
           nonmanifold_vertex_examples, one);
  describe(parts, duplicate_faces, "duplicate face", "duplicate faces", duplicate_face_examples,
           [](const std::array<int, 2>& d) { return detail::concat(d[0], " = ", d[1]); });
  describe(parts, repeated_vertex_faces, "face repeating a vertex", "faces repeating a vertex",
           repeated_vertex_face_examples, one);
  describe(parts, zero_area_faces, "zero-area face", "zero-area faces", zero_area_face_examples, one);
  describe(parts, zero_length_edges, "zero-length edge", "zero-length edges", zero_length_edge_examples,
           pair);
  describe(parts, isolated_vertices, "isolated vertex", "isolated vertices", isolated_vertex_examples, one);
  if (components > 1) {
    std::string sizes;
    for (size_t k = 0; k < component_sizes.size() && k < max_examples; ++k)
      sizes += (k ? ", " : "") + std::to_string(component_sizes[k]);
    if (component_sizes.size() > max_examples) sizes += ", ...";
    parts.push_back(detail::concat(components, " components (", sizes, " vertices)"));
  }
  if (parts.empty()) return "none";
  std::string out;
  for (size_t k = 0; k < parts.size(); ++k) out += (k ? "; " : "") + parts[k];
  return out;
}

MeshDefects mesh_defects(const Mesh& mesh) {
  MeshDefects d;
  const Index n = mesh.num_vertices(), m = mesh.num_faces();
  const Faces& F = mesh.F;

  // Faces: repeated vertices, duplicates (by sorted vertex set), zero area. `proper` keeps the faces that
  // count for the edges' and vertices' topology: no repeated vertex, first copy of a duplicate.
  std::vector<int> proper;
  std::map<std::array<int, 3>, int> first_with_set;
  for (Index f = 0; f < m; ++f) {
    if (face_repeats_vertex(F, f)) {
      ++d.repeated_vertex_faces;
      keep_example(d.repeated_vertex_face_examples, static_cast<int>(f));
      continue;
    }
    auto [it, inserted] = first_with_set.emplace(sorted_face(F, f), static_cast<int>(f));
    if (!inserted) {
      ++d.duplicate_faces;
      keep_example(d.duplicate_face_examples, {static_cast<int>(f), it->second});
      continue;
    }
    proper.push_back(static_cast<int>(f));
    if (face_has_zero_area(mesh.V, F, f)) {
      ++d.zero_area_faces;
      keep_example(d.zero_area_face_examples, static_cast<int>(f));
    }
  }
  Faces P(proper.size(), 3);
  for (size_t k = 0; k < proper.size(); ++k) P.row(k) = F.row(proper[k]);

  EdgeFaceCount ec = edge_face_count(P);
  std::vector<char> on_nonmanifold_edge(n, 0);
  std::vector<int> boundary;
  for (Index e = 0; e < ec.E.rows(); ++e) {
    const int a = ec.E(e, 0), b = ec.E(e, 1);
    if (mesh.V.row(a) == mesh.V.row(b)) {
      ++d.zero_length_edges;
      keep_example(d.zero_length_edge_examples, {a, b});
    }
    if (ec.faces[e] > 2) {
      ++d.nonmanifold_edges;
      keep_example(d.nonmanifold_edge_examples, {a, b, ec.faces[e]});
      on_nonmanifold_edge[a] = on_nonmanifold_edge[b] = 1;
    }
    if (ec.faces[e] == 1) boundary.push_back(static_cast<int>(e));
  }
  d.boundary_edges = static_cast<Index>(boundary.size());
  Edges B(boundary.size(), 2);
  for (size_t k = 0; k < boundary.size(); ++k) B.row(k) = ec.E.row(boundary[k]);
  Components loops = connected_components(n, B);
  std::vector<char> loop_has_edge(loops.count, 0);
  for (Index k = 0; k < B.rows(); ++k) loop_has_edge[loops.label[B(k, 0)]] = 1;
  d.boundary_loops = static_cast<int>(std::count(loop_has_edge.begin(), loop_has_edge.end(), 1));

  CornerFans fans = corner_fans(n, P);
  for (Index v = 0; v < n; ++v)
    if (fans.fan_count[v] > 1 && !on_nonmanifold_edge[v]) {
      ++d.nonmanifold_vertices;
      keep_example(d.nonmanifold_vertex_examples, static_cast<int>(v));
    }

  // Components of the edge graph of every face (a repeated-vertex face still joins its two vertices).
  // A point cloud has no edges: its components are not described (see mesh/knn_graph.h for its graph).
  if (!mesh.is_point_cloud()) {
    Components comp = connected_components(n, mesh_edges(F));
    d.components = comp.count;
    d.component_sizes = comp.sizes;
    std::sort(d.component_sizes.begin(), d.component_sizes.end(), std::greater<int>());
    std::vector<char> used(n, 0);
    for (Index f = 0; f < m; ++f)
      for (int c = 0; c < 3; ++c) used[F(f, c)] = 1;
    for (Index v = 0; v < n; ++v)
      if (!used[v]) {
        ++d.isolated_vertices;
        keep_example(d.isolated_vertex_examples, static_cast<int>(v));
      }
  }
  return d;
}

}  // namespace cshapes
