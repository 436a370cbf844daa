#include "cshapes/data/synthetic.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <vector>

#include "cshapes/support/error.h"

namespace cshapes {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

Mesh icosphere(int subdivisions, double radius) {
  CSHAPES_REQUIRE(subdivisions >= 0 && subdivisions <= 8, "icosphere: subdivisions must be in 0..8, got ",
                  subdivisions);
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> verts = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                        {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                        {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& v : verts) v.normalize();
  std::vector<Eigen::Vector3i> tris = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int b) {
      auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      verts.push_back((verts[a] + verts[b]).normalized());
      return midpoint[key] = static_cast<int>(verts.size()) - 1;
    };
    std::vector<Eigen::Vector3i> next;
    next.reserve(4 * tris.size());
    for (const auto& f : tris) {
      int a = mid(f[0], f[1]), b = mid(f[1], f[2]), c = mid(f[2], f[0]);
      next.emplace_back(f[0], a, c);
      next.emplace_back(f[1], b, a);
      next.emplace_back(f[2], c, b);
      next.emplace_back(a, b, c);
    }
    tris.swap(next);
  }
  for (auto& v : verts) v *= radius;
  return mesh_from_vectors(verts, tris);
}

Mesh torus(int nu, int nv, double R, double r) {
  CSHAPES_REQUIRE(nu >= 3 && nv >= 3, "torus: needs nu, nv >= 3, got ", nu, ", ", nv);
  std::vector<Eigen::Vector3d> verts;
  std::vector<Eigen::Vector3i> tris;
  for (int i = 0; i < nu; ++i) {
    double u = 2 * kPi * i / nu;
    for (int j = 0; j < nv; ++j) {
      double v = 2 * kPi * j / nv;
      verts.emplace_back((R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u),
                         r * std::sin(v));
    }
  }
  auto id = [&](int i, int j) { return ((i + nu) % nu) * nv + (j + nv) % nv; };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      tris.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      tris.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  return mesh_from_vectors(verts, tris);
}

Mesh grid(int nx, int ny, double width, double height) {
  CSHAPES_REQUIRE(nx >= 2 && ny >= 2, "grid: needs nx, ny >= 2, got ", nx, ", ", ny);
  std::vector<Eigen::Vector3d> verts;
  std::vector<Eigen::Vector3i> tris;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) verts.emplace_back(width * i / (nx - 1), height * j / (ny - 1), 0.0);
  auto id = [&](int i, int j) { return j * nx + i; };
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      if ((i + j) % 2 == 0) {
        tris.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
        tris.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
      } else {
        tris.emplace_back(id(i, j), id(i + 1, j), id(i, j + 1));
        tris.emplace_back(id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
      }
    }
  return mesh_from_vectors(verts, tris);
}

Points lumpy_blob(Index n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Points X(n, 3);
  for (Index i = 0; i < n; ++i) {
    Eigen::Vector3d u(normal(rng), normal(rng), normal(rng));
    u.normalize();
    double r = 1.0 + 0.3 * std::sin(3 * u.x() + 1) * std::cos(2 * u.y()) + 0.2 * u.z() * u.z() * u.x();
    X.row(i) = (Eigen::Vector3d(3.0, 1.5, 1.0).asDiagonal() * (r * u)).transpose();
  }
  return X;
}

Mesh capsule(const CapsuleOptions& o) {
  CSHAPES_REQUIRE(o.segments >= 3, "capsule: needs segments >= 3, got ", o.segments);
  CSHAPES_REQUIRE(o.length >= 0 && o.radius > 0 && std::isfinite(o.length) && std::isfinite(o.radius),
                  "capsule: needs length >= 0 and radius > 0, got ", o.length, ", ", o.radius);
  const int s = o.segments;
  const double h = 2 * kPi * o.radius / s;  // spacing around a ring
  const int cylinder_steps = std::max(1, static_cast<int>(std::lround(o.length / h)));
  const int cap_steps = std::max(1, static_cast<int>(std::lround(0.5 * kPi * o.radius / h)));
  // Rings as (axial position a along the straight axis, radius ρ), pole to pole.
  std::vector<std::pair<double, double>> rings;
  for (int k = 1; k < cap_steps; ++k) {  // first cap, from near the pole to the equator (exclusive)
    const double theta = 0.5 * kPi * k / cap_steps;
    rings.emplace_back(-o.radius * std::cos(theta), o.radius * std::sin(theta));
  }
  for (int k = 0; k <= cylinder_steps; ++k) rings.emplace_back(o.length * k / cylinder_steps, o.radius);
  for (int k = cap_steps - 1; k >= 1; --k) {
    const double theta = 0.5 * kPi * k / cap_steps;
    rings.emplace_back(o.length + o.radius * std::cos(theta), o.radius * std::sin(theta));
  }
  // The axis point at axial position a, and the unit frame (tangent, normal in the plane, z) there.
  auto place = [&](double a, double rho, double phi) {
    const double y = rho * std::cos(phi), z = rho * std::sin(phi);
    if (o.bend == 0) return Eigen::Vector3d(a, y, z);
    const double R = std::max(o.length, 1e-300) / o.bend;  // bend radius of the axis
    const double clamped = std::clamp(a, 0.0, o.length), angle = clamped / R;
    const Eigen::Vector3d centre(R * std::sin(angle), R * (1 - std::cos(angle)), 0.0);
    const Eigen::Vector3d tangent(std::cos(angle), std::sin(angle), 0.0),
        normal(-std::sin(angle), std::cos(angle), 0.0);
    return Eigen::Vector3d(centre + (a - clamped) * tangent + y * normal + Eigen::Vector3d(0, 0, z));
  };
  std::vector<Eigen::Vector3d> verts;
  std::vector<Eigen::Vector3i> tris;
  verts.push_back(place(-o.radius, 0, 0));
  for (const auto& [a, rho] : rings)
    for (int j = 0; j < s; ++j) verts.push_back(place(a, rho, 2 * kPi * j / s));
  verts.push_back(place(o.length + o.radius, 0, 0));
  const int num_rings = static_cast<int>(rings.size());
  const int last_pole = static_cast<int>(verts.size()) - 1;
  auto id = [&](int ring, int j) { return 1 + ring * s + (j + s) % s; };
  // Ring vertices go counter-clockwise about +x (the axis direction), so outward faces below.
  for (int j = 0; j < s; ++j) tris.emplace_back(0, id(0, j + 1), id(0, j));
  for (int ring = 0; ring + 1 < num_rings; ++ring)
    for (int j = 0; j < s; ++j) {
      if ((ring + j) % 2 == 0) {
        tris.emplace_back(id(ring, j), id(ring, j + 1), id(ring + 1, j + 1));
        tris.emplace_back(id(ring, j), id(ring + 1, j + 1), id(ring + 1, j));
      } else {
        tris.emplace_back(id(ring, j), id(ring, j + 1), id(ring + 1, j));
        tris.emplace_back(id(ring, j + 1), id(ring + 1, j + 1), id(ring + 1, j));
      }
    }
  for (int j = 0; j < s; ++j) tris.emplace_back(last_pole, id(num_rings - 1, j), id(num_rings - 1, j + 1));
  return mesh_from_vectors(verts, tris);
}

Mesh split_faces(const Mesh& mesh, int every, double w0, double w1) {
  CSHAPES_REQUIRE(every >= 1, "split_faces: every must be at least 1, got ", every);
  CSHAPES_REQUIRE(w0 > 0 && w1 > 0 && w0 + w1 < 1, "split_faces: barycentric weights must be positive, got ",
                  w0, ", ", w1, ", ", 1 - w0 - w1);
  const Index n = mesh.num_vertices(), m = mesh.num_faces();
  const Index splits = (m + every - 1) / every;
  Mesh out;
  out.V.resize(n + splits, 3);
  out.V.topRows(n) = mesh.V;
  out.F.resize(m + 2 * splits, 3);
  Index next_vertex = n, next_face = m;
  for (Index f = 0; f < m; ++f) {
    out.F.row(f) = mesh.F.row(f);
    if (f % every != 0) continue;
    const int a = mesh.F(f, 0), b = mesh.F(f, 1), c = mesh.F(f, 2);
    out.V.row(next_vertex) = w0 * mesh.V.row(a) + w1 * mesh.V.row(b) + (1 - w0 - w1) * mesh.V.row(c);
    const int p = static_cast<int>(next_vertex++);
    out.F.row(f) << a, b, p;
    out.F.row(next_face++) << b, c, p;
    out.F.row(next_face++) << c, a, p;
  }
  return out;
}

double swiss_roll_length(double t0, double t1) {
  auto primitive = [](double t) { return 0.5 * (t * std::sqrt(1 + t * t) + std::asinh(t)); };
  return primitive(t1) - primitive(t0);
}

std::pair<int, int> swiss_roll_grid(long n) {
  double best = 1e300;
  std::pair<int, int> grid{2, 2};
  for (int nv = 2; nv <= n / 2; ++nv) {
    int nu = static_cast<int>(std::lround(static_cast<double>(n) / nv));
    if (nu < 2) break;
    double cost = std::abs(static_cast<double>(nu) * nv - n) / n +
                  0.05 * std::abs(std::log((nu - 1.0) / (nv - 1.0) / 5.0));
    if (cost < best) best = cost, grid = {nu, nv};
  }
  return grid;
}

Mesh swiss_roll(const SwissRollOptions& o) {
  CSHAPES_REQUIRE(o.nu >= 2 && o.nv >= 2, "swiss_roll: needs nu, nv >= 2, got ", o.nu, ", ", o.nv);
  CSHAPES_REQUIRE(o.t1 > o.t0 && o.t0 >= 0 && o.height > 0, "swiss_roll: needs 0 <= t0 < t1 and height > 0");
  // Sample t so that consecutive columns are equally spaced in arc length (Newton on the arc-length map).
  double total = swiss_roll_length(o.t0, o.t1);
  std::vector<double> ts(o.nu);
  double t = o.t0;
  for (int i = 0; i < o.nu; ++i) {
    double target = total * i / (o.nu - 1);
    for (int it = 0; it < 50; ++it) {
      double f = swiss_roll_length(o.t0, t) - target;
      t -= f / std::sqrt(1 + t * t);
    }
    ts[i] = t;
  }
  Mesh flat = grid(o.nu, o.nv, 1.0, o.height);
  for (Index k = 0; k < flat.V.rows(); ++k) {
    int i = static_cast<int>(k % o.nu);
    double y = flat.V(k, 1);
    flat.V.row(k) << ts[i] * std::cos(ts[i]), y, ts[i] * std::sin(ts[i]);
  }
  return flat;
}

SwissRollSample random_swiss_roll_points(Index n, unsigned seed, const SwissRollOptions& roll) {
  CSHAPES_REQUIRE(n >= 0, "random_swiss_roll_points: n must be >= 0, got ", n);
  CSHAPES_REQUIRE(roll.t1 > roll.t0 && roll.t0 >= 0 && roll.height > 0,
                  "random_swiss_roll_points: needs 0 <= t0 < t1 and height > 0");
  const double length = swiss_roll_length(roll.t0, roll.t1);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> along(0.0, length), across(0.0, roll.height);
  // Arc length → spiral angle by a fine table (the roll's arc length is monotone in t).
  const int table = 4096;
  std::vector<double> arc(table + 1);
  for (int k = 0; k <= table; ++k)
    arc[k] = swiss_roll_length(roll.t0, roll.t0 + (roll.t1 - roll.t0) * k / table);
  SwissRollSample sample;
  sample.flat.resize(n, 2);
  sample.X.resize(n, 3);
  for (Index i = 0; i < n; ++i) {
    const double s = along(rng), y = across(rng);
    const int k = std::min<int>(table - 1, std::lower_bound(arc.begin(), arc.end(), s) - arc.begin());
    const double t = roll.t0 + (roll.t1 - roll.t0) * (k + (k + 1 < table ? 0.5 : 0.0)) / table;
    sample.flat.row(i) << s, y;
    sample.X.row(i) << t * std::cos(t), y, t * std::sin(t);
  }
  return sample;
}

DistanceMatrix swiss_roll_geodesic_distances(const SwissRollSample& sample) {
  const Index n = sample.flat.rows();
  require_memory(distance_matrix_bytes(n), "the " + std::to_string(n) + "x" + std::to_string(n) +
                                               " distance matrix of the Swiss roll sample");
  DistanceMatrix D = uninitialized_distance_matrix(n, n);
  const Eigen::MatrixX2d& flat = sample.flat;
#pragma omp parallel for schedule(static)
  for (Index j = 0; j < n; ++j)
    for (Index i = 0; i < n; ++i) D(i, j) = static_cast<float>((flat.row(i) - flat.row(j)).norm());
  return D;
}

PointDistribution parse_point_distribution(const std::string& name) {
  if (name == "uniform") return PointDistribution::Uniform;
  if (name == "sphere") return PointDistribution::Sphere;
  if (name == "clustered") return PointDistribution::Clustered;
  fail("unknown point distribution '", name, "' (expected uniform, sphere or clustered)");
}

std::string to_string(PointDistribution distribution) {
  switch (distribution) {
    case PointDistribution::Uniform:
      return "uniform";
    case PointDistribution::Sphere:
      return "sphere";
    case PointDistribution::Clustered:
      return "clustered";
  }
  return "?";
}

Points random_points(Index n, PointDistribution distribution, std::mt19937_64& rng) {
  CSHAPES_REQUIRE(n >= 0, "random_points: n must be >= 0, got ", n);
  Points X(n, 3);
  std::uniform_real_distribution<double> uniform(0, 1);
  std::normal_distribution<double> normal(0, 1);
  switch (distribution) {
    case PointDistribution::Uniform:
      for (Index i = 0; i < n; ++i) X.row(i) << uniform(rng), uniform(rng), uniform(rng);
      break;
    case PointDistribution::Sphere:
      for (Index i = 0; i < n; ++i) {
        Eigen::RowVector3d v(normal(rng), normal(rng), normal(rng));
        X.row(i) = v / std::max(v.norm(), 1e-300);
      }
      break;
    case PointDistribution::Clustered: {
      const int clusters = 20;
      std::vector<Eigen::RowVector3d> centers(clusters);
      std::vector<double> widths(clusters), weights(clusters);
      for (int c = 0; c < clusters; ++c) {
        centers[c] << uniform(rng), uniform(rng), uniform(rng);
        widths[c] = std::pow(10.0, -3 + 2 * uniform(rng));
        weights[c] = 1 + 9 * uniform(rng);
      }
      std::discrete_distribution<int> pick(weights.begin(), weights.end());
      for (Index i = 0; i < n; ++i) {
        const int c = pick(rng);
        X.row(i) = centers[c] + widths[c] * Eigen::RowVector3d(normal(rng), normal(rng), normal(rng));
      }
      break;
    }
  }
  return X;
}

Points sample_surface(const Mesh& mesh, Index n, std::mt19937_64& rng) {
  std::vector<double> area(mesh.F.rows());
  for (Index f = 0; f < mesh.F.rows(); ++f) {
    const Eigen::RowVector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)),
                             c = mesh.V.row(mesh.F(f, 2));
    area[f] = 0.5 * (b - a).cross(c - a).norm();
  }
  CSHAPES_REQUIRE(std::any_of(area.begin(), area.end(), [](double a) { return a > 0; }),
                  "sample_surface: the mesh has no face of positive area to sample points on");
  std::discrete_distribution<Index> pick(area.begin(), area.end());
  std::uniform_real_distribution<double> uniform(0, 1);
  Points X(n, 3);
  for (Index i = 0; i < n; ++i) {
    const Index f = pick(rng);
    double u = uniform(rng), v = uniform(rng);
    if (u + v > 1) u = 1 - u, v = 1 - v;
    X.row(i) =
        (1 - u - v) * mesh.V.row(mesh.F(f, 0)) + u * mesh.V.row(mesh.F(f, 1)) + v * mesh.V.row(mesh.F(f, 2));
  }
  return X;
}

}  // namespace cshapes
