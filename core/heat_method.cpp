#include "core/heat_method.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>

#include "core/error.h"
#include "core/intrinsic_delaunay.h"

#ifdef CSHAPES_HAVE_CHOLMOD
#include <cholmod.h>
#endif

namespace cshapes {

namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;

// A symmetric positive definite matrix, factorised once; solve() may run concurrently from several threads.
class SparseCholesky {
 public:
  SparseCholesky() = default;
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;
  ~SparseCholesky() {
#ifdef CSHAPES_HAVE_CHOLMOD
    if (factor_) cholmod_free_factor(&factor_, &common_);
    if (started_) cholmod_finish(&common_);
#endif
  }

  // `what` names the matrix in error messages. A is symmetric with both triangles stored.
  void factorize(const SparseMatrix& A, const std::string& what) {
    n_ = A.rows();
#ifdef CSHAPES_HAVE_CHOLMOD
    cholmod_start(&common_);
    started_ = true;
    common_.print = 0;
    common_.error_handler = nullptr;
    SparseMatrix lower = A.triangularView<Eigen::Lower>();
    lower.makeCompressed();
    cholmod_sparse view = sparse_view(lower);
    factor_ = cholmod_analyze(&view, &common_);
    CSHAPES_REQUIRE(factor_ && common_.status == CHOLMOD_OK, "heat method: CHOLMOD could not analyse the ", what,
                    " matrix (status ", common_.status, ")");
    int ok = cholmod_factorize(&view, factor_, &common_);
    CSHAPES_REQUIRE(ok && common_.status == CHOLMOD_OK, "heat method: the ", what,
                    " matrix is not positive definite (CHOLMOD status ", common_.status,
                    "); degenerate or inverted triangles?");
#else
    ldlt_.compute(A);
    CSHAPES_REQUIRE(ldlt_.info() == Eigen::Success, "heat method: the ", what,
                    " matrix could not be factorised; degenerate triangles?");
#endif
  }

  // B (n × k) is overwritten by A⁻¹ B.
  void solve(Eigen::MatrixXd& B) const {
#ifdef CSHAPES_HAVE_CHOLMOD
    // Each call has its own cholmod_common: CHOLMOD keeps workspace and status there.
    cholmod_common common;
    cholmod_start(&common);
    common.print = 0;
    common.error_handler = nullptr;
    cholmod_dense rhs;
    rhs.nrow = B.rows();
    rhs.ncol = B.cols();
    rhs.nzmax = B.size();
    rhs.d = B.rows();
    rhs.x = B.data();
    rhs.z = nullptr;
    rhs.xtype = CHOLMOD_REAL;
    rhs.dtype = CHOLMOD_DOUBLE;
    cholmod_dense *X = nullptr, *Y = nullptr, *E = nullptr;
    int ok = cholmod_solve2(CHOLMOD_A, factor_, &rhs, nullptr, &X, nullptr, &Y, &E, &common);
    if (ok) B = Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(X->x), B.rows(), B.cols());
    cholmod_free_dense(&X, &common);
    cholmod_free_dense(&Y, &common);
    cholmod_free_dense(&E, &common);
    cholmod_finish(&common);
    CSHAPES_REQUIRE(ok, "heat method: CHOLMOD solve failed (status ", common.status, ")");
#else
    B = ldlt_.solve(B);
#endif
  }

  static std::string backend() {
#ifdef CSHAPES_HAVE_CHOLMOD
    return "cholmod";
#else
    return "eigen-ldlt";
#endif
  }

 private:
  Index n_ = 0;
#ifdef CSHAPES_HAVE_CHOLMOD
  static cholmod_sparse sparse_view(SparseMatrix& lower) {
    cholmod_sparse s;
    s.nrow = lower.rows();
    s.ncol = lower.cols();
    s.nzmax = lower.nonZeros();
    s.p = lower.outerIndexPtr();
    s.i = lower.innerIndexPtr();
    s.nz = nullptr;
    s.x = lower.valuePtr();
    s.z = nullptr;
    s.stype = -1;  // symmetric, lower triangle stored
    s.itype = CHOLMOD_INT;
    s.xtype = CHOLMOD_REAL;
    s.dtype = CHOLMOD_DOUBLE;
    s.sorted = 1;
    s.packed = 1;
    return s;
  }
  mutable cholmod_common common_;
  bool started_ = false;
  cholmod_factor* factor_ = nullptr;
#else
  Eigen::SimplicialLDLT<SparseMatrix> ldlt_;
#endif
};

}  // namespace

struct HeatMethod::Impl {
  Faces F;  // faces of the triangulation used (the mesh's, or its intrinsic Delaunay flips)
  // Per face and corner c, r_c = ½ J e_c in the face's own plane (e_c the edge opposite c, counter-clockwise,
  // J the rotation by +90°): the face's area times the gradient of the hat function of corner c.
  // 6 values per face (2-D: an intrinsic triangle has no embedding, only a layout from its edge lengths).
  std::vector<double> r;
  std::vector<int> component;  // connected component of each vertex; -1 for a vertex in no face
  std::vector<int> pinned;     // one vertex per component: φ = 0 there
  SparseCholesky heat, poisson;

  // Steps 2-3 for one column: b = Σ_f Σ_c (r_c · X_f) e_{v_c}, X_f = -∇u / |∇u|, then pinned entries zeroed.
  void divergence(const double* u, double* b, Index n) const {
    std::fill(b, b + n, 0.0);
    const Index m = F.rows();
    for (Index f = 0; f < m; ++f) {
      const double* rf = &r[6 * f];
      const int v0 = F(f, 0), v1 = F(f, 1), v2 = F(f, 2);
      const double u0 = u[v0], u1 = u[v1], u2 = u[v2];
      double gx = u0 * rf[0] + u1 * rf[2] + u2 * rf[4];
      double gy = u0 * rf[1] + u1 * rf[3] + u2 * rf[5];
      const double norm = std::sqrt(gx * gx + gy * gy);
      if (!(norm > 0)) continue;  // u underflowed to a constant here: no direction to follow
      gx /= -norm, gy /= -norm;
      b[v0] += rf[0] * gx + rf[1] * gy;
      b[v1] += rf[2] * gx + rf[3] * gy;
      b[v2] += rf[4] * gx + rf[5] * gy;
    }
    for (int p : pinned) b[p] = 0;
  }
};

HeatMethod::HeatMethod(const Mesh& mesh, const HeatMethodOptions& options)
    : impl_(std::make_unique<Impl>()), num_vertices_(mesh.num_vertices()), options_(options) {
  const Index n = num_vertices_, m = mesh.num_faces();
  CSHAPES_REQUIRE(m > 0, "heat method: the mesh has no faces (a point cloud); use --method graph");
  CSHAPES_REQUIRE(options.time_factor > 0, "heat method: time_factor must be positive, got ", options.time_factor);
  CSHAPES_REQUIRE(options.block_size >= 1, "heat method: block_size must be at least 1");
  Impl& im = *impl_;
  IntrinsicTriangulation T = options.intrinsic_delaunay ? intrinsic_delaunay(mesh) : intrinsic_triangulation(mesh);
  flips_ = T.flips;
  im.F = T.F;
  im.r.resize(6 * m);
  std::vector<Eigen::Triplet<double>> stiffness;
  stiffness.reserve(9 * m);
  Eigen::VectorXd mass = Eigen::VectorXd::Zero(n);
  double length_sum = 0;
  for (Index f = 0; f < m; ++f) {
    const int v[3] = {T.F(f, 0), T.F(f, 1), T.F(f, 2)};
    // Layout: corner 0 at the origin, corner 1 on the x axis, corner 2 above.
    const double l01 = T.length(f, 0), l12 = T.length(f, 1), l20 = T.length(f, 2);
    length_sum += l01 + l12 + l20;
    const double x2 = (l01 * l01 + l20 * l20 - l12 * l12) / (2 * l01);
    const double y2 = std::sqrt(std::max(0.0, l20 * l20 - x2 * x2));
    const double area = 0.5 * l01 * y2;
    CSHAPES_REQUIRE(area > 0 && std::isfinite(area), "heat method: face ", f, " (vertices ", v[0], ", ", v[1], ", ",
                    v[2], ") has zero area; the heat method needs non-degenerate triangles");
    const Eigen::Vector2d x[3] = {{0.0, 0.0}, {l01, 0.0}, {x2, y2}};
    Eigen::Vector2d rc[3];
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector2d e = x[(c + 2) % 3] - x[(c + 1) % 3];
      rc[c] = 0.5 * Eigen::Vector2d(-e.y(), e.x());
      im.r[6 * f + 2 * c] = rc[c].x();
      im.r[6 * f + 2 * c + 1] = rc[c].y();
      mass[v[c]] += area / 3;  // lumped (barycentric) mass: a third of each incident triangle
    }
    // L_ab = Σ_f A_f ∇ψ_a·∇ψ_b = Σ_f r_a·r_b / A_f: the cotangent Laplacian.
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) stiffness.emplace_back(v[a], v[b], rc[a].dot(rc[b]) / area);
  }
  SparseMatrix L(n, n);
  L.setFromTriplets(stiffness.begin(), stiffness.end());

  // Components (through faces) and the pinned vertex of each.
  Components comp = connected_components(n, mesh_edges(mesh.F));
  im.component = comp.label;
  std::vector<int> first(comp.count, -1);
  for (Index i = 0; i < n; ++i) {
    if (mass[i] == 0) {
      im.component[i] = -1;
      continue;
    }
    if (first[comp.label[i]] < 0) first[comp.label[i]] = static_cast<int>(i);
  }
  for (int p : first)
    if (p >= 0) im.pinned.push_back(p);

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
  poisson.setFromTriplets(poisson_entries.begin(), poisson_entries.end());
  im.heat.factorize(heat, "heat-flow (M + tL)");
  im.poisson.factorize(poisson, "Poisson (cotangent Laplacian)");
}

HeatMethod::~HeatMethod() = default;

std::string HeatMethod::backend() const { return SparseCholesky::backend(); }

Eigen::VectorXd HeatMethod::distances(const std::vector<int>& sources) const {
  const Index n = num_vertices_;
  const Impl& im = *impl_;
  CSHAPES_REQUIRE(!sources.empty(), "heat method: no source vertex given");
  Eigen::MatrixXd U = Eigen::MatrixXd::Zero(n, 1);
  for (int s : sources) {
    CSHAPES_REQUIRE(s >= 0 && s < n, "heat method: source vertex ", s, " out of range 0..", n - 1);
    U(s, 0) = 1;
  }
  im.heat.solve(U);
  Eigen::MatrixXd phi(n, 1);
  im.divergence(U.data(), phi.data(), n);
  im.poisson.solve(phi);
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
    Eigen::MatrixXd U, phi;
    Eigen::VectorXd column(n);
#pragma omp for schedule(dynamic, 1)
    for (Index b = 0; b < num_blocks; ++b) {
      bool failed = false;
#pragma omp critical(cshapes_heat_error)
      failed = static_cast<bool>(error);
      if (failed) continue;
      try {
      const Index begin = b * block, k = std::min(block, count - begin);
      U.setZero(n, k);
      phi.resize(n, k);
      for (Index j = 0; j < k; ++j) U(sources[begin + j], j) = 1;
      im.heat.solve(U);
      for (Index j = 0; j < k; ++j) im.divergence(U.col(j).data(), phi.col(j).data(), n);
      im.poisson.solve(phi);
      for (Index j = 0; j < k; ++j) {
        const int s = sources[begin + j];
        const int c = im.component[s];
        const double phi_s = phi(s, j);
        for (Index i = 0; i < n; ++i) {
          // |φ - φ(s)| as CGAL's Heat_method_3 does: slightly negative values next to the source are rounding.
          column[i] = (c >= 0 && im.component[i] == c) ? std::abs(phi(i, j) - phi_s) : inf;
        }
        column[s] = 0;
        sink(begin + j, column);
      }
      Index finished = done += k;
      if (options_.progress) {
#pragma omp critical(cshapes_progress)
        options_.progress("heat method", static_cast<double>(finished), static_cast<double>(count));
      }
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
  for_each_source(sources, [&](Index k, const Eigen::Ref<const Eigen::VectorXd>& column) { D.col(k) = column; });
  return D;
}

Eigen::VectorXd heat_method(const Mesh& mesh, const std::vector<int>& sources, const HeatMethodOptions& options) {
  return HeatMethod(mesh, options).distances(sources);
}

}  // namespace cshapes
