#include "cshapes/data/topological_noise.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <queue>
#include <set>
#include <unordered_map>

#include "cshapes/support/format.h"
#include "cshapes/support/deterministic_random.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"

namespace cshapes {

namespace {

struct Candidate {
  int a, b;
  double euclidean;
  double lower_bound;  // landmark lower bound of the geodesic distance
  double score;        // smaller first
  bool rejected = false;
  double spot_distance = std::numeric_limits<double>::infinity();  // geodesic distance to glued spots
};

// Segment pq against triangle abc (Möller-Trumbore); true when they cross in the segment's interior.
bool segment_hits_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& a,
                           const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d dir = q - p, e1 = b - a, e2 = c - a;
  const Eigen::Vector3d h = dir.cross(e2);
  const double det = e1.dot(h);
  if (std::abs(det) < 1e-300) return false;
  const Eigen::Vector3d s = p - a;
  const double u = s.dot(h) / det;
  if (u < 0 || u > 1) return false;
  const Eigen::Vector3d qv = s.cross(e1);
  const double v = dir.dot(qv) / det;
  if (v < 0 || u + v > 1) return false;
  const double t = e2.dot(qv) / det;
  return t > 0 && t < 1;
}

// The mesh being glued: faces with a removal flag, and vertex-to-face incidence.
struct WorkingMesh {
  const Points& V;
  std::vector<Eigen::Vector3i> faces;
  std::vector<bool> removed;
  std::vector<std::vector<int>> vertex_faces;

  WorkingMesh(const Mesh& mesh) : V(mesh.V), vertex_faces(mesh.num_vertices()) {
    for (Index f = 0; f < mesh.num_faces(); ++f) add(mesh.F.row(f).transpose());
  }
  void add(const Eigen::Vector3i& face) {
    int id = static_cast<int>(faces.size());
    faces.push_back(face);
    removed.push_back(false);
    for (int k = 0; k < 3; ++k) vertex_faces[face[k]].push_back(id);
  }
  void remove(int f) { removed[f] = true; }
  Mesh to_mesh() const {
    Mesh m;
    m.V = V;
    Index count = std::count(removed.begin(), removed.end(), false);
    m.F.resize(count, 3);
    Index row = 0;
    for (size_t f = 0; f < faces.size(); ++f)
      if (!removed[f]) m.F.row(row++) = faces[f].transpose();
    return m;
  }
  bool has_edge(int i, int j) const {
    for (int f : vertex_faces[i])
      if (!removed[f] && (faces[f][0] == j || faces[f][1] == j || faces[f][2] == j)) return true;
    return false;
  }
  Eigen::Vector3d centroid(int f) const {
    return (V.row(faces[f][0]) + V.row(faces[f][1]) + V.row(faces[f][2])).transpose() / 3.0;
  }
};

// The 6 tube triangles bridging faces fa = (a0, a1, a2) and fb = (b0, b1, b2), both given in their mesh
// order. New faces must use each rim edge in the direction the removed face used it (the neighbours use the
// reverse). With c_j = b_{(s - j) mod 3}, a walk around the tube adds (a_i, a_{i+1}, c_j) or (a_i, c_{j+1},
// c_j); every offset s and interleaving is tried and the one with the shortest new edges is kept.
std::vector<Eigen::Vector3i> bridge(const Points& V, const Eigen::Vector3i& fa, const Eigen::Vector3i& fb,
                                    std::vector<std::pair<int, int>>* new_edges) {
  double best = std::numeric_limits<double>::infinity();
  std::vector<Eigen::Vector3i> best_faces;
  std::vector<std::pair<int, int>> best_edges;
  auto dist = [&](int i, int j) { return (V.row(i) - V.row(j)).norm(); };
  for (int s = 0; s < 3; ++s) {
    auto c = [&](int j) { return fb[((s - j) % 3 + 3) % 3]; };
    auto a = [&](int i) { return fa[i % 3]; };
    for (int moves = 0; moves < 64; ++moves) {
      if (__builtin_popcount(moves) != 3) continue;
      int i = 0, j = 0;
      double cost = dist(a(0), c(0));
      std::vector<Eigen::Vector3i> tris;
      std::vector<std::pair<int, int>> edges = {{a(0), c(0)}};
      for (int step = 0; step < 6; ++step) {
        if (moves >> step & 1) {
          tris.emplace_back(a(i), a(i + 1), c(j));
          ++i;
        } else {
          tris.emplace_back(a(i), c(j + 1), c(j));
          ++j;
        }
        if (step < 5) {
          cost += dist(a(i), c(j));
          edges.emplace_back(a(i), c(j));
        }
      }
      // A walk that goes once round one rim before the other (e.g. three A moves first) comes back to an edge
      // it already made: the tube would pinch there. Every new edge must be new.
      std::set<std::pair<int, int>> distinct(edges.begin(), edges.end());
      if (distinct.size() != edges.size()) continue;
      if (cost < best) {
        best = cost;
        best_faces = tris;
        best_edges = edges;
      }
    }
  }
  *new_edges = best_edges;
  return best_faces;
}

}  // namespace

namespace {
TopologicalNoiseResult glue_once(const Mesh& mesh, const TopologicalNoiseOptions& o);
}  // namespace

TopologicalNoiseResult glue_topological_noise(const Mesh& mesh, const TopologicalNoiseOptions& options) {
  check_limit(noise_limits::kRelax, options.relax_steps, "noise");
  check_limit(noise_limits::kGlue, options.glue_count, "noise");
  check_limit(noise_limits::kMaxGap, options.max_gap, "noise");
  check_limit(noise_limits::kGapEdges, options.gap_edge_lengths, "noise");
  check_limit(noise_limits::kMinRatio, options.min_ratio, "noise");
  check_limit(noise_limits::kMinFraction, options.min_geodesic_fraction, "noise");
  check_limit(noise_limits::kSeparation, options.min_separation_fraction, "noise");
  TopologicalNoiseOptions o = options;
  for (int step = 0;; ++step) {
    try {
      TopologicalNoiseResult r = glue_once(mesh, o);
      r.min_ratio = o.min_ratio;
      r.relax_steps_used = step;
      return r;
    } catch (const Error&) {
      if (step >= options.relax_steps) throw;
      if (o.max_gap > 0) o.max_gap *= 1.5;
      o.gap_edge_lengths *= 1.5;
      o.min_ratio = std::max(2.0, 0.8 * o.min_ratio);
    }
  }
}

namespace {

// Landmarks by farthest-point sampling from vertex 0: their distance fields (lower bounds |d_L(a) − d_L(b)| ≤
// g(a, b)) and the largest distance seen, the diameter estimate.
std::vector<Eigen::VectorXd> landmark_fields(const Mesh& mesh, const TopologicalNoiseOptions& o,
                                             double* diameter) {
  std::vector<Eigen::VectorXd> fields;
  Eigen::VectorXd nearest = geodesic_distances(mesh, {0}, o.geodesic);
  for (int l = 0; l < std::max(2, o.landmarks); ++l) {
    Index far;
    nearest.maxCoeff(&far);
    Eigen::VectorXd field = geodesic_distances(mesh, {static_cast<int>(far)}, o.geodesic);
    *diameter = std::max(*diameter, field.maxCoeff());
    nearest = nearest.cwiseMin(field);
    fields.push_back(std::move(field));
  }
  return fields;
}

// Outward vertex normals: a closed mesh with inward-facing triangles (negative signed volume, divergence
// theorem) has its normals turned round, since "facing" across a gap needs outward ones.
Points outward_normals(const Mesh& mesh, const MeshInfo& info) {
  Points normals = vertex_normals(mesh);
  if (info.boundary_edges == 0) {
    double volume = 0;
    for (Index f = 0; f < mesh.num_faces(); ++f)
      volume += mesh.V.row(mesh.F(f, 0)).dot(mesh.V.row(mesh.F(f, 1)).cross(mesh.V.row(mesh.F(f, 2))));
    if (volume < 0) normals = -normals;
  }
  return normals;
}

// Candidate pairs: within the gap (sweep along x), normals facing each other across the gap, with their
// landmark lower bounds; sorted by (a, b), then scored with the seeded random draw.
std::vector<Candidate> facing_pairs(const Mesh& mesh, const Points& normals,
                                    const std::vector<Eigen::VectorXd>& fields, double gap,
                                    const TopologicalNoiseOptions& o) {
  const Index n = mesh.num_vertices();
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int i, int j) {
    return mesh.V(i, 0) < mesh.V(j, 0) || (mesh.V(i, 0) == mesh.V(j, 0) && i < j);
  });
  DeterministicRandom rng(o.seed);
  std::vector<Candidate> candidates;
  for (Index p = 0; p < n; ++p) {
    const int i = order[p];
    for (Index q = p + 1; q < n && mesh.V(order[q], 0) - mesh.V(i, 0) <= gap; ++q) {
      const int j = order[q];
      const Eigen::Vector3d d = (mesh.V.row(j) - mesh.V.row(i)).transpose();
      const double len = d.norm();
      if (len > gap || len <= 0) continue;
      if (normals.row(i).dot(d) < o.min_facing * len || -normals.row(j).dot(d) < o.min_facing * len) continue;
      double lower = 0;
      for (const auto& field : fields) lower = std::max(lower, std::abs(field[i] - field[j]));
      candidates.push_back({std::min(i, j), std::max(i, j), len, lower, 0});
    }
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate& x, const Candidate& y) { return x.a < y.a || (x.a == y.a && x.b < y.b); });
  for (auto& c : candidates) c.score = c.euclidean / gap + 0.5 * rng.uniform();
  return candidates;
}

// Cheap rejection: the edge-graph distance is an upper bound of the surface geodesic, so a pair that the
// graph joins by a path shorter than its threshold cannot qualify. One Dijkstra per distinct first vertex,
// stopped at the largest threshold among its pairs, run lazily when the selection first reaches that
// vertex (run(a)). Valid after gluing too: tubes only shorten distances.
class GraphPrefilter {
 public:
  using Threshold = std::function<double(const Candidate&)>;
  GraphPrefilter(const Mesh& mesh, std::vector<Candidate>& candidates, Threshold threshold)
      : candidates_(candidates),
        threshold_(std::move(threshold)),
        edges_(mesh_edges(mesh.F)),
        graph_(adjacency(mesh.num_vertices(), edges_)),
        lengths_(edge_lengths(mesh.V, edges_)),
        by_source_(mesh.num_vertices()),
        filtered_(mesh.num_vertices(), false),
        ball_(mesh.num_vertices(), std::numeric_limits<double>::infinity()),
        is_target_(mesh.num_vertices(), false) {
    for (size_t k = 0; k < candidates.size(); ++k) by_source_[candidates[k].a].push_back(static_cast<int>(k));
  }

  // Rejects the pairs of first vertex a that the graph joins within their threshold (once per vertex).
  void run(int a) {
    if (filtered_[a]) return;
    filtered_[a] = true;
    const double inf = std::numeric_limits<double>::infinity();
    double radius = 0;
    for (int k : by_source_[a]) radius = std::max(radius, threshold_(candidates_[k]));
    // Stop as soon as every partner is settled: near partners (the common, inadmissible case) end it early.
    for (int k : by_source_[a]) is_target_[candidates_[k].b] = true;
    size_t remaining = by_source_[a].size();
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    ball_[a] = 0;
    touched_.push_back(a);
    queue.emplace(0.0, a);
    while (!queue.empty() && remaining > 0) {
      auto [d, i] = queue.top();
      queue.pop();
      if (d > ball_[i]) continue;
      if (d >= radius) break;
      if (is_target_[i]) {
        is_target_[i] = false;
        --remaining;
      }
      for (int k = graph_.offsets[i]; k < graph_.offsets[i + 1]; ++k) {
        int j = graph_.neighbors[k];
        double nd = d + lengths_[graph_.edge_ids[k]];
        if (nd < ball_[j]) {
          if (ball_[j] == inf) touched_.push_back(j);
          ball_[j] = nd;
          queue.emplace(nd, j);
        }
      }
    }
    for (int k : by_source_[a])
      if (ball_[candidates_[k].b] < threshold_(candidates_[k])) candidates_[k].rejected = true;
    for (int i : touched_) ball_[i] = inf;
    for (int k : by_source_[a]) is_target_[candidates_[k].b] = false;
    touched_.clear();
  }

 private:
  std::vector<Candidate>& candidates_;
  Threshold threshold_;
  Edges edges_;
  Adjacency graph_;
  Eigen::VectorXd lengths_;
  std::vector<std::vector<int>> by_source_;
  std::vector<bool> filtered_;
  std::vector<double> ball_;
  std::vector<int> touched_;
  std::vector<bool> is_target_;
};

// The triangles at the two ends of pair (a, b): the pair of faces, one incident to each, whose centroids are
// closest; false when one end has none left.
bool closest_end_faces(const WorkingMesh& work, int a, int b, int* best_fa, int* best_fb) {
  *best_fa = *best_fb = -1;
  double best_d = std::numeric_limits<double>::infinity();
  for (int fa : work.vertex_faces[a]) {
    if (work.removed[fa]) continue;
    for (int fb : work.vertex_faces[b]) {
      if (work.removed[fb]) continue;
      double d = (work.centroid(fa) - work.centroid(fb)).norm();
      if (d < best_d) best_d = d, *best_fa = fa, *best_fb = fb;
    }
  }
  return *best_fa >= 0;
}

// Whether the tube's new edges or its axis (centroid of face_a to centroid of face_b) pass through a face of
// the surface other than those at its ends.
bool tube_crosses_surface(const Points& V, const WorkingMesh& work, int face_a, int face_b,
                          const std::vector<std::pair<int, int>>& new_edges) {
  const Eigen::Vector3i fa = work.faces[face_a], fb = work.faces[face_b];
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> segments;
  for (auto [x, y] : new_edges) segments.emplace_back(V.row(x), V.row(y));
  segments.emplace_back(work.centroid(face_a), work.centroid(face_b));
  std::set<int> ends = {fa[0], fa[1], fa[2], fb[0], fb[1], fb[2]};
  Eigen::AlignedBox3d box;
  for (const auto& [p, q] : segments) box.extend(p), box.extend(q);
  for (size_t f = 0; f < work.faces.size(); ++f) {
    if (work.removed[f]) continue;
    const Eigen::Vector3i& t = work.faces[f];
    Eigen::AlignedBox3d face_box(Eigen::Vector3d(V.row(t[0])));
    face_box.extend(Eigen::Vector3d(V.row(t[1]))).extend(Eigen::Vector3d(V.row(t[2])));
    if (!box.intersects(face_box)) continue;
    if (ends.count(t[0]) || ends.count(t[1]) || ends.count(t[2])) continue;
    for (const auto& [p, q] : segments)
      if (segment_hits_triangle(p, q, V.row(t[0]), V.row(t[1]), V.row(t[2]))) return true;
  }
  return false;
}

// Whether the two end faces share a corner or are joined by an edge: a tube between them would pinch.
bool rims_touch(const WorkingMesh& work, const Eigen::Vector3i& fa, const Eigen::Vector3i& fb) {
  for (int x = 0; x < 3; ++x)
    for (int y = 0; y < 3; ++y)
      if (fa[x] == fb[y] || work.has_edge(fa[x], fb[y])) return true;
  return false;
}

// The construction guarantees these; checked anyway, the output is meant as a test input for others: one
// component, manifold, the input's boundary, χ lower by 2 per glue.
void check_glued(const Mesh& glued, const MeshInfo& input, int glue_count) {
  MeshInfo out = mesh_info(glued);
  CSHAPES_REQUIRE(
      out.components == 1 && out.nonmanifold_edges == 0 && out.boundary_edges == input.boundary_edges &&
          out.euler_characteristic == input.euler_characteristic - 2 * glue_count,
      "noise: internal error, the glued mesh is not as constructed (chi ", out.euler_characteristic,
      ", components ", out.components, ", non-manifold edges ", out.nonmanifold_edges, ")");
}

GluedPair glued_pair(const Candidate& c, const Eigen::Vector3i& fa, const Eigen::Vector3i& fb, double geodesic) {
  GluedPair pair;
  pair.a = c.a;
  pair.b = c.b;
  pair.rim_a = {fa[0], fa[1], fa[2]};
  pair.rim_b = {fb[0], fb[1], fb[2]};
  pair.euclidean = c.euclidean;
  pair.geodesic = geodesic;
  return pair;
}

TopologicalNoiseResult glue_once(const Mesh& mesh, const TopologicalNoiseOptions& o) {
  CSHAPES_REQUIRE(!mesh.is_point_cloud(), "noise: the input has no faces");
  validate_mesh(mesh, "noise input");
  const MeshInfo info = mesh_info(mesh);
  CSHAPES_REQUIRE(info.components == 1, "noise: the input must have one connected component, it has ",
                  info.components, " (glue within one component: extract it first)");

  TopologicalNoiseResult result;
  result.mean_edge_length = info.mean_edge_length;
  result.max_gap = o.max_gap > 0 ? o.max_gap : o.gap_edge_lengths * info.mean_edge_length;
  const double gap = result.max_gap;
  const std::vector<Eigen::VectorXd> fields = landmark_fields(mesh, o, &result.geodesic_diameter);
  const double diameter = result.geodesic_diameter;

  std::vector<Candidate> candidates = facing_pairs(mesh, outward_normals(mesh, info), fields, gap, o);
  auto threshold = [&](const Candidate& c) {
    return std::max(o.min_ratio * c.euclidean, o.min_geodesic_fraction * diameter);
  };
  // Pairs certainly far apart (by the landmark bound) first, then the rest; each group by score.
  std::stable_sort(candidates.begin(), candidates.end(), [&](const Candidate& x, const Candidate& y) {
    bool sx = x.lower_bound >= threshold(x), sy = y.lower_bound >= threshold(y);
    if (sx != sy) return sx;
    return x.score < y.score;
  });
  result.candidates = static_cast<Index>(candidates.size());
  GraphPrefilter prefilter(mesh, candidates, threshold);

  WorkingMesh work(mesh);
  Mesh current = mesh;
  std::unordered_map<int, Eigen::VectorXd> field_cache;  // source -> distances on `current`
  double separation = o.min_separation_fraction * diameter;
  const double min_separation = 2 * gap;

  while (static_cast<int>(result.pairs.size()) < o.glue_count) {
    bool glued = false;
    for (auto& c : candidates) {
      if (c.rejected || c.spot_distance < separation) continue;
      if (result.geodesic_checks >= o.max_checks) break;
      prefilter.run(c.a);
      if (c.rejected) continue;
      int best_fa, best_fb;
      if (!closest_end_faces(work, c.a, c.b, &best_fa, &best_fb)) {
        c.rejected = true;
        continue;
      }
      const Eigen::Vector3i fa = work.faces[best_fa], fb = work.faces[best_fb];
      if (rims_touch(work, fa, fb)) {
        c.rejected = true;
        continue;
      }
      std::vector<std::pair<int, int>> new_edges;
      std::vector<Eigen::Vector3i> tube_faces = bridge(mesh.V, fa, fb, &new_edges);
      // The geodesic test on the mesh as glued so far.
      auto it = field_cache.find(c.a);
      if (it == field_cache.end()) {
        ++result.geodesic_checks;
        it = field_cache.emplace(c.a, geodesic_distances(current, {c.a}, o.geodesic)).first;
      }
      const double g = it->second[c.b];
      if (!(g >= threshold(c)) || tube_crosses_surface(mesh.V, work, best_fa, best_fb, new_edges)) {
        c.rejected = true;
        continue;
      }
      // Glue: the tube replaces the two end faces; every candidate learns its distance to the new spots.
      result.pairs.push_back(glued_pair(c, fa, fb, g));
      work.remove(best_fa);
      work.remove(best_fb);
      for (const auto& t : tube_faces) work.add(t);
      current = work.to_mesh();
      field_cache.clear();
      c.rejected = true;
      Eigen::VectorXd spots = geodesic_distances(current, {c.a, c.b}, o.geodesic);
      for (auto& other : candidates)
        other.spot_distance = std::min(other.spot_distance, std::min(spots[other.a], spots[other.b]));
      glued = true;
      break;
    }
    if (glued) continue;
    if (separation > min_separation && result.geodesic_checks < o.max_checks) {
      separation = std::max(min_separation, separation / 2);
      continue;
    }
    fail("noise: found only ", result.pairs.size(), " of ", o.glue_count,
         " admissible pairs (Euclidean gap <= ", significant(gap), ", geodesic >= ", significant(o.min_ratio),
         " x gap and >= ", significant(o.min_geodesic_fraction), " x diameter ", significant(diameter),
         ", normals facing across the gap, tube crossing no face; ",
         counted(static_cast<long long>(candidates.size()), "pair"), " within the gap, ",
         counted(result.geodesic_checks, "geodesic check"), "); try a larger --max-gap or a smaller --min-ratio");
  }
  result.separation = separation;
  result.mesh = current;

  check_glued(result.mesh, info, o.glue_count);
  return result;
}
}  // namespace

Edges glue_bridges(const Points& V, const Edges& E, int count) {
  CSHAPES_REQUIRE(count >= 1, "glue_bridges: count must be >= 1, got ", count);
  const Index n = V.rows();
  const Eigen::VectorXd lengths = edge_lengths(V, E);
  const double h = lengths.mean();
  const Adjacency adj = adjacency(n, E);
  // Hop-limited BFS rejects the pairs that are near along the surface (most near pairs) cheaply.
  const int hops = 10;
  struct Pair {
    double distance;
    int i, j;
  };
  std::vector<Pair> pairs;
  std::vector<int> seen(n, -1);
  for (Index i = 0; i < n; ++i) {
    std::vector<int> frontier{static_cast<int>(i)};
    seen[i] = static_cast<int>(i);
    for (int hop = 0; hop < hops; ++hop) {
      std::vector<int> next;
      for (int v : frontier)
        for (int k = adj.offsets[v]; k < adj.offsets[v + 1]; ++k)
          if (seen[adj.neighbors[k]] != i) {
            seen[adj.neighbors[k]] = static_cast<int>(i);
            next.push_back(adj.neighbors[k]);
          }
      frontier.swap(next);
    }
    for (Index j = i + 1; j < n; ++j) {
      if (seen[j] == i) continue;
      const double d = (V.row(i) - V.row(j)).norm();
      if (d < 8 * h) pairs.push_back({d, static_cast<int>(i), static_cast<int>(j)});
    }
  }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) {
    return a.distance != b.distance ? a.distance < b.distance : (a.i != b.i ? a.i < b.i : a.j < b.j);
  });
  std::vector<Pair> chosen;
  std::vector<char> used(n, 0);
  for (const Pair& p : pairs) {
    if (static_cast<int>(chosen.size()) >= count) break;
    if (used[p.i] || used[p.j]) continue;
    if (!chosen.empty()) {
      // Same site as the first bridge: both ends near its ends.
      const Pair& f = chosen.front();
      if ((V.row(p.i) - V.row(f.i)).norm() > 8 * h && (V.row(p.i) - V.row(f.j)).norm() > 8 * h) continue;
      if ((V.row(p.j) - V.row(f.i)).norm() > 8 * h && (V.row(p.j) - V.row(f.j)).norm() > 8 * h) continue;
    }
    const Eigen::VectorXd graph = dijkstra(n, adj, lengths, {p.i});
    if (graph(p.j) < 15 * h) continue;
    chosen.push_back(p);
    used[p.i] = used[p.j] = 1;
  }
  CSHAPES_REQUIRE(!chosen.empty(),
                  "glue_bridges: found no vertex pair to glue (closer than 8 mean edges in space, "
                  "farther than 15 along the edges)");
  Edges bridges(static_cast<Index>(chosen.size()), 2);
  for (size_t k = 0; k < chosen.size(); ++k)
    bridges.row(static_cast<Index>(k)) << std::min(chosen[k].i, chosen[k].j),
        std::max(chosen[k].i, chosen[k].j);
  return bridges;
}

}  // namespace cshapes
