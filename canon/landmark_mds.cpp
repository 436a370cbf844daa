#include "cshapes/canon/landmark_mds.h"

#include <Eigen/Eigenvalues>
#include <algorithm>

#include <cmath>
#include <limits>
#include <vector>

#include "cshapes/support/error.h"
#include "cshapes/support/serial_eigen_products.h"
#include "cshapes/support/timing.h"

namespace cshapes {

namespace {

// Columns of points processed together: a block's squared distances (L × block doubles) stay small.
constexpr Index kPointBlock = 1024;

template <class Rows>
void check_rows(const Rows& rows, const std::vector<int>& landmarks) {
  const Index L = rows.rows(), n = rows.cols();
  CSHAPES_REQUIRE(static_cast<Index>(landmarks.size()) == L, "landmark MDS: ", landmarks.size(),
                  " landmarks for ", L, " rows");
  CSHAPES_REQUIRE(L >= 4, "landmark MDS: needs at least 4 landmarks for a 3-D embedding, got ", L);
  std::vector<char> seen(n, 0);
  for (int l : landmarks) {
    CSHAPES_REQUIRE(l >= 0 && l < n, "landmark MDS: landmark vertex ", l, " out of range 0..", n - 1);
    CSHAPES_REQUIRE(!seen[l], "landmark MDS: landmark vertex ", l, " given twice");
    seen[l] = 1;
  }
  for (Index j = 0; j < n; ++j)
    for (Index k = 0; k < L; ++k)
      if (!(rows(k, j) >= 0 && std::isfinite(rows(k, j))))
        fail("landmark MDS: the distance from landmark ", landmarks[k], " (row ", k, ") to point ", j, " is ",
             rows(k, j), "; distances must be finite and non-negative");
}

// The landmarks' distances among themselves, symmetrised ((D + Dᵀ)/2, zero diagonal), L × L.
template <class Rows>
Eigen::MatrixXd landmark_block(const Rows& rows, const std::vector<int>& landmarks) {
  const Index L = rows.rows();
  Eigen::MatrixXd block(L, L);
  for (Index j = 0; j < L; ++j)
    for (Index i = 0; i < L; ++i) block(i, j) = rows(i, landmarks[j]);
  block = 0.5 * (block + block.transpose()).eval();
  block.diagonal().setZero();
  return block;
}

// The classical MDS of the landmarks and the triangulation map: Y (L×3) and L^# (3×L), δ_μ.
struct LandmarkFrame {
  Points Y;
  Eigen::Matrix<double, 3, Eigen::Dynamic> pseudo_inverse;  // rows v_iᵀ/√λ_i, zero where λ_i ≤ 0
  Eigen::VectorXd mean_squared;                             // δ_μ
  Eigen::Vector3d eigenvalues;
  double explained_energy = 0;
};

LandmarkFrame landmark_frame(const Eigen::MatrixXd& block) {
  const Index L = block.rows();
  const Eigen::MatrixXd squared = block.cwiseAbs2();
  LandmarkFrame f;
  f.mean_squared = squared.rowwise().mean();
  // B = −½ J Δ J, centring rows and columns (Δ symmetric).
  Eigen::MatrixXd B = squared;
  B.rowwise() -= B.colwise().mean();
  B.colwise() -= B.rowwise().mean();
  B *= -0.5;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(B);
  CSHAPES_REQUIRE(eig.info() == Eigen::Success, "landmark MDS: the eigensolver failed on the ", L, "×", L,
                  " landmark block");
  f.Y = Points::Zero(L, 3);
  f.pseudo_inverse.setZero(3, L);
  double top_energy = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const double lambda = eig.eigenvalues()[L - 1 - axis];  // ascending order
    f.eigenvalues[axis] = lambda;
    top_energy += lambda * lambda;
    if (lambda <= 0) continue;
    const Eigen::VectorXd v = eig.eigenvectors().col(L - 1 - axis);
    f.Y.col(axis) = std::sqrt(lambda) * v;
    f.pseudo_inverse.row(axis) = v.transpose() / std::sqrt(lambda);
  }
  const double frobenius = eig.eigenvalues().squaredNorm();
  f.explained_energy = frobenius > 0 ? top_energy / frobenius : 0;
  return f;
}

// Union-find with path halving (the components of the fold repair).
struct Components {
  std::vector<Index> parent;
  explicit Components(Index n) : parent(static_cast<size_t>(n)) {
    for (Index i = 0; i < n; ++i) parent[i] = i;
  }
  Index find(Index i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void join(Index a, Index b) { parent[find(a)] = find(b); }
};

// Landmark SMACOF's fold repair (canon/landmark_mds.h, "Folds"): cut the overstretched edges; in each
// component of the input graph keep the largest remaining part, and place every other point again from its
// neighbours, breadth first from that part. settle(j, start, radius) runs point j's Guttman transforms
// within `radius` of `start`.
template <class Settle>
void repair_folds(const LandmarkNeighbourGraph& graph, Settle&& settle, LandmarkMdsResult& result) {
  Points& X = result.X;
  const Index n = X.rows(), m = graph.edges.rows();
  CSHAPES_REQUIRE(graph.lengths.size() == m, "landmark SMACOF: ", graph.lengths.size(), " edge lengths for ",
                  m, " edges");
  CSHAPES_REQUIRE(graph.overstretch > 1, "landmark SMACOF: overstretch must be > 1, not ", graph.overstretch);
  for (Index e = 0; e < m; ++e)
    for (int side = 0; side < 2; ++side)
      CSHAPES_REQUIRE(graph.edges(e, side) >= 0 && graph.edges(e, side) < n, "landmark SMACOF: edge ", e,
                      " names point ", graph.edges(e, side), " of ", n);
  const double mean_length = graph.lengths.cwiseAbs().mean();
  auto overstretched = [&](Index e) {
    const double limit = graph.overstretch * std::max(std::abs(graph.lengths[e]), mean_length);
    return (X.row(graph.edges(e, 0)) - X.row(graph.edges(e, 1))).norm() > limit;
  };
  // Neighbours in compressed rows.
  std::vector<Index> offset(static_cast<size_t>(n) + 1, 0), neighbour(static_cast<size_t>(2 * m));
  for (Index e = 0; e < m; ++e) ++offset[graph.edges(e, 0) + 1], ++offset[graph.edges(e, 1) + 1];
  for (Index i = 0; i < n; ++i) offset[i + 1] += offset[i];
  {
    std::vector<Index> fill(offset.begin(), offset.end() - 1);
    for (Index e = 0; e < m; ++e) {
      neighbour[fill[graph.edges(e, 0)]++] = graph.edges(e, 1);
      neighbour[fill[graph.edges(e, 1)]++] = graph.edges(e, 0);
    }
  }
  Components input(n);
  for (Index e = 0; e < m; ++e) input.join(graph.edges(e, 0), graph.edges(e, 1));
  // A point placed again stays within half the mean input length of its edges of its start (the mean of
  // its placed neighbours): its edges then stay about as long as its neighbours' spread plus that.
  std::vector<double> radius(static_cast<size_t>(n), 0.0);
  std::vector<int> degree(static_cast<size_t>(n), 0);
  for (Index e = 0; e < m; ++e)
    for (int side = 0; side < 2; ++side)
      radius[graph.edges(e, side)] += std::abs(graph.lengths[e]), ++degree[graph.edges(e, side)];
  for (Index i = 0; i < n; ++i) radius[i] = 0.5 * (degree[i] ? radius[i] / degree[i] : mean_length);

  const Points interpolated = X;
  Index over_before = 0;
  for (Index e = 0; e < m; ++e) over_before += overstretched(e);
  for (int round = 0; round < graph.rounds; ++round) {
    std::vector<char> cut(static_cast<size_t>(m));
    Index cuts = 0;
    for (Index e = 0; e < m; ++e) cuts += (cut[e] = overstretched(e));
    if (cuts == 0) break;
    // The largest part of each input component once the cut edges are gone: placed; the rest is not.
    Components kept(n);
    for (Index e = 0; e < m; ++e)
      if (!cut[e]) kept.join(graph.edges(e, 0), graph.edges(e, 1));
    std::vector<Index> part_size(static_cast<size_t>(n), 0), largest(static_cast<size_t>(n), -1);
    for (Index i = 0; i < n; ++i) ++part_size[kept.find(i)];
    for (Index i = 0; i < n; ++i) {
      const Index c = input.find(i), p = kept.find(i);
      if (largest[c] < 0 || part_size[p] > part_size[largest[c]]) largest[c] = p;
    }
    std::vector<char> placed(static_cast<size_t>(n));
    for (Index i = 0; i < n; ++i) placed[i] = kept.find(i) == largest[input.find(i)];
    if (std::all_of(placed.begin(), placed.end(), [](char p) { return p != 0; })) break;  // nothing cut off
    ++result.repair_rounds;
    // Breadth first from the placed points; a layer is placed in parallel from the layers before it.
    std::vector<Index> layer;
    for (Index i = 0; i < n; ++i)
      if (!placed[i])
        for (Index k = offset[i]; k < offset[i + 1]; ++k)
          if (placed[neighbour[k]]) {
            layer.push_back(i);
            break;
          }
    while (!layer.empty()) {
      const Index size = static_cast<Index>(layer.size());
#pragma omp parallel for schedule(dynamic, 16)
      for (Index q = 0; q < size; ++q) {
        const Index i = layer[q];
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();
        int count = 0;
        for (Index k = offset[i]; k < offset[i + 1]; ++k)
          if (placed[neighbour[k]]) mean += X.row(neighbour[k]).transpose(), ++count;
        X.row(i) = settle(i, Eigen::Vector3d(mean / count), radius[i]).transpose();
      }
      for (Index i : layer) placed[i] = 1;
      result.replaced_points += size;
      std::vector<Index> next;
      for (Index i : layer)
        for (Index k = offset[i]; k < offset[i + 1]; ++k) {
          const Index j = neighbour[k];
          if (!placed[j] && (next.empty() || next.back() != j)) next.push_back(j);
        }
      std::sort(next.begin(), next.end());
      next.erase(std::unique(next.begin(), next.end()), next.end());
      layer = std::move(next);
    }
  }
  for (Index e = 0; e < m; ++e) result.overstretched_edges += overstretched(e);
  // Kept only when it leaves fewer edges over the limit than the interpolation did.
  if (result.replaced_points > 0 && result.overstretched_edges >= over_before) {
    X = interpolated;
    result.overstretched_edges = over_before;
    result.repair_kept = false;
  }
}

}  // namespace

const std::vector<std::string>& mds_solver_names() {
  static const std::vector<std::string> names = {"full", "landmarks", "auto"};  // MdsSolver's order
  return names;
}

MdsSolver parse_mds_solver(const std::string& name) {
  const std::vector<std::string>& names = mds_solver_names();
  for (size_t k = 0; k < names.size(); ++k)
    if (names[k] == name) return static_cast<MdsSolver>(k);
  fail("mds solver: unknown '", name, "'; known: full, landmarks, auto");
}

std::string to_string(MdsSolver solver) {
  return mds_solver_names().at(static_cast<size_t>(solver));
}

bool mds_uses_landmarks(const MdsSolverOptions& options, Index n, double available_bytes) {
  switch (options.solver) {
    case MdsSolver::Full:
      return false;
    case MdsSolver::Landmarks:
      return true;
    case MdsSolver::Auto:
      break;
  }
  if (n > options.auto_full_max_vertices) return true;
  const double matrix_bytes = 4.0 * static_cast<double>(n) * static_cast<double>(n);
  return available_bytes >= 0 && matrix_bytes > 0.5 * available_bytes;
}

namespace {

// Landmark classical MDS of float or double rows (the header's two overloads).
template <class Rows>
LandmarkMdsResult landmark_classical_mds_of(const Rows& rows, const std::vector<int>& landmarks) {
  const SerialEigenProducts serial_eigen_products;  // bit-identical for any thread count
  const auto start = WallClock::now();
  check_rows(rows, landmarks);
  const Index n = rows.cols();
  const LandmarkFrame frame = landmark_frame(landmark_block(rows, landmarks));
  LandmarkMdsResult result;
  result.eigenvalues = frame.eigenvalues;
  result.explained_energy = frame.explained_energy;
  result.X.resize(n, 3);
  // x_a = −½ L^# (δ_a − δ_μ), in blocks of points.
#pragma omp parallel for schedule(static)
  for (Index j0 = 0; j0 < n; j0 += kPointBlock) {
    const Index count = std::min(kPointBlock, n - j0);
    Eigen::MatrixXd delta = rows.middleCols(j0, count).template cast<double>().cwiseAbs2();
    delta.colwise() -= frame.mean_squared;
    result.X.middleRows(j0, count) = (-0.5 * frame.pseudo_inverse * delta).transpose();
  }
  result.X.rowwise() -= result.X.colwise().mean();
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace

LandmarkMdsResult landmark_classical_mds(const Eigen::MatrixXf& rows, const std::vector<int>& landmarks) {
  return landmark_classical_mds_of(rows, landmarks);
}

LandmarkMdsResult landmark_classical_mds_double(const Eigen::MatrixXd& rows, const std::vector<int>& landmarks) {
  return landmark_classical_mds_of(rows, landmarks);
}

namespace {

// Landmark weights: uniform, or the per-point weights summed over each landmark's Voronoi cell (the landmark
// of a point's smallest row entry), normalised to mean 1.
Eigen::VectorXd landmark_weights(const Eigen::MatrixXf& rows, const Eigen::VectorXd& vertex_weights) {
  const Index L = rows.rows(), n = rows.cols();
  Eigen::VectorXd w = Eigen::VectorXd::Ones(L);
  if (vertex_weights.size() == 0) return w;
  CSHAPES_REQUIRE(vertex_weights.size() == n, "landmark SMACOF: ", vertex_weights.size(), " vertex weights for ",
                  n, " points");
  w.setZero();
  for (Index j = 0; j < n; ++j) {
    Index nearest = 0;
    rows.col(j).minCoeff(&nearest);
    w[nearest] += vertex_weights[j];
  }
  w /= w.mean();
  return w;
}

// A point placed against the fixed landmark configuration Y: its stress against its row of distances, and
// its Guttman transforms.
struct PointPlacement {
  const Eigen::MatrixXf& rows;  // L × n distances
  const Points& Y;              // the landmarks' SMACOF configuration
  const Eigen::VectorXd& w;     // landmark weights
  double w_sum;
  int iterations;

  // Point j's normalised weighted stress at p.
  double stress(Index j, const Eigen::Vector3d& p) const {
    const Eigen::VectorXd delta = rows.col(j).cast<double>();
    const double energy = delta.cwiseAbs2().dot(w);
    const Eigen::VectorXd d = (Y.rowwise() - p.transpose()).rowwise().norm();
    return energy > 0 ? (delta - d).cwiseAbs2().dot(w) / energy : 0.0;
  }
  // Guttman transforms of point j's stress with the landmarks fixed, from x; with a radius, each projected
  // onto the ball of that radius around the start (the majorizer is isotropic, so the projection is its
  // minimum over the ball: the stress still never increases).
  Eigen::Vector3d settle(Index j, Eigen::Vector3d x, double radius) const {
    const Index L = Y.rows();
    const Eigen::VectorXd delta = rows.col(j).cast<double>();
    const Eigen::Vector3d centre = x;
    for (int it = 0; it < iterations; ++it) {
      Eigen::Vector3d next = Eigen::Vector3d::Zero();
      for (Index k = 0; k < L; ++k) {
        const Eigen::Vector3d y = Y.row(k).transpose();
        const double d = (x - y).norm();
        next += w[k] * (d > 0 ? y + (delta[k] / d) * (x - y) : y);
      }
      next /= w_sum;
      if (radius < std::numeric_limits<double>::infinity() && (next - centre).norm() > radius)
        next = centre + radius * (next - centre).normalized();
      const bool settled = (next - x).norm() <= 1e-9 * (std::abs(delta.maxCoeff()) + 1e-300);
      x = next;
      if (settled) break;
    }
    return x;
  }
};

}  // namespace

LandmarkMdsResult landmark_smacof(const Eigen::MatrixXf& rows, const std::vector<int>& landmarks,
                                  const SmacofOptions& smacof_options, int interpolation_iterations,
                                  const Points& start_configuration, const LandmarkNeighbourGraph& graph) {
  const SerialEigenProducts serial_eigen_products;  // bit-identical for any thread count
  const auto start = WallClock::now();
  check_rows(rows, landmarks);
  CSHAPES_REQUIRE(interpolation_iterations >= 0,
                  "landmark SMACOF: interpolation iterations must be ≥ 0, not ", interpolation_iterations);
  const Index L = rows.rows(), n = rows.cols();
  const Eigen::MatrixXd block = landmark_block(rows, landmarks);
  const LandmarkFrame frame = landmark_frame(block);

  SmacofOptions so = smacof_options;
  const Eigen::VectorXd w = landmark_weights(rows, smacof_options.vertex_weights);
  if (smacof_options.vertex_weights.size() > 0) so.vertex_weights = w;
  LandmarkMdsResult result;
  result.eigenvalues = frame.eigenvalues;
  result.explained_energy = frame.explained_energy;
  CSHAPES_REQUIRE(start_configuration.rows() == 0 || start_configuration.rows() == L,
                  "landmark SMACOF: a start of ", start_configuration.rows(), " points for ", L,
                  " landmarks");
  result.landmark_smacof =
      smacof(block.cast<float>(), start_configuration.rows() ? start_configuration : frame.Y, so);
  result.landmark_normalized_stress = result.landmark_smacof.normalized_stress;
  const Points& Y = result.landmark_smacof.X;

  // Least-squares triangulation in SMACOF's frame: x = P (c − δ²), P = (AᵀA)⁻¹Aᵀ, A = 2(Y − ȳ).
  const Eigen::RowVector3d y_mean = Y.colwise().mean();
  const Eigen::MatrixXd A = 2.0 * (Y.rowwise() - y_mean);
  const Eigen::Matrix3d AtA = A.transpose() * A;
  const Eigen::MatrixXd P = AtA.completeOrthogonalDecomposition().pseudoInverse() * A.transpose();
  Eigen::VectorXd c = Y.rowwise().squaredNorm();
  c.array() -= c.mean();

  std::vector<char> is_landmark(n, 0);
  for (int l : landmarks) is_landmark[l] = 1;
  const PointPlacement placement{rows, Y, w, w.sum(), interpolation_iterations};
  auto point_stress = [&](Index j, const Eigen::Vector3d& p) { return placement.stress(j, p); };
  auto settle = [&](Index j, Eigen::Vector3d x, double radius) { return placement.settle(j, x, radius); };
  result.X.resize(n, 3);
  double stress_before = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : stress_before)
  for (Index j = 0; j < n; ++j) {
    if (is_landmark[j]) continue;
    const Eigen::VectorXd delta = rows.col(j).cast<double>();
    // Start beside the nearest landmark, at its distance, towards the linear triangulation: the point then
    // descends into the basin of its own neighbourhood (from the triangulation alone, points near folds
    // fell into the basin across the fold).
    Index nearest = 0;
    delta.minCoeff(&nearest);
    const Eigen::Vector3d y_near = Y.row(nearest).transpose();
    const Eigen::Vector3d towards = P * (c - delta.cwiseAbs2()) - y_near;
    const Eigen::Vector3d x = y_near + (towards.norm() > 0 ? Eigen::Vector3d(delta[nearest] * towards.normalized())
                                                           : Eigen::Vector3d::Zero());
    stress_before += point_stress(j, x);
    result.X.row(j) = settle(j, x, std::numeric_limits<double>::infinity()).transpose();
  }
  for (Index k = 0; k < L; ++k) result.X.row(landmarks[k]) = Y.row(k);
  if (graph.edges.rows() > 0) repair_folds(graph, settle, result);
  double stress_after = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : stress_after)
  for (Index j = 0; j < n; ++j)
    if (!is_landmark[j]) stress_after += point_stress(j, result.X.row(j).transpose());
  const double others = static_cast<double>(std::max<Index>(1, n - L));
  result.start_point_stress = stress_before / others;
  result.interpolated_point_stress = stress_after / others;
  result.X.rowwise() -= result.X.colwise().mean();
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace cshapes
