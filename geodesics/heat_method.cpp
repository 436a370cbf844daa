#include "cshapes/geodesics/heat_method.h"

#include <Eigen/SparseCore>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>
#include <sstream>

#include "cshapes/operators/cotangent_operator.h"
#include "cshapes/support/error.h"
#include "cshapes/geodesics/fast_marching.h"
#include "cshapes/operators/intrinsic_delaunay.h"
#include "cshapes/support/simd.h"
#include "cshapes/operators/sparse_cholesky.h"
#include "cshapes/mesh/unit_scale.h"

namespace cshapes {

namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;
// A block of right-hand sides, one row per vertex: the k values of a vertex are contiguous, so the sparse
// triangular solves and the gradient/divergence step run vectorised across the k sources.
using Block = SparseCholesky::Block;

}  // namespace

// The heat values are kept inside [kHeatFloor, kHeatPeak] where they are trusted: the right-hand side is
// scaled so that u ≤ kHeatPeak at the source (and the forward solve's intermediate values too), and below
// kHeatFloor, still far above the double range's bottom (2.2e-308, where precision is lost to subnormals), a
// vertex is taken as underflowed. On a Stieltjes matrix (the intrinsic Delaunay Laplacian's M + tL) the
// triangular solves add terms of one sign only, so u is accurate to rounding relative to itself down to the
// floor. The range spans exp(-990): ~1,000 mean edge lengths on a regular tube, where the unscaled δ_s with
// |∇u|² computed plainly lost the direction (|∇u|² underflowing to zero) at exp(-350), ~380 edge lengths.
constexpr double kHeatPeak = 1e150;
constexpr double kTinySquare = 1e-290;  // |∇u|² below this is recomputed with scaling
constexpr double kHeatFloor = 1e-280;

namespace {
namespace baseline {
#include "cshapes/geodesics/heat_method_simd.inl"
}  // namespace baseline
#pragma GCC push_options
#pragma GCC target("avx2,fma")
#pragma GCC optimize("fp-contract=off")
namespace avx2 {
#include "cshapes/geodesics/heat_method_simd.inl"
}  // namespace avx2
#pragma GCC pop_options
#pragma GCC push_options
#pragma GCC target("avx2,fma,avx512f,avx512vl,avx512dq,avx512bw")
#pragma GCC optimize("fp-contract=off")
namespace avx512 {
#include "cshapes/geodesics/heat_method_simd.inl"
}  // namespace avx512
#pragma GCC pop_options
}  // namespace

struct HeatMethod::Impl {
  Mesh mesh;  // the input, for the fast-marching continuation
  Faces F;    // faces of the triangulation used (the mesh's, or its intrinsic Delaunay flips)
  // Per face and corner c, r_c = ½ J e_c in the face's own plane (e_c the edge opposite c, counter-clockwise,
  // J the rotation by +90°): the face's area times the gradient of the hat function of corner c; stored as
  // g_c = r_c / ρ_f with ρ_f = max |r_c| component, so that the gradient of u ≤ kHeatPeak cannot overflow.
  // 6 values per face (2-D: an intrinsic triangle has no embedding, only a layout from its edge lengths).
  std::vector<double> g;
  std::vector<double> rho;
  SparseMatrix L;              // the cotangent stiffness (operators/cotangent_operator.h)
  Eigen::VectorXd mass;        // the lumped mass
  std::vector<int> component;  // connected component of each vertex; -1 for a vertex in no face
  std::vector<int> pinned;     // one vertex per component: φ = 0 there
  double source_heat = 1;      // right-hand side at a source vertex (see kHeatPeak)
  SparseCholesky heat, poisson;
  // Fast marching on the input mesh, built on first use (only meshes long enough to underflow need it).
  mutable std::once_flag fast_marching_once;
  mutable std::unique_ptr<FastMarching> fast_marching;
  mutable std::atomic<Index> continuations{0};  // source sets continued by fast marching

  // Steps 2-3 for a block of k sources: b = Σ_f Σ_c (r_c · X_f) e_{v_c} with X_f = -∇u / |∇u| per source,
  // then the pinned rows zeroed. u and b are n × k row-major. Faces with a corner below kHeatFloor get X = 0:
  // the Poisson problem then ends there with the natural boundary condition ∇φ·n = X·n, and distances beyond
  // are continued by fast marching (continue_underflowed).
  void divergence(const Block& u, Block& b) const {
    const Index k = u.cols();
    b.setZero(u.rows(), k);
    std::vector<double> x(k), y(k);
    const Index m = F.rows();
    const int *F0 = F.col(0).data(), *F1 = F.col(1).data(), *F2 = F.col(2).data();
    switch (simd_target()) {
      case SimdTarget::Avx512:
        avx512::divergence_faces(m, F0, F1, F2, g.data(), rho.data(), u.data(), b.data(), k, x.data(),
                                 y.data());
        break;
      case SimdTarget::Avx2:
        avx2::divergence_faces(m, F0, F1, F2, g.data(), rho.data(), u.data(), b.data(), k, x.data(),
                               y.data());
        break;
      case SimdTarget::Baseline:
        baseline::divergence_faces(m, F0, F1, F2, g.data(), rho.data(), u.data(), b.data(), k, x.data(),
                                   y.data());
        break;
    }
    for (int p : pinned) b.row(p).setZero();
  }

  // Whether column c of u has a vertex of the component `component_of[c]` below kHeatFloor, per column.
  void find_underflow(const Block& u, const std::vector<int>& component_of,
                      std::vector<char>& underflow) const {
    const Index n = u.rows(), k = u.cols();
    underflow.assign(k, 0);
    for (Index i = 0; i < n; ++i) {
      const double* ui = u.row(i).data();
      const int ci = component[i];
      for (Index c = 0; c < k; ++c)
        underflow[c] |= (ui[c] < kHeatFloor) & (ci >= 0) & (ci == component_of[c]);
    }
  }

  // Replaces the distances of the vertices whose heat underflowed (column `column` of u) by fast marching
  // from the others, seeded with their heat-method distances.
  void continue_underflowed(const Block& u, Index column, Eigen::Ref<Eigen::VectorXd> distances) const {
    std::call_once(fast_marching_once, [&] { fast_marching = std::make_unique<FastMarching>(mesh); });
    const Index n = u.rows();
    std::vector<char> known(n);
    for (Index i = 0; i < n; ++i) known[i] = u(i, column) >= kHeatFloor && std::isfinite(distances[i]);
    Eigen::VectorXd d = distances;
    ++continuations;
    fast_marching->continue_distances(d, known);
    distances = d;
  }
};

namespace {

// Per face f of T and corner c, the scaled hat-function gradient g_c = r_c / ρ_f of HeatMethod::Impl (6 values
// per face, laid out with corner 0 at the origin, corner 1 on the x axis, corner 2 above), and ρ_f. Returns
// the sum of the faces' edge lengths.
double layout_gradients(const IntrinsicTriangulation& T, std::vector<double>& g, std::vector<double>& rho_of) {
  const Index m = T.F.rows();
  g.resize(6 * m);
  rho_of.resize(m);
  double length_sum = 0;
  for (Index f = 0; f < m; ++f) {
    const int v[3] = {T.F(f, 0), T.F(f, 1), T.F(f, 2)};
    const double l01 = T.length(f, 0), l12 = T.length(f, 1), l20 = T.length(f, 2);
    length_sum += l01 + l12 + l20;
    const double x2 = (l01 * l01 + l20 * l20 - l12 * l12) / (2 * l01);
    const double y2 = std::sqrt(std::max(0.0, l20 * l20 - x2 * x2));
    const double area = 0.5 * l01 * y2;
    // Cannot fail after the mollification (every margin is positive); kept as the precondition's check.
    CSHAPES_REQUIRE(area > 0 && std::isfinite(area), "heat method: face ", f, " (vertices ", v[0], ", ", v[1],
                    ", ", v[2], ") of the intrinsic triangulation has zero area (edge lengths ", l01, ", ",
                    l12, ", ", l20, "); please report the mesh");
    const Eigen::Vector2d x[3] = {{0.0, 0.0}, {l01, 0.0}, {x2, y2}};
    Eigen::Vector2d rc[3];
    double rho = 0;
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector2d e = x[(c + 2) % 3] - x[(c + 1) % 3];
      rc[c] = 0.5 * Eigen::Vector2d(-e.y(), e.x());
      rho = std::max(rho, rc[c].cwiseAbs().maxCoeff());
    }
    rho_of[f] = rho;
    for (int c = 0; c < 3; ++c) {
      g[6 * f + 2 * c] = rc[c].x() / rho;
      g[6 * f + 2 * c + 1] = rc[c].y() / rho;
    }
  }
  return length_sum;
}

// The connected components (through faces) of each vertex, −1 for a vertex of zero mass (in no face), and
// the pinned vertex of each component (its first vertex of positive mass).
void pin_components(const Mesh& mesh, const Eigen::VectorXd& mass, std::vector<int>& component,
                    std::vector<int>& pinned) {
  const Index n = mesh.num_vertices();
  Components comp = connected_components(n, mesh_edges(mesh.F));
  component = comp.label;
  std::vector<int> first(comp.count, -1);
  for (Index i = 0; i < n; ++i) {
    if (mass[i] == 0) {
      component[i] = -1;
      continue;
    }
    if (first[comp.label[i]] < 0) first[comp.label[i]] = static_cast<int>(i);
  }
  for (int p : first)
    if (p >= 0) pinned.push_back(p);
}

}  // namespace

HeatMethod::HeatMethod(const Mesh& mesh, const HeatMethodOptions& options)
    : impl_(std::make_unique<Impl>()), num_vertices_(mesh.num_vertices()), options_(options) {
  const Index n = num_vertices_, m = mesh.num_faces();
  CSHAPES_REQUIRE(m > 0, "heat method: the mesh has no faces (a point cloud); use --method graph");
  CSHAPES_REQUIRE(options.time_factor > 0, "heat method: time_factor must be positive, got ",
                  options.time_factor);
  CSHAPES_REQUIRE(options.block_size >= 1, "heat method: block_size must be at least 1");
  Impl& im = *impl_;
  const ProgressFn poll = polls_of(options.progress);
  report_progress_in_parallel(poll, "", 0, 0);
  // Both modes work on mollified lengths (operators/intrinsic_delaunay.h): every triangle, the input's and the
  // flipped ones, has a positive area bounded away from zero, so the Laplacian, the mass matrix and the
  // gradient below are defined on any mesh, degenerate faces included.
  IntrinsicTriangulation T =
      options.intrinsic_delaunay ? intrinsic_delaunay(mesh) : intrinsic_triangulation(mesh);
  report_progress_in_parallel(poll, "", 0, 0);
  flips_ = T.flips;
  skipped_flips_ = T.skipped_flips;
  mollification_ = T.mollification;
  im.F = T.F;
  im.mesh = mesh;
  // L and M: the cotangent operator (operators/cotangent_operator.h), the same matrices as the Laplace–Beltrami
  // eigensolver's; the layout gives the gradients of the hat functions (step 2).
  CotangentOperator op = cotangent_operator(T, n);
  report_progress_in_parallel(poll, "", 0, 0);
  im.L = std::move(op.L);
  im.mass = std::move(op.mass);
  const SparseMatrix& L = im.L;
  const Eigen::VectorXd& mass = im.mass;
  const double length_sum = layout_gradients(T, im.g, im.rho);
  report_progress_in_parallel(poll, "", 0, 0);
  pin_components(mesh, mass, im.component, im.pinned);
  report_progress_in_parallel(poll, "", 0, 0);

  // eq. (5): t = m h², h the mean edge length (over half-edges: on a closed mesh, the mean edge length).
  const double h = length_sum / (3.0 * m);
  time_step_ = options.time_factor * h * h;

  // Vertices in no face get an identity row, so both systems stay definite.
  std::vector<Eigen::Triplet<double>> heat_entries, poisson_entries;
  heat_entries.reserve(L.nonZeros() + n);
  poisson_entries.reserve(L.nonZeros() + n);
  std::vector<char> is_pinned(n, 0);
  for (int p : im.pinned) is_pinned[p] = 1;
  for (Index j = 0; j < n; ++j) {
    if (mass[j] == 0 || is_pinned[j]) poisson_entries.emplace_back(j, j, 1.0);
    if (mass[j] == 0) heat_entries.emplace_back(j, j, 1.0);
    for (SparseMatrix::InnerIterator it(L, j); it; ++it) {
      const Index i = it.row();
      heat_entries.emplace_back(i, j, time_step_ * it.value() + (i == j ? mass[j] : 0.0));
      if (!is_pinned[i] && !is_pinned[j]) poisson_entries.emplace_back(i, j, it.value());
    }
  }
  SparseMatrix heat(n, n), poisson(n, n);
  heat.setFromTriplets(heat_entries.begin(), heat_entries.end());
  // Right-hand side β δ_s with u ≤ β / M_ss (maximum principle on the diagonally dominant M-matrix M + tL)
  // and the forward solve's y_j ≤ L_jj u_j ≤ √A_jj u_j: β = kHeatPeak · min M / max(1, √max A) keeps both
  // below kHeatPeak. The normalised gradient does not depend on β.
  double min_mass = std::numeric_limits<double>::infinity(), max_diagonal = 1;
  for (Index j = 0; j < n; ++j) {
    if (mass[j] > 0) min_mass = std::min(min_mass, mass[j]);
    max_diagonal = std::max(max_diagonal, heat.coeff(j, j));
  }
  im.source_heat = kHeatPeak * min_mass / std::sqrt(max_diagonal);
  poisson.setFromTriplets(poisson_entries.begin(), poisson_entries.end());
  im.heat.factorize(heat, "heat method", "heat-flow (M + tL)", poll);
  im.poisson.factorize(poisson, "heat method", "Poisson (cotangent Laplacian)", poll);
}

HeatMethod::~HeatMethod() = default;

const Eigen::SparseMatrix<double>& HeatMethod::laplacian() const {
  return impl_->L;
}

const Eigen::VectorXd& HeatMethod::mass() const {
  return impl_->mass;
}

Index HeatMethod::fast_marching_continuations() const {
  return impl_->continuations;
}

std::string HeatMethod::backend() {
  return SparseCholesky::backend();
}

Eigen::VectorXd HeatMethod::distances(const std::vector<int>& sources) const {
  const Index n = num_vertices_;
  const Impl& im = *impl_;
  CSHAPES_REQUIRE(!sources.empty(), "heat method: no source vertex given");
  Block U = Block::Zero(n, 1), phi, work;
  for (int s : sources) {
    CSHAPES_REQUIRE(s >= 0 && s < n, "heat method: source vertex ", s, " out of range 0..", n - 1);
    U(s, 0) = im.source_heat;
  }
  report_progress_in_parallel(options_.progress, "", 0, 0);
  im.heat.solve(U, work);
  report_progress_in_parallel(options_.progress, "", 0, 0);
  im.divergence(U, phi);
  im.poisson.solve(phi, work);
  report_progress_in_parallel(options_.progress, "", 0, 0);
  // φ is defined up to a constant per component: make it zero on average over the component's sources.
  const double inf = std::numeric_limits<double>::infinity();
  int max_label = 0;
  for (int c : im.component) max_label = std::max(max_label, c);
  std::vector<double> offset_sum(max_label + 1, 0.0);
  std::vector<int> offset_count(max_label + 1, 0);
  for (int s : sources)
    if (im.component[s] >= 0) offset_sum[im.component[s]] += phi(s, 0), ++offset_count[im.component[s]];
  Eigen::VectorXd d(n);
  for (Index i = 0; i < n; ++i) {
    const int c = im.component[i];
    if (c < 0 || offset_count[c] == 0) {
      d[i] = inf;
      continue;
    }
    d[i] = std::max(0.0, phi(i, 0) - offset_sum[c] / offset_count[c]);
  }
  for (int s : sources) d[s] = 0;
  bool underflow = false;
  for (Index i = 0; i < n && !underflow; ++i) {
    const int c = im.component[i];
    underflow = c >= 0 && offset_count[c] > 0 && U(i, 0) < kHeatFloor;
  }
  if (underflow) im.continue_underflowed(U, 0, d);
  return d;
}

void HeatMethod::for_each_source(
    const std::vector<int>& sources,
    const std::function<void(Index k, const Eigen::Ref<const Eigen::VectorXd>& column)>& sink) const {
  const Index n = num_vertices_;
  const Impl& im = *impl_;
  for (int s : sources)
    CSHAPES_REQUIRE(s >= 0 && s < n, "heat method: source vertex ", s, " out of range 0..", n - 1);
  const Index count = static_cast<Index>(sources.size());
  const Index block = options_.block_size;
  const Index num_blocks = (count + block - 1) / block;
  const double inf = std::numeric_limits<double>::infinity();
  std::atomic<Index> done{0};
  std::exception_ptr error;  // exceptions must not leave an OpenMP region: the first is rethrown after it
#pragma omp parallel
  {
    Block U, phi, work;
    Eigen::MatrixXd columns;
    std::vector<int> source_component;
    std::vector<char> underflow;
#pragma omp for schedule(dynamic, 1)
    for (Index b = 0; b < num_blocks; ++b) {
      bool failed = false;
#pragma omp critical(cshapes_heat_error)
      failed = static_cast<bool>(error);
      if (failed) continue;
      try {
        const Index begin = b * block, k = std::min(block, count - begin);
        U.setZero(n, k);
        source_component.resize(k);
        for (Index j = 0; j < k; ++j) {
          U(sources[begin + j], j) = im.source_heat;
          source_component[j] = im.component[sources[begin + j]];
        }
        // Polls between the steps of a block: on a large mesh one block of sources takes seconds.
        report_progress_in_parallel(options_.progress, "", 0, 0);
        im.heat.solve(U, work);
        report_progress_in_parallel(options_.progress, "", 0, 0);
        im.find_underflow(U, source_component, underflow);
        im.divergence(U, phi);
        im.poisson.solve(phi, work);
        report_progress_in_parallel(options_.progress, "", 0, 0);
        // Transpose to one column per source in tiles of rows (the row-major block is too large for the
        // cache).
        columns.resize(n, k);
        constexpr Index tile = 64;
        for (Index i0 = 0; i0 < n; i0 += tile)
          for (Index j = 0; j < k; ++j)
            for (Index i = i0; i < std::min(n, i0 + tile); ++i) columns(i, j) = phi(i, j);
        for (Index j = 0; j < k; ++j) {
          const int s = sources[begin + j];
          const int c = im.component[s];
          const double phi_s = phi(s, j);
          double* __restrict col = columns.col(j).data();
          for (Index i = 0; i < n; ++i) {
            // |φ - φ(s)| as CGAL's Heat_method_3 does: slightly negative values next to the source are
            // rounding.
            col[i] = (c >= 0 && im.component[i] == c) ? std::abs(col[i] - phi_s) : inf;
          }
          col[s] = 0;
          if (underflow[j]) im.continue_underflowed(U, j, columns.col(j));
          sink(begin + j, columns.col(j));
        }
        Index finished = done += k;
        report_progress_in_parallel(options_.progress, "heat method", static_cast<double>(finished),
                                    static_cast<double>(count));
      } catch (...) {
#pragma omp critical(cshapes_heat_error)
        if (!error) error = std::current_exception();
      }
    }
  }
  if (error) std::rethrow_exception(error);
}

Eigen::MatrixXd HeatMethod::distances_each(const std::vector<int>& sources) const {
  Eigen::MatrixXd D(num_vertices_, static_cast<Index>(sources.size()));
  for_each_source(sources,
                  [&](Index k, const Eigen::Ref<const Eigen::VectorXd>& column) { D.col(k) = column; });
  return D;
}

Eigen::VectorXd heat_method(const Mesh& mesh, const std::vector<int>& sources,
                            const HeatMethodOptions& options) {
  return HeatMethod(mesh, options).distances(sources);
}

std::string heat_method_warning(const Mesh& mesh) {
  const Index n = mesh.num_vertices(), m = mesh.num_faces();
  if (n == 0 || m == 0) return "";
  // A ratio of lengths, measured at unit size: the norms underflow or overflow far from it.
  if (const double scale = power_of_two_unit_scale(mesh.V); scale != 1)
    return heat_method_warning(Mesh{mesh.V * scale, mesh.F});
  double length_sum = 0;
  for (Index f = 0; f < m; ++f)
    for (int c = 0; c < 3; ++c)
      length_sum += (mesh.V.row(mesh.F(f, c)) - mesh.V.row(mesh.F(f, (c + 1) % 3))).norm();
  const double mean_edge = length_sum / (3.0 * m);
  const double diagonal = (mesh.V.colwise().maxCoeff() - mesh.V.colwise().minCoeff()).norm();
  const double fraction = diagonal > 0 ? mean_edge / diagonal : 1.0;
  if (n >= kHeatMethodMinVertices && fraction <= kHeatMethodMaxEdgeFraction) return "";
  std::ostringstream out;
  out.precision(2);
  out << "the heat method is inaccurate on a mesh this coarse (" << n << " vertices, mean edge "
      << 100 * fraction << "% of the bounding-box diagonal; it needs about " << kHeatMethodMinVertices
      << "+ vertices and edges under " << 100 * kHeatMethodMaxEdgeFraction
      << "%): expect errors of 5-30% (a regular tetrahedron is off by up to "
      << "32%); use --method exact or fmm";
  return out.str();
}

}  // namespace cshapes
