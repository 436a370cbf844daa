#include "cshapes/mesh/subdivide.h"

#include <algorithm>
#include <functional>
#include <map>
#include <utility>
#include <vector>

#include "cshapes/support/error.h"

namespace cshapes {

Mesh midpoint_subdivide(const Mesh& mesh) {
  Edges E = mesh_edges(mesh.F);
  const Index n = mesh.num_vertices();
  std::map<std::pair<int, int>, int> midpoint;
  Mesh out;
  out.V.resize(n + E.rows(), 3);
  out.V.topRows(n) = mesh.V;
  for (Index e = 0; e < E.rows(); ++e) {
    out.V.row(n + e) = 0.5 * (mesh.V.row(E(e, 0)) + mesh.V.row(E(e, 1)));
    midpoint[{E(e, 0), E(e, 1)}] = static_cast<int>(n + e);
  }
  auto mid = [&](int a, int b) { return midpoint.at({std::min(a, b), std::max(a, b)}); };
  out.F.resize(4 * mesh.num_faces(), 3);
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    int a = mesh.F(f, 0), b = mesh.F(f, 1), c = mesh.F(f, 2);
    int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
    out.F.row(4 * f) << a, ab, ca;
    out.F.row(4 * f + 1) << b, bc, ab;
    out.F.row(4 * f + 2) << c, ca, bc;
    out.F.row(4 * f + 3) << ab, bc, ca;
  }
  return out;
}

Mesh split_longest_edges(Mesh mesh, Index target) {
  while (mesh.num_vertices() < target) {
    std::map<std::pair<int, int>, std::vector<int>> faces_of;  // undirected edge → faces
    for (Index f = 0; f < mesh.num_faces(); ++f)
      for (int k = 0; k < 3; ++k) {
        int a = mesh.F(f, k), b = mesh.F(f, (k + 1) % 3);
        faces_of[{std::min(a, b), std::max(a, b)}].push_back(static_cast<int>(f));
      }
    std::vector<std::pair<double, std::pair<int, int>>> by_length;
    for (const auto& [edge, faces] : faces_of)
      if (faces.size() <= 2)
        by_length.push_back({(mesh.V.row(edge.first) - mesh.V.row(edge.second)).norm(), edge});
    std::sort(by_length.begin(), by_length.end(), std::greater<>());
    std::vector<char> touched(mesh.num_faces(), 0);
    std::vector<Eigen::Vector3i> faces(mesh.num_faces());
    for (Index f = 0; f < mesh.num_faces(); ++f) faces[f] = mesh.F.row(f).transpose();
    std::vector<Eigen::RowVector3d> new_vertices;
    Index n = mesh.num_vertices();
    for (const auto& [length, edge] : by_length) {
      if (n + static_cast<Index>(new_vertices.size()) >= target) break;
      const std::vector<int>& fs = faces_of[edge];
      if (std::any_of(fs.begin(), fs.end(), [&](int f) { return touched[f]; })) continue;
      const int m = static_cast<int>(n + new_vertices.size());
      new_vertices.push_back(0.5 * (mesh.V.row(edge.first) + mesh.V.row(edge.second)));
      for (int f : fs) {
        touched[f] = 1;
        Eigen::Vector3i t = faces[f];
        int k = 0;  // t(k) → t(k+1) is the split edge
        while (!((t(k) == edge.first && t((k + 1) % 3) == edge.second) ||
                 (t(k) == edge.second && t((k + 1) % 3) == edge.first)))
          ++k;
        const int a = t(k), b = t((k + 1) % 3), c = t((k + 2) % 3);
        faces[f] = Eigen::Vector3i(a, m, c);
        faces.emplace_back(m, b, c);
      }
    }
    CSHAPES_REQUIRE(!new_vertices.empty(), "split_longest_edges: no edge left to split (",
                    mesh.num_vertices(), " vertices, ", target, " wanted)");
    Mesh out;
    out.V.resize(n + new_vertices.size(), 3);
    out.V.topRows(n) = mesh.V;
    for (size_t k = 0; k < new_vertices.size(); ++k) out.V.row(n + k) = new_vertices[k];
    out.F.resize(faces.size(), 3);
    for (size_t f = 0; f < faces.size(); ++f) out.F.row(f) = faces[f].transpose();
    mesh = std::move(out);
  }
  return mesh;
}

RefineToVertexCountResult refine_to_vertex_count(Mesh mesh, Index target) {
  RefineToVertexCountResult result;
  while (mesh.num_vertices() + mesh_edges(mesh.F).rows() <= target) {
    mesh = midpoint_subdivide(mesh);
    ++result.subdivisions;
  }
  const Index before = mesh.num_vertices();
  result.mesh = split_longest_edges(std::move(mesh), target);
  result.edge_splits = result.mesh.num_vertices() - before;
  return result;
}

}  // namespace cshapes
