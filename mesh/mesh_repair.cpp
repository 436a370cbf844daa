#include "cshapes/mesh/mesh_repair.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "cshapes/support/error.h"
#include "cshapes/support/progress.h"
#include "cshapes/mesh/mesh_defects.h"

namespace cshapes {

MeshRequirements MeshRequirements::edge_graph() {
  return MeshRequirements{};
}

MeshRequirements MeshRequirements::manifold_surface() {
  MeshRequirements r;
  r.manifold = true;
  r.no_degenerate_faces = true;
  return r;
}

namespace {

// Keeps the faces with keep[f] set.
Faces select_faces(const Faces& F, const std::vector<char>& keep) {
  Faces out(std::count(keep.begin(), keep.end(), 1), 3);
  Index k = 0;
  for (Index f = 0; f < F.rows(); ++f)
    if (keep[f]) out.row(k++) = F.row(f);
  return out;
}

// Keeps the vertices with keep[v] set (faces must use only those), renumbering in order; composes the map.
void select_vertices(Mesh& mesh, std::vector<int>& vertex_map, const std::vector<char>& keep) {
  std::vector<int> new_index(mesh.num_vertices(), -1);
  std::vector<int> map;
  for (Index v = 0; v < mesh.num_vertices(); ++v)
    if (keep[v]) {
      new_index[v] = static_cast<int>(map.size());
      map.push_back(vertex_map[v]);
    }
  Points V(map.size(), 3);
  for (Index v = 0; v < mesh.num_vertices(); ++v)
    if (keep[v]) V.row(new_index[v]) = mesh.V.row(v);
  for (Index f = 0; f < mesh.num_faces(); ++f)
    for (int c = 0; c < 3; ++c) mesh.F(f, c) = new_index[mesh.F(f, c)];
  mesh.V = std::move(V);
  vertex_map = std::move(map);
}

// Counts one kind of repair (nothing when count is 0).
void act(RepairedMesh& r, const std::string& what, Index count) {
  if (count > 0) r.actions.push_back({what, count});
}

// 1. Faces that are not triangles of the surface: repeating a vertex, repeating an earlier face, and (with
// no_degenerate_faces) of zero area.
void drop_bad_faces(RepairedMesh& r, const MeshRequirements& req) {
  Mesh& mesh = r.mesh;
  const Index m = mesh.num_faces();
  std::vector<char> keep(m, 1);
  // A face repeating an earlier one (its vertices in any order): the faces sorted by their sorted vertices,
  // every one after the first of a run of equals is a duplicate.
  std::vector<std::pair<std::array<int, 3>, Index>> by_vertices;
  by_vertices.reserve(static_cast<size_t>(m));
  for (Index f = 0; f < m; ++f) by_vertices.push_back({sorted_face(mesh.F, f), f});
  std::sort(by_vertices.begin(), by_vertices.end());
  std::vector<char> duplicate(m, 0);
  for (size_t k = 1; k < by_vertices.size(); ++k)
    if (by_vertices[k].first == by_vertices[k - 1].first) duplicate[by_vertices[k].second] = 1;
  Index repeated = 0, duplicates = 0, zero_area = 0;
  for (Index f = 0; f < m; ++f) {
    if (face_repeats_vertex(mesh.F, f)) {
      keep[f] = 0;
      ++repeated;
    } else if (duplicate[f]) {
      keep[f] = 0;
      ++duplicates;
    } else if (req.no_degenerate_faces && face_has_zero_area(mesh.V, mesh.F, f)) {
      keep[f] = 0;
      ++zero_area;
    }
  }
  act(r, "faces repeating a vertex dropped", repeated);
  act(r, "duplicate faces dropped", duplicates);
  act(r, "zero-area faces dropped", zero_area);
  if (repeated + duplicates + zero_area > 0) mesh.F = select_faces(mesh.F, keep);
}

// 2. Non-manifold vertices: one copy per fan (see the header); the first fan keeps the vertex.
void split_fans(RepairedMesh& r) {
  Mesh& mesh = r.mesh;
  CornerFans fans = corner_fans(mesh.num_vertices(), mesh.F);
  std::vector<int> first_copy(mesh.num_vertices(), -1);
  Index split = 0, added = 0;
  for (Index v = 0; v < mesh.num_vertices(); ++v)
    if (fans.fan_count[v] > 1) {
      first_copy[v] = static_cast<int>(mesh.num_vertices() + added);
      added += fans.fan_count[v] - 1;
      ++split;
    }
  if (split == 0) return;
  const Index n = mesh.num_vertices();
  Points V(n + added, 3);
  V.topRows(n) = mesh.V;
  r.vertex_map.resize(n + added);
  for (Index v = 0; v < n; ++v)
    for (int k = 1; k < fans.fan_count[v]; ++k) {
      V.row(first_copy[v] + k - 1) = mesh.V.row(v);
      r.vertex_map[first_copy[v] + k - 1] = r.vertex_map[v];
    }
  for (Index f = 0; f < mesh.num_faces(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int v = mesh.F(f, c), fan = fans.corner_fan[3 * f + c];
      if (fan > 0) mesh.F(f, c) = first_copy[v] + fan - 1;
    }
  mesh.V = std::move(V);
  act(r, "non-manifold vertices split into fans", split);
  act(r, "vertex copies added by splitting", added);
}

// 3. Vertices in no face.
void drop_isolated_vertices(RepairedMesh& r) {
  Mesh& mesh = r.mesh;
  std::vector<char> used(mesh.num_vertices(), 0);
  for (Index f = 0; f < mesh.num_faces(); ++f)
    for (int c = 0; c < 3; ++c) used[mesh.F(f, c)] = 1;
  const Index unused = mesh.num_vertices() - std::count(used.begin(), used.end(), 1);
  act(r, "isolated vertices dropped", unused);
  if (unused > 0) select_vertices(mesh, r.vertex_map, used);
}

// 4. All but the largest component.
void keep_largest_component(RepairedMesh& r) {
  Mesh& mesh = r.mesh;
  Components comp = connected_components(mesh.num_vertices(), mesh_edges(mesh.F));
  if (comp.count <= 1) return;
  const int largest = comp.largest();
  std::vector<char> keep(mesh.num_vertices());
  for (Index v = 0; v < mesh.num_vertices(); ++v) keep[v] = comp.label[v] == largest;
  std::vector<char> keep_face(mesh.num_faces());
  for (Index f = 0; f < mesh.num_faces(); ++f) keep_face[f] = keep[mesh.F(f, 0)];
  act(r, "smaller components dropped", comp.count - 1);
  act(r, "vertices of smaller components dropped", mesh.num_vertices() - comp.sizes[largest]);
  mesh.F = select_faces(mesh.F, keep_face);
  select_vertices(mesh, r.vertex_map, keep);
}

// The one-line account of what was repaired; refused under options.strict.
void describe_repair(RepairedMesh& r, const Mesh& input, const RepairOptions& options,
                     const std::string& purpose) {
  r.text = options.name + ": repaired" + purpose + ": ";
  for (size_t k = 0; k < r.actions.size(); ++k)
    r.text += detail::concat(k ? ", " : "", r.actions[k].what, " ", r.actions[k].count);
  const Index kept = static_cast<Index>(valid_input_vertices(r.vertex_map, input.num_vertices()).sum());
  r.text += detail::concat(" (", kept, " of ", input.num_vertices(), " input vertices kept, ",
                           r.mesh.num_vertices(), " vertices after repair)");
  if (options.strict) {
    std::string needs;
    for (size_t k = 0; k < r.actions.size(); ++k)
      needs += detail::concat(k ? ", " : "", r.actions[k].what, " ", r.actions[k].count);
    fail(options.name, ": refused (--strict)", purpose, ": the mesh has ", mesh_defects(input).summary(),
         "; a repair would have: ", needs, ". Drop --strict to repair it");
  }
}

}  // namespace

RepairedMesh repair_for(const Mesh& input, const MeshRequirements& req, const RepairOptions& options) {
  RepairedMesh r;
  r.mesh = input;
  r.input_vertices = input.num_vertices();
  r.vertex_map.resize(input.num_vertices());
  for (Index v = 0; v < input.num_vertices(); ++v) r.vertex_map[v] = static_cast<int>(v);
  if (!input.is_point_cloud()) {
    // A stop is heard between the passes: each takes about a second at a million faces.
    report_progress_in_parallel(options.progress, "", 0, 0);
    drop_bad_faces(r, req);
    report_progress_in_parallel(options.progress, "", 0, 0);
    if (req.manifold) split_fans(r);
    report_progress_in_parallel(options.progress, "", 0, 0);
    drop_isolated_vertices(r);
    if (req.single_component && r.mesh.num_vertices() > 0) keep_largest_component(r);
    report_progress_in_parallel(options.progress, "", 0, 0);
  }
  const std::string purpose = options.purpose.empty() ? "" : " for " + options.purpose;
  if (r.changed()) describe_repair(r, input, options, purpose);
  if (r.mesh.num_vertices() < req.min_vertices)
    fail(options.name, ": only ", r.mesh.num_vertices(), " vertices left", purpose,
         r.changed() ? " after repair" : "", " (of ", input.num_vertices(), "), at least ", req.min_vertices,
         " needed");
  return r;
}

Points to_input_vertices(const Points& X, const std::vector<int>& vertex_map, Index input_vertices) {
  CSHAPES_REQUIRE(X.rows() == static_cast<Index>(vertex_map.size()), "to_input_vertices: ", X.rows(),
                  " rows for ", vertex_map.size(), " mapped vertices");
  Points out = Points::Constant(input_vertices, 3, std::numeric_limits<double>::quiet_NaN());
  std::vector<char> done(input_vertices, 0);
  for (size_t k = 0; k < vertex_map.size(); ++k)
    if (!done[vertex_map[k]]) {
      out.row(vertex_map[k]) = X.row(k);
      done[vertex_map[k]] = 1;
    }
  return out;
}

Eigen::VectorXd to_input_vertices(const Eigen::VectorXd& values, const std::vector<int>& vertex_map,
                                  Index input_vertices, double fill) {
  CSHAPES_REQUIRE(values.size() == static_cast<Index>(vertex_map.size()),
                  "to_input_vertices: ", values.size(), " values for ", vertex_map.size(),
                  " mapped vertices");
  Eigen::VectorXd out = Eigen::VectorXd::Constant(input_vertices, fill);
  std::vector<char> done(input_vertices, 0);
  for (size_t k = 0; k < vertex_map.size(); ++k)
    if (!done[vertex_map[k]]) {
      out[vertex_map[k]] = values[k];
      done[vertex_map[k]] = 1;
    }
  return out;
}

Eigen::VectorXd valid_input_vertices(const std::vector<int>& vertex_map, Index input_vertices) {
  Eigen::VectorXd valid = Eigen::VectorXd::Zero(input_vertices);
  for (int v : vertex_map) valid[v] = 1;
  return valid;
}

std::vector<int> repaired_copies(const std::vector<int>& vertex_map, int v) {
  std::vector<int> copies;
  for (size_t k = 0; k < vertex_map.size(); ++k)
    if (vertex_map[k] == v) copies.push_back(static_cast<int>(k));
  return copies;
}

Eigen::VectorXd distances_to_input_vertices(const Eigen::VectorXd& d, const std::vector<int>& vertex_map,
                                            Index input_vertices) {
  CSHAPES_REQUIRE(d.size() == static_cast<Index>(vertex_map.size()), "distances_to_input_vertices: ",
                  d.size(), " values for ", vertex_map.size(), " mapped vertices");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXd out = Eigen::VectorXd::Constant(input_vertices, nan);
  for (size_t k = 0; k < vertex_map.size(); ++k) {
    double& o = out[vertex_map[k]];
    o = std::isnan(o) ? d[k] : std::min(o, d[k]);
  }
  return out;
}

DistanceMatrix distances_to_input_vertices(const DistanceMatrix& D, const std::vector<int>& vertex_map,
                                           Index input_vertices) {
  CSHAPES_REQUIRE(D.rows() == static_cast<Index>(vertex_map.size()) && D.cols() == D.rows(),
                  "distances_to_input_vertices: a ", D.rows(), "x", D.cols(), " matrix for ",
                  vertex_map.size(), " mapped vertices");
  const float nan = std::numeric_limits<float>::quiet_NaN();
  DistanceMatrix out = uninitialized_distance_matrix(input_vertices, input_vertices);
  out.setConstant(nan);
  const Index m = D.rows();
  for (Index b = 0; b < m; ++b)
    for (Index a = 0; a < m; ++a) {
      float& o = out(vertex_map[a], vertex_map[b]);
      o = std::isnan(o) ? D(a, b) : std::min(o, D(a, b));
    }
  return out;
}

}  // namespace cshapes
