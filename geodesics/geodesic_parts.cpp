#include "cshapes/geodesics/geodesic_parts.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cshapes/support/error.h"
#include "cshapes/mesh/mesh_repair.h"

namespace cshapes {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Topological persistence of the local maxima of d (superlevel sets, union-find over the vertices in
// decreasing d): a maximum is born at its value and dies where its region first joins a region with a higher
// maximum; persistence = birth − death. The tip of a limb dies where the limb meets the body (about the
// limb's length), a bump on the surface almost at once. The global maximum never dies: its persistence is
// its value. Per vertex: the persistence of the maximum it is, −1 for a vertex that is no maximum.
Eigen::VectorXd maxima_persistence(const Adjacency& adj, const Eigen::VectorXd& d) {
  const Index n = d.size();
  std::vector<int> order;
  for (Index v = 0; v < n; ++v)
    if (std::isfinite(d[v])) order.push_back(static_cast<int>(v));
  std::sort(order.begin(), order.end(), [&](int a, int b) { return d[a] > d[b] || (d[a] == d[b] && a < b); });
  std::vector<int> parent(static_cast<size_t>(n), -1);  // −1: not yet reached
  std::vector<int> peak(static_cast<size_t>(n), -1);    // per root: its region's maximum
  Eigen::VectorXd persistence = Eigen::VectorXd::Constant(n, -1.0);
  for (int v : order) {
    parent[v] = v;
    peak[v] = v;
    for (int k = adj.offsets[v]; k < adj.offsets[v + 1]; ++k) {
      const int u = adj.neighbors[k];
      if (parent[u] < 0) continue;
      const int ru = union_find_root(parent, u), rv = union_find_root(parent, v);
      if (ru == rv) continue;
      // The lower peak dies here; the region keeps the higher one.
      const bool u_higher = d[peak[ru]] > d[peak[rv]] || (d[peak[ru]] == d[peak[rv]] && peak[ru] < peak[rv]);
      const int survivor = u_higher ? ru : rv, dying = u_higher ? rv : ru;
      if (peak[dying] != v) persistence[peak[dying]] = d[peak[dying]] - d[v];
      parent[dying] = survivor;
    }
    if (peak[union_find_root(parent, v)] == v && persistence[v] < 0) persistence[v] = 0;  // a maximum so far
  }
  // Maxima still alive at the end: the global one of each component.
  for (int v : order)
    if (parent[v] == v) persistence[peak[v]] = d[peak[v]];
  return persistence;
}

}  // namespace

GeodesicPartsResult geodesic_parts(const Mesh& mesh, const GeodesicPartsOptions& o) {
  CSHAPES_REQUIRE(!mesh.is_point_cloud(), "geodesic_parts: the mesh has no faces");
  CSHAPES_REQUIRE(
      o.centre_sources >= 1 && o.max_extremities >= 1 && o.part_fraction > 0 && o.min_persistence > 0,
      "geodesic_parts: centre_sources and max_extremities must be ≥ 1, part_fraction and "
      "min_persistence > 0");
  RepairOptions ro;
  ro.name = "mesh";
  ro.purpose = "the part finder's geodesics";
  const RepairedMesh repaired = repair_for(mesh, MeshRequirements::manifold_surface(), ro);
  const Mesh& m = repaired.mesh;
  const Index n = m.num_vertices();
  CSHAPES_REQUIRE(n >= 4, "geodesic_parts: ", n, " vertices left after the repair (need 4)");

  // 1. The centre: least summed distance to evenly spaced sources.
  const int sources = static_cast<int>(std::min<Index>(o.centre_sources, n));
  Eigen::VectorXd summed = Eigen::VectorXd::Zero(n);
  for (int s = 0; s < sources; ++s) {
    const int source = static_cast<int>(static_cast<Index>(s) * n / sources);
    summed += geodesic_distances(m, {source}, o.geodesics);
  }
  Index centre = 0;
  summed.minCoeff(&centre);
  const Eigen::VectorXd d_centre = geodesic_distances(m, {static_cast<int>(centre)}, o.geodesics);
  double reach = 0;
  for (Index v = 0; v < n; ++v)
    if (std::isfinite(d_centre[v])) reach = std::max(reach, d_centre[v]);
  CSHAPES_REQUIRE(reach > 0, "geodesic_parts: every vertex is at distance 0 from the centre");

  // 2. Extremities: the local maxima of d_c that persist (the tips of protrusions), farthest first.
  const Eigen::VectorXd persistence = maxima_persistence(adjacency(n, mesh_edges(m.F)), d_centre);
  std::vector<int> extremities;
  for (Index v = 0; v < n; ++v)
    if (persistence[v] >= o.min_persistence * reach) extremities.push_back(static_cast<int>(v));
  // The most persistent when there are too many, then farthest from the centre first.
  std::sort(extremities.begin(), extremities.end(), [&](int a, int b) {
    return persistence[a] > persistence[b] || (persistence[a] == persistence[b] && a < b);
  });
  if (static_cast<int>(extremities.size()) > o.max_extremities) extremities.resize(o.max_extremities);
  std::sort(extremities.begin(), extremities.end(),
            [&](int a, int b) { return d_centre[a] > d_centre[b] || (d_centre[a] == d_centre[b] && a < b); });
  double refused = 0;  // the most persistent maximum left out
  for (Index v = 0; v < n; ++v)
    if (persistence[v] >= 0 && std::find(extremities.begin(), extremities.end(), v) == extremities.end())
      refused = std::max(refused, persistence[v] / reach);
  std::vector<Eigen::VectorXd> d_extremity;
  for (int e : extremities) d_extremity.push_back(geodesic_distances(m, {e}, o.geodesics));

  // 3. Parts: the nearest extremity's, within part_fraction of its distance to the centre.
  Eigen::VectorXi part = Eigen::VectorXi::Zero(n);
  for (Index v = 0; v < n; ++v) {
    int closest = -1;
    double closest_distance = kInfinity;
    for (size_t e = 0; e < extremities.size(); ++e)
      if (d_extremity[e][v] < closest_distance) {
        closest_distance = d_extremity[e][v];
        closest = static_cast<int>(e);
      }
    if (closest >= 0 && closest_distance < o.part_fraction * d_centre[extremities[closest]])
      part[v] = closest + 1;
  }

  GeodesicPartsResult r;
  r.repair_text = repaired.text;
  r.centre = repaired.vertex_map[static_cast<size_t>(centre)];
  for (int e : extremities) {
    r.extremities.push_back(repaired.vertex_map[static_cast<size_t>(e)]);
    r.extremity_reach.push_back(d_centre[e] / reach);
    r.extremity_persistence.push_back(persistence[e] / reach);
  }
  r.refused_persistence = refused;
  r.centre_distance = to_input_vertices(d_centre, repaired.vertex_map, mesh.num_vertices(), kInfinity);
  r.part = Eigen::VectorXi::Constant(mesh.num_vertices(), -1);
  // A split vertex takes its first copy's part, as to_input_vertices does.
  for (Index k = n - 1; k >= 0; --k) r.part[repaired.vertex_map[static_cast<size_t>(k)]] = part[k];
  return r;
}

}  // namespace cshapes
