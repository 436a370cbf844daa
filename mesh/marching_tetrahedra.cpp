#include "cshapes/mesh/marching_tetrahedra.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>
#include <vector>

#include "cshapes/support/error.h"

namespace cshapes {

Mesh marching_tetrahedra(const std::function<double(const Eigen::Vector3d&)>& field,
                         const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                         const MarchingTetrahedraOptions& o) {
  CSHAPES_REQUIRE(o.cell_size > 0, "marching_tetrahedra: cell size must be positive, got ", o.cell_size);
  CSHAPES_REQUIRE((hi.array() > lo.array()).all(), "marching_tetrahedra: empty box");
  Eigen::Array3i count = (((hi - lo) / o.cell_size).array().ceil().cast<int>() + 1).max(2);
  const long total = static_cast<long>(count[0]) * count[1] * count[2];
  CSHAPES_REQUIRE(total <= 200'000'000L, "marching_tetrahedra: ", total,
                  " grid points are too many; raise the cell size");
  const long nx = count[0], ny = count[1], nz = count[2];
  auto point = [&](long i, long j, long k) {
    return Eigen::Vector3d(lo + o.cell_size * Eigen::Vector3d(i, j, k));
  };

  std::vector<double> value(total);
#pragma omp parallel for schedule(static)
  for (long k = 0; k < nz; ++k)
    for (long j = 0; j < ny; ++j)
      for (long i = 0; i < nx; ++i) {
        double v = field(point(i, j, k));
        value[i + nx * (j + ny * k)] = v == 0 ? 1e-300 : v;  // no vertex exactly on the surface
      }

  // Cube corners (bit 0: +x, bit 1: +y, bit 2: +z) and the Kuhn tetrahedra: the 6 monotone paths from corner
  // 0 to corner 7, each tetrahedron (0, a, a|b, 7).
  static const int kTets[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7},
                                  {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};
  std::vector<Eigen::Vector3d> verts;
  std::vector<Eigen::Vector3i> tris;
  std::unordered_map<std::uint64_t, int> edge_vertex;
  auto crossing = [&](long a, long b) {
    std::uint64_t key = static_cast<std::uint64_t>(std::min(a, b)) * static_cast<std::uint64_t>(total) +
                        static_cast<std::uint64_t>(std::max(a, b));
    auto it = edge_vertex.find(key);
    if (it != edge_vertex.end()) return it->second;
    auto pos = [&](long id) { return point(id % nx, (id / nx) % ny, id / (nx * ny)); };
    double t = value[a] / (value[a] - value[b]);
    t = std::clamp(t, o.min_edge_fraction, 1 - o.min_edge_fraction);
    verts.push_back((1 - t) * pos(a) + t * pos(b));
    int id = static_cast<int>(verts.size()) - 1;
    edge_vertex.emplace(key, id);
    return id;
  };
  auto emit = [&](int p, int q, int r, const Eigen::Vector3d& outward) {
    Eigen::Vector3d n = (verts[q] - verts[p]).cross(verts[r] - verts[p]);
    if (n.dot(outward) < 0) std::swap(q, r);
    tris.emplace_back(p, q, r);
  };
  for (long k = 0; k + 1 < nz; ++k)
    for (long j = 0; j + 1 < ny; ++j)
      for (long i = 0; i + 1 < nx; ++i) {
        std::array<long, 8> corner;
        for (int c = 0; c < 8; ++c)
          corner[c] = (i + (c & 1)) + nx * ((j + (c >> 1 & 1)) + ny * (k + (c >> 2 & 1)));
        bool any_in = false, any_out = false;
        for (long id : corner) (value[id] < 0 ? any_in : any_out) = true;
        if (!any_in || !any_out) continue;
        for (const auto& tet : kTets) {
          std::array<long, 4> v;
          std::vector<long> in, out;
          for (int c = 0; c < 4; ++c) {
            v[c] = corner[tet[c]];
            (value[v[c]] < 0 ? in : out).push_back(v[c]);
          }
          if (in.empty() || out.empty()) continue;
          auto pos = [&](long id) { return point(id % nx, (id / nx) % ny, id / (nx * ny)); };
          Eigen::Vector3d in_c = Eigen::Vector3d::Zero(), out_c = Eigen::Vector3d::Zero();
          for (long id : in) in_c += pos(id) / static_cast<double>(in.size());
          for (long id : out) out_c += pos(id) / static_cast<double>(out.size());
          const Eigen::Vector3d outward = out_c - in_c;
          if (in.size() == 1 || out.size() == 1) {
            // One vertex alone on its side: a triangle cutting its three edges.
            long apex = in.size() == 1 ? in[0] : out[0];
            const std::vector<long>& others = in.size() == 1 ? out : in;
            emit(crossing(apex, others[0]), crossing(apex, others[1]), crossing(apex, others[2]), outward);
          } else {
            // Two and two: a quad in the cyclic order a-c, a-d, b-d, b-c.
            int ac = crossing(in[0], out[0]), ad = crossing(in[0], out[1]), bd = crossing(in[1], out[1]),
                bc = crossing(in[1], out[0]);
            emit(ac, ad, bd, outward);
            emit(ac, bd, bc, outward);
          }
        }
      }
  return mesh_from_vectors(verts, tris);
}

}  // namespace cshapes
