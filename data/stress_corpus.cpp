#include "cshapes/data/stress_corpus.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

#include "cshapes/data/articulated.h"
#include "cshapes/support/deterministic_random.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/mesh/remesh.h"
#include "cshapes/mesh/subdivide.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/data/topological_noise.h"

namespace cshapes {

namespace fs = std::filesystem;

namespace {

std::uint64_t mix(std::uint64_t seed, Index index) {
  // SplitMix64 of the pair: neighbouring (seed, index) give unrelated generators.
  std::uint64_t z = seed * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(index) + 0x632BE59BD9B4E019ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

std::vector<std::string> tosca_shapes(const std::string& folder) {
  std::vector<std::string> names;
  if (folder.empty() || !fs::is_directory(folder)) return names;
  for (const auto& entry : fs::directory_iterator(folder))
    if (entry.path().extension() == ".off") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

// The base shapes before remeshing, made once per process.
Mesh base_shape(const std::string& base, const StressCorpusOptions& options) {
  static std::mutex mutex;
  static std::map<std::string, Mesh> made;
  {
    std::lock_guard<std::mutex> lock(mutex);
    auto it = made.find(base);
    if (it != made.end()) return it->second;
  }
  Mesh m;
  if (base == "icosphere") {
    m = icosphere(5, 1.0);
  } else if (base == "torus") {
    m = torus(96, 32, 1.0, 0.3);
  } else if (base == "capsule") {
    CapsuleOptions co;
    co.length = 6;
    co.segments = 32;
    co.bend = 1.5;
    m = capsule(co);
  } else if (base.rfind("articulated:", 0) == 0) {
    RestMeshOptions ro;
    ro.target_vertices = 4000;
    m = articulated_rest_mesh(articulated_skeleton(base.substr(12)), ro);
  } else if (base.rfind("tosca:", 0) == 0) {
    m = read_mesh((fs::path(options.tosca_folder) / (base.substr(6) + ".off")).string());
  } else {
    fail("stress corpus: unknown base shape '", base, "'");
  }
  std::lock_guard<std::mutex> lock(mutex);
  made.emplace(base, m);
  return m;
}

// The base at `vertices`: CGAL's isotropic remeshing below the base's own size; above it, midpoint
// subdivisions and longest-edge splits of the base's triangles (flat, anisotropic: no easier than a remesh,
// and 20-50× cheaper than remeshing up to 30,000 vertices, which dominated a stress run's time).
Mesh remeshed(const std::string& base, Index vertices, const StressCorpusOptions& options) {
  const Mesh shape = base_shape(base, options);
  if (vertices > shape.num_vertices()) return refine_to_vertex_count(shape, vertices).mesh;
  RemeshOptions ro;
  ro.target_vertices = vertices;
  return remesh(shape, ro).mesh;
}

// Drops vertices in no face, renumbering the faces.
Mesh drop_unreferenced(const Mesh& mesh) {
  std::vector<int> new_index(mesh.num_vertices(), -1);
  int count = 0;
  for (Index f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (new_index[mesh.F(f, k)] < 0) new_index[mesh.F(f, k)] = count++;
  Mesh out;
  out.V.resize(count, 3);
  for (Index v = 0; v < mesh.num_vertices(); ++v)
    if (new_index[v] >= 0) out.V.row(new_index[v]) = mesh.V.row(v);
  out.F.resize(mesh.F.rows(), 3);
  for (Index f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) out.F(f, k) = new_index[mesh.F(f, k)];
  return out;
}

// The faces of the largest component (connected through shared vertices), vertices renumbered.
Mesh largest_component(const Mesh& mesh) {
  Components comp = connected_components(mesh.num_vertices(), mesh_edges(mesh.F));
  if (comp.count <= 1) return drop_unreferenced(mesh);
  std::vector<int> face_count(comp.count, 0);
  for (Index f = 0; f < mesh.F.rows(); ++f) ++face_count[comp.label[mesh.F(f, 0)]];
  const int keep = static_cast<int>(std::max_element(face_count.begin(), face_count.end()) - face_count.begin());
  Mesh kept;
  kept.V = mesh.V;
  std::vector<Index> rows;
  for (Index f = 0; f < mesh.F.rows(); ++f)
    if (comp.label[mesh.F(f, 0)] == keep) rows.push_back(f);
  kept.F.resize(static_cast<Index>(rows.size()), 3);
  for (size_t r = 0; r < rows.size(); ++r) kept.F.row(static_cast<Index>(r)) = mesh.F.row(rows[r]);
  return drop_unreferenced(kept);
}

// Mean length of the edges at each vertex.
Eigen::VectorXd local_edge_length(const Mesh& mesh) {
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(mesh.num_vertices()), count = sum;
  for (Index f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.F(f, k), b = mesh.F(f, (k + 1) % 3);
      const double l = (mesh.V.row(a) - mesh.V.row(b)).norm();
      sum[a] += l, count[a] += 1;
      sum[b] += l, count[b] += 1;
    }
  for (Index v = 0; v < sum.size(); ++v) sum[v] = count[v] > 0 ? sum[v] / count[v] : 0.0;
  return sum;
}

Mesh jitter(Mesh mesh, double fraction, DeterministicRandom& rng) {
  const Eigen::VectorXd h = local_edge_length(mesh);
  for (Index v = 0; v < mesh.num_vertices(); ++v) {
    Eigen::Vector3d r;
    do r = Eigen::Vector3d(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    while (r.squaredNorm() > 1);
    mesh.V.row(v) += fraction * h[v] * r.transpose();
  }
  return mesh;
}

// Splits edges near one end: each split edge (a, b) gets a vertex at a + t(b - a), t ∈ [0.003, 0.06], and
// its two faces become four (valence-4 vertices beside a near-zero edge, obtuse fans). No face is split twice.
Mesh split_edges_near_end(const Mesh& mesh, double fraction, DeterministicRandom& rng) {
  std::map<std::pair<int, int>, std::vector<std::pair<Index, int>>> faces_of;  // edge → (face, corner k)
  for (Index f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      int a = mesh.F(f, k), b = mesh.F(f, (k + 1) % 3);
      faces_of[{std::min(a, b), std::max(a, b)}].emplace_back(f, k);
    }
  std::vector<Eigen::RowVector3d> V;
  for (Index v = 0; v < mesh.num_vertices(); ++v) V.push_back(mesh.V.row(v));
  std::vector<Eigen::Vector3i> F;
  std::vector<char> used(mesh.F.rows(), 0);
  for (const auto& [edge, incident] : faces_of) {
    if (rng.uniform() >= fraction) continue;
    bool free = true;
    for (auto [f, k] : incident) free = free && !used[f];
    if (!free) continue;
    const double t = rng.uniform(0.003, 0.06);
    const int mid = static_cast<int>(V.size());
    V.push_back(mesh.V.row(edge.first) + t * (mesh.V.row(edge.second) - mesh.V.row(edge.first)));
    for (auto [f, k] : incident) {
      used[f] = 1;
      const int a = mesh.F(f, k), b = mesh.F(f, (k + 1) % 3), c = mesh.F(f, (k + 2) % 3);
      F.emplace_back(a, mid, c);
      F.emplace_back(mid, b, c);
    }
  }
  for (Index f = 0; f < mesh.F.rows(); ++f)
    if (!used[f]) F.emplace_back(mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2));
  Mesh out;
  out.V.resize(static_cast<Index>(V.size()), 3);
  for (size_t i = 0; i < V.size(); ++i) out.V.row(static_cast<Index>(i)) = V[i];
  out.F.resize(static_cast<Index>(F.size()), 3);
  for (size_t i = 0; i < F.size(); ++i) out.F.row(static_cast<Index>(i)) = F[i].transpose();
  return out;
}

// Moves some vertices onto the opposite edge of one of their faces (that face gets zero area) or onto a
// neighbour (a zero-length edge); a moved vertex's neighbours are not moved.
Mesh near_degenerate(Mesh mesh, double fraction, DeterministicRandom& rng) {
  std::vector<char> frozen(mesh.num_vertices(), 0);
  for (Index f = 0; f < mesh.F.rows(); ++f) {
    if (rng.uniform() >= fraction) continue;
    const int k = static_cast<int>(rng.index(3));
    const int c = mesh.F(f, k), a = mesh.F(f, (k + 1) % 3), b = mesh.F(f, (k + 2) % 3);
    if (frozen[c] || frozen[a] || frozen[b]) continue;
    if (rng.uniform() < 0.7) {
      const double t = rng.uniform(0.15, 0.85);
      mesh.V.row(c) = mesh.V.row(a) + t * (mesh.V.row(b) - mesh.V.row(a));  // collinear: zero area
    } else {
      mesh.V.row(c) = mesh.V.row(a);  // coincident: zero-length edge
    }
    frozen[a] = frozen[b] = frozen[c] = 1;
  }
  return mesh;
}

// Removes `holes` patches of faces (k-rings of a random face) and keeps the largest component.
Mesh cut_holes(const Mesh& mesh, int holes, int rings, DeterministicRandom& rng) {
  std::vector<char> removed(mesh.F.rows(), 0);
  std::vector<std::vector<Index>> faces_of_vertex(mesh.num_vertices());
  for (Index f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) faces_of_vertex[mesh.F(f, k)].push_back(f);
  for (int h = 0; h < holes; ++h) {
    std::vector<Index> front{static_cast<Index>(rng.index(mesh.F.rows()))};
    removed[front[0]] = 1;
    for (int r = 0; r < rings; ++r) {
      std::vector<Index> next;
      for (Index f : front)
        for (int k = 0; k < 3; ++k)
          for (Index g : faces_of_vertex[mesh.F(f, k)])
            if (!removed[g]) removed[g] = 1, next.push_back(g);
      front = next;
    }
  }
  Mesh kept;
  kept.V = mesh.V;
  std::vector<Index> rows;
  for (Index f = 0; f < mesh.F.rows(); ++f)
    if (!removed[f]) rows.push_back(f);
  kept.F.resize(static_cast<Index>(rows.size()), 3);
  for (size_t r = 0; r < rows.size(); ++r) kept.F.row(static_cast<Index>(r)) = mesh.F.row(rows[r]);
  return largest_component(kept);
}

}  // namespace

Mesh random_edge_flips(const Mesh& mesh, double fraction, std::uint64_t seed) {
  DeterministicRandom rng(seed);
  Mesh out = mesh;
  Faces& F = out.F;
  const Index m = F.rows();
  // Half-edge twins by vertex pair, kept up to date through the flips.
  std::map<std::pair<int, int>, int> half;  // (a, b) → half-edge 3f+k running a→b
  for (Index f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) half[{F(f, k), F(f, (k + 1) % 3)}] = static_cast<int>(3 * f + k);
  std::vector<int> degree(mesh.num_vertices(), 0);
  for (const auto& [e, h] : half) ++degree[e.first];  // each edge counted once per direction
  const Index wanted = static_cast<Index>(fraction * 1.5 * static_cast<double>(m));
  for (Index attempt = 0, flips = 0; attempt < 4 * wanted && flips < wanted; ++attempt) {
    const Index f = static_cast<Index>(rng.index(m));
    const int k = static_cast<int>(rng.index(3));
    const int a = F(f, k), b = F(f, (k + 1) % 3), c = F(f, (k + 2) % 3);
    auto twin = half.find({b, a});
    if (twin == half.end()) continue;  // boundary
    const Index g = twin->second / 3;
    const int kk = twin->second % 3;
    const int d = F(g, (kk + 2) % 3);
    if (g == f || c == d || half.count({c, d}) || half.count({d, c})) continue;
    if (degree[a] <= 3 || degree[b] <= 3) continue;
    for (Index face : {f, g})
      for (int j = 0; j < 3; ++j) half.erase({F(face, j), F(face, (j + 1) % 3)});
    F.row(f) << a, d, c;
    F.row(g) << d, b, c;
    for (Index face : {f, g})
      for (int j = 0; j < 3; ++j) half[{F(face, j), F(face, (j + 1) % 3)}] = static_cast<int>(3 * face + j);
    --degree[a], --degree[b], ++degree[c], ++degree[d];
    ++flips;
  }
  return out;
}

std::string to_string(StressKind kind) {
  switch (kind) {
    case StressKind::Remesh:
      return "remesh";
    case StressKind::Jitter:
      return "jitter";
    case StressKind::Flips:
      return "flips";
    case StressKind::Splits:
      return "splits";
    case StressKind::NearDegenerate:
      return "near-degenerate";
    case StressKind::Tube:
      return "tube";
    case StressKind::Handles:
      return "handles";
    case StressKind::Boundary:
      return "boundary";
    case StressKind::Scale:
      return "scale";
  }
  return "?";
}

std::string StressCase::name() const {
  return "s" + std::to_string(seed) + "-i" + std::to_string(index) + "-" + to_string(kind);
}

std::string StressCase::describe() const {
  std::ostringstream out;
  out << name() << ": " << base << " at " << base_vertices << " vertices, " << to_string(kind) << " "
      << amount;
  return out.str();
}

void check_stress_corpus_options(const StressCorpusOptions& options) {
  CSHAPES_REQUIRE(options.min_vertices >= 50 && options.max_vertices >= options.min_vertices,
                  "stress corpus: need 50 <= min_vertices <= max_vertices, got ", options.min_vertices, " and ",
                  options.max_vertices);
}

StressCase stress_case(std::uint64_t seed, Index index, const StressCorpusOptions& options) {
  check_stress_corpus_options(options);
  DeterministicRandom rng(mix(seed, index));
  StressCase c;
  c.seed = seed;
  c.index = index;
  c.kind = static_cast<StressKind>(index % kStressKinds);
  std::vector<std::string> bases = {"icosphere", "torus", "capsule"};
  for (const std::string& cls : articulated_classes()) bases.push_back("articulated:" + cls);
  for (const std::string& name : tosca_shapes(options.tosca_folder)) bases.push_back("tosca:" + name);
  c.base = bases[rng.index(bases.size())];
  const double lo = std::log(static_cast<double>(options.min_vertices)),
               hi = std::log(static_cast<double>(options.max_vertices));
  c.base_vertices = static_cast<Index>(std::lround(std::exp(rng.uniform(lo, hi))));
  switch (c.kind) {
    case StressKind::Remesh:
      c.amount = 0;
      break;
    case StressKind::Jitter:
      c.amount = rng.uniform(0.1, 0.45);
      break;
    case StressKind::Flips:
      c.amount = rng.uniform(0.05, 0.6);
      break;
    case StressKind::Splits:
      c.amount = rng.uniform(0.05, 0.4);
      break;
    case StressKind::NearDegenerate:
      c.amount = rng.uniform(0.01, 0.1);
      break;
    case StressKind::Tube:
      c.base = "tube";
      c.amount = std::exp(rng.uniform(std::log(20.0), std::log(400.0)));  // length / radius
      break;
    case StressKind::Handles:
      c.base = rng.uniform() < 0.5 ? "articulated:hand" : c.base;
      c.amount = static_cast<double>(1 + rng.index(4));
      break;
    case StressKind::Boundary:
      c.amount = static_cast<double>(1 + rng.index(6));  // holes
      if (rng.uniform() < 0.2) c.base = "grid";
      break;
    case StressKind::Scale:
      c.amount = std::pow(10.0, rng.uniform(-4, 4));
      break;
  }
  return c;
}

Mesh make_stress_mesh(const StressCase& c, const StressCorpusOptions& options) {
  // The perturbation's own generator, independent of the parameter draws.
  DeterministicRandom rng(mix(c.seed ^ 0x5DEECE66DULL, c.index));
  if (c.kind == StressKind::Tube) {
    CapsuleOptions co;
    co.radius = 1;
    co.length = c.amount;
    co.segments = 3 + static_cast<int>(rng.index(6));
    co.bend = rng.uniform() < 0.5 ? rng.uniform(0.5, 3.0) : 0.0;
    Mesh tube = capsule(co);
    if (rng.uniform() >= 0.5) return tube;
    const double w0 = rng.uniform(0.7, 0.95), w1 = rng.uniform(0.1, 0.9) * (1 - w0);  // w2 > 0 too
    return split_faces(tube, 2, w0, w1);
  }
  if (c.base == "grid") {
    const int nx = 3 + static_cast<int>(std::sqrt(static_cast<double>(c.base_vertices)) * rng.uniform(0.5, 2));
    const int ny = std::max(3, static_cast<int>(c.base_vertices / nx));
    return jitter(grid(nx, ny, rng.uniform(0.2, 5.0), 1.0), 0.3, rng);
  }
  Mesh mesh = remeshed(c.base, c.base_vertices, options);
  switch (c.kind) {
    case StressKind::Remesh:
      return mesh;
    case StressKind::Jitter:
      return jitter(mesh, c.amount, rng);
    case StressKind::Flips:
      return random_edge_flips(mesh, c.amount, rng.next());
    case StressKind::Splits: {
      const double w0 = rng.uniform(0.85, 0.99), w1 = rng.uniform(0.1, 0.9) * (1 - w0);  // w2 > 0 too
      Mesh split = split_faces(mesh, 2 + static_cast<int>(rng.index(4)), w0, w1);
      return split_edges_near_end(split, c.amount, rng);
    }
    case StressKind::NearDegenerate:
      return near_degenerate(mesh, c.amount, rng);
    case StressKind::Handles: {
      TopologicalNoiseOptions no;
      no.glue_count = static_cast<int>(c.amount);
      no.relax_steps = 4;
      try {
        return glue_topological_noise(mesh, no).mesh;
      } catch (const Error&) {
        no.glue_count = 1;  // a shape without that many almost-touching spots: one handle
        try {
          return glue_topological_noise(mesh, no).mesh;
        } catch (const Error&) {
          return random_edge_flips(mesh, 0.2, rng.next());  // none at all: still a perturbed mesh
        }
      }
    }
    case StressKind::Boundary:
      return cut_holes(mesh, static_cast<int>(c.amount), 1 + static_cast<int>(rng.index(4)), rng);
    case StressKind::Scale: {
      Mesh flipped = random_edge_flips(mesh, rng.uniform(0.1, 0.3), rng.next());
      flipped.V *= c.amount;
      return flipped;
    }
    case StressKind::Tube:
      break;
  }
  return mesh;
}

}  // namespace cshapes
