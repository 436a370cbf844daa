#include "cshapes/mesh/mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "cshapes/support/error.h"
#include "cshapes/mesh/mesh_defects.h"

namespace cshapes {

Mesh mesh_from_vectors(const std::vector<Eigen::Vector3d>& vertices,
                       const std::vector<Eigen::Vector3i>& triangles) {
  Mesh m;
  m.V.resize(static_cast<Index>(vertices.size()), 3);
  for (size_t i = 0; i < vertices.size(); ++i) m.V.row(static_cast<Index>(i)) = vertices[i];
  m.F.resize(static_cast<Index>(triangles.size()), 3);
  for (size_t f = 0; f < triangles.size(); ++f) m.F.row(static_cast<Index>(f)) = triangles[f];
  return m;
}

Edges mesh_edges(const Faces& F) {
  std::vector<std::pair<int, int>> all;
  all.reserve(3 * F.rows());
  for (Index f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      int a = F(f, k), b = F(f, (k + 1) % 3);
      if (a == b) continue;
      all.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end()), all.end());
  Edges E(all.size(), 2);
  for (size_t e = 0; e < all.size(); ++e) E.row(e) << all[e].first, all[e].second;
  return E;
}

Eigen::VectorXd edge_lengths(const Points& V, const Edges& E) {
  Eigen::VectorXd d(E.rows());
  for (Index e = 0; e < E.rows(); ++e) d[e] = (V.row(E(e, 0)) - V.row(E(e, 1))).norm();
  return d;
}

Adjacency adjacency(Index num_vertices, const Edges& E) {
  Adjacency adj;
  adj.offsets.assign(num_vertices + 1, 0);
  for (Index e = 0; e < E.rows(); ++e) {
    ++adj.offsets[E(e, 0) + 1];
    ++adj.offsets[E(e, 1) + 1];
  }
  std::partial_sum(adj.offsets.begin(), adj.offsets.end(), adj.offsets.begin());
  adj.neighbors.resize(2 * E.rows());
  adj.edge_ids.resize(2 * E.rows());
  std::vector<int> fill(adj.offsets.begin(), adj.offsets.end() - 1);
  for (Index e = 0; e < E.rows(); ++e) {
    for (int s = 0; s < 2; ++s) {
      int i = E(e, s), j = E(e, 1 - s);
      adj.neighbors[fill[i]] = j;
      adj.edge_ids[fill[i]] = static_cast<int>(e);
      ++fill[i];
    }
  }
  // Sort each neighbour list by index, carrying the edge ids along.
  std::vector<std::pair<int, int>> tmp;
  for (Index i = 0; i < num_vertices; ++i) {
    int begin = adj.offsets[i], end = adj.offsets[i + 1];
    tmp.clear();
    for (int k = begin; k < end; ++k) tmp.emplace_back(adj.neighbors[k], adj.edge_ids[k]);
    std::sort(tmp.begin(), tmp.end());
    for (int k = begin; k < end; ++k) {
      adj.neighbors[k] = tmp[k - begin].first;
      adj.edge_ids[k] = tmp[k - begin].second;
    }
  }
  return adj;
}

int Components::largest() const {
  return static_cast<int>(std::max_element(sizes.begin(), sizes.end()) - sizes.begin());
}

int union_find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

Components connected_components(Index num_vertices, const Edges& E) {
  std::vector<int> parent(num_vertices);
  std::iota(parent.begin(), parent.end(), 0);
  for (Index e = 0; e < E.rows(); ++e) {
    int a = union_find_root(parent, E(e, 0)), b = union_find_root(parent, E(e, 1));
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
  Components c;
  c.label.assign(num_vertices, -1);
  std::vector<int> root_label(num_vertices, -1);
  for (Index i = 0; i < num_vertices; ++i) {
    int r = union_find_root(parent, static_cast<int>(i));
    if (root_label[r] < 0) {
      root_label[r] = c.count++;
      c.sizes.push_back(0);
    }
    c.label[i] = root_label[r];
    ++c.sizes[c.label[i]];
  }
  return c;
}

std::vector<int> edge_face_counts(const Faces& F, const Edges& E) {
  std::vector<int> count(E.rows(), 0);
  Adjacency adj = adjacency(F.rows() ? F.maxCoeff() + 1 : 0, E);
  for (Index f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      int a = std::min(F(f, k), F(f, (k + 1) % 3)), b = std::max(F(f, k), F(f, (k + 1) % 3));
      if (a == b) continue;
      auto first = adj.neighbors.begin() + adj.offsets[a], last = adj.neighbors.begin() + adj.offsets[a + 1];
      auto it = std::lower_bound(first, last, b);
      ++count[adj.edge_ids[it - adj.neighbors.begin()]];
    }
  }
  return count;
}

double surface_area(const Points& V, const Faces& F) {
  double area = 0;
  for (Index f = 0; f < F.rows(); ++f) {
    Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    area += 0.5 * (b - a).cross(c - a).norm();
  }
  return area;
}

double even_triangulation_vertices(const Points& V, const Faces& F) {
  const Edges E = mesh_edges(F);
  if (E.rows() == 0) return 0;
  const double mean_edge = edge_lengths(V, E).mean(), area = surface_area(V, F);
  if (!(mean_edge > 0) || !(area > 0)) return 0;
  return area / (0.5 * std::sqrt(3.0) * mean_edge * mean_edge);
}

namespace {

// The length of a box's diagonal: norm() where its squares stay within the range of a double (the same bits
// as always there), stableNorm() where they underflow or overflow (a box of 1e-300 or 1e300).
double diagonal_length(const Eigen::RowVector3d& extent) {
  const double plain = extent.norm();
  return plain > 0 && std::isfinite(plain) ? plain : extent.stableNorm();
}

}  // namespace

double bbox_diagonal(const Points& V) {
  if (V.rows() == 0) return 0;
  return diagonal_length(V.colwise().maxCoeff() - V.colwise().minCoeff());
}

double finite_bbox_diagonal(const Points& V) {
  Eigen::RowVector3d lo = Eigen::RowVector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::RowVector3d hi = -lo;
  bool any = false;
  for (Index i = 0; i < V.rows(); ++i) {
    if (!V.row(i).allFinite()) continue;
    lo = lo.cwiseMin(V.row(i));
    hi = hi.cwiseMax(V.row(i));
    any = true;
  }
  return any ? diagonal_length(hi - lo) : 0.0;
}

MeshInfo mesh_info(const Mesh& mesh) {
  MeshInfo info;
  info.vertices = mesh.num_vertices();
  info.faces = mesh.num_faces();
  Edges E = mesh_edges(mesh.F);
  info.edges = E.rows();
  Components comp = connected_components(mesh.num_vertices(), E);
  info.components = comp.count;
  Adjacency adj = adjacency(mesh.num_vertices(), E);
  for (Index i = 0; i < mesh.num_vertices(); ++i) info.isolated_vertices += adj.degree(i) == 0;
  info.euler_characteristic = static_cast<long>(info.vertices) - info.edges + info.faces;
  info.bbox_diagonal = bbox_diagonal(mesh.V);
  info.area = surface_area(mesh.V, mesh.F);
  if (E.rows() > 0) info.mean_edge_length = edge_lengths(mesh.V, E).mean();

  // Boundaries and non-manifold edges as mesh/mesh_defects.h defines them (a duplicate face is a duplicate,
  // not two faces making its edges non-manifold).
  const MeshDefects defects = mesh_defects(mesh);
  info.boundary_edges = defects.boundary_edges;
  info.boundary_loops = defects.boundary_loops;
  info.nonmanifold_edges = defects.nonmanifold_edges;

  if (mesh.is_point_cloud() || info.nonmanifold_edges > 0 || defects.nonmanifold_vertices > 0 ||
      defects.duplicate_faces > 0 || defects.repeated_vertex_faces > 0) {
    info.genus = -1;
  } else {
    // chi = sum_c (2 - 2 g_c - b_c) over surface components (isolated vertices contribute chi = 1 each and
    // are not surfaces, so they are taken out first).
    long surfaces = info.components - static_cast<long>(info.isolated_vertices);
    long chi = info.euler_characteristic - static_cast<long>(info.isolated_vertices);
    info.genus = (2 * surfaces - chi - info.boundary_loops) / 2;
  }
  return info;
}

Submesh extract_component(const Mesh& mesh, const Components& components, int label) {
  Submesh sub;
  std::vector<int> new_index(mesh.num_vertices(), -1);
  for (Index i = 0; i < mesh.num_vertices(); ++i) {
    if (components.label[i] == label) {
      new_index[i] = static_cast<int>(sub.vertex_map.size());
      sub.vertex_map.push_back(static_cast<int>(i));
    }
  }
  sub.mesh.V.resize(sub.vertex_map.size(), 3);
  for (size_t k = 0; k < sub.vertex_map.size(); ++k) sub.mesh.V.row(k) = mesh.V.row(sub.vertex_map[k]);
  std::vector<int> kept;
  for (Index f = 0; f < mesh.num_faces(); ++f)
    if (components.label[mesh.F(f, 0)] == label) kept.push_back(static_cast<int>(f));
  sub.mesh.F.resize(kept.size(), 3);
  for (size_t k = 0; k < kept.size(); ++k)
    for (int c = 0; c < 3; ++c) sub.mesh.F(k, c) = new_index[mesh.F(kept[k], c)];
  return sub;
}

Submesh require_connected(const Mesh& mesh, const std::string& name, bool keep_largest, std::string* note) {
  Components comp = connected_components(mesh.num_vertices(), mesh_edges(mesh.F));
  if (comp.count == 1) {
    Submesh sub;
    sub.mesh = mesh;
    sub.vertex_map.resize(mesh.num_vertices());
    std::iota(sub.vertex_map.begin(), sub.vertex_map.end(), 0);
    return sub;
  }
  int largest = comp.largest();
  if (!keep_largest) {
    fail(name, ": the mesh has ", comp.count, " connected components (largest ", comp.sizes[largest], " of ",
         mesh.num_vertices(),
         " vertices); this stage needs one: keep the largest (mesh/mesh_repair.h; the CLI does unless --strict)");
  }
  Submesh sub = extract_component(mesh, comp, largest);
  if (note) {
    *note = detail::concat(name, ": kept the largest of ", comp.count, " components (",
                           sub.mesh.num_vertices(), " of ", mesh.num_vertices(), " vertices); dropped ",
                           mesh.num_vertices() - sub.mesh.num_vertices(), " vertices and ",
                           mesh.num_faces() - sub.mesh.num_faces(), " faces");
  }
  return sub;
}

Points vertex_normals(const Mesh& mesh) {
  Points N = Points::Zero(mesh.num_vertices(), 3);
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)), c = mesh.V.row(mesh.F(f, 2));
    Eigen::Vector3d n = (b - a).cross(c - a);  // length = 2 × area: area weighting for free
    for (int k = 0; k < 3; ++k) N.row(mesh.F(f, k)) += n.transpose();
  }
  for (Index i = 0; i < N.rows(); ++i) {
    double len = N.row(i).norm();
    if (len > 0) N.row(i) /= len;
  }
  return N;
}

}  // namespace cshapes
