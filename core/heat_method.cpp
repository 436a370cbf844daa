#include "core/heat_method.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>

#include "core/error.h"

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
  Faces F;
  // Per face and corner c, r_c = ½ N × e_c (e_c the edge opposite c, counter-clockwise): the face's area
  // times the gradient of the hat function of its corner c. 9 values per face.
  std::vector<double> r;
  std::vector<int> component;  // connected component of each vertex; -1 for a vertex in no face
  std::vector<int> pinned;     // one vertex per component: φ = 0 there
  SparseCholesky heat, poisson;

  // Steps 2-3 for one column: b = Σ_f Σ_c (r_c · X_f) e_{v_c}, X_f = -∇u / |∇u|, then pinned entries zeroed.
  void divergence(const double* u, double* b, Index n) const {
    std::fill(b, b + n, 0.0);
    const Index m = F.rows();
    for (Index f = 0; f < m; ++f) {
      const double* rf = &r[9 * f];
      const double u0 = u[F(f, 0)], u1 = u[F(f, 1)], u2 = u[F(f, 2)];
      double gx = u0 * rf[0] + u1 * rf[3] + u2 * rf[6];
      double gy = u0 * rf[1] + u1 * rf[4] + u2 * rf[7];
      double gz = u0 * rf[2] + u1 * rf[5] + u2 * rf[8];
      const double norm = std::sqrt(gx * gx + gy * gy + gz * gz);
      if (!(norm > 0)) continue;  // u underflowed to a constant here: no direction to follow
      gx /= -norm, gy /= -norm, gz /= -norm;
      for (int c = 0; c < 3; ++c) b[F(f, c)] += rf[3 * c] * gx + rf[3 * c + 1] * gy + rf[3 * c + 2] * gz;
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
  im.F = mesh.F;
  im.r.resize(9 * m);
  std::vector<Eigen::Triplet<double>> stiffness;
  stiffness.reserve(9 * m);
  Eigen::VectorXd mass = Eigen::VectorXd::Zero(n);
  for (Index f = 0; f < m; ++f) {
    int v[3];
    for (int c = 0; c < 3; ++c) {
      v[c] = mesh.F(f, c);
      CSHAPES_REQUIRE(v[c] >= 0 && v[c] < n, "heat method: face ", f, " has vertex index ", v[c], " outside 0..",
                      n - 1);
    }
    Eigen::Vector3d x[3] = {mesh.V.row(v[0]), mesh.V.row(v[1]), mesh.V.row(v[2])};
    Eigen::Vector3d normal = (x[1] - x[0]).cross(x[2] - x[0]);
    const double twice_area = normal.norm();
    CSHAPES_REQUIRE(twice_area > 0, "heat method: face ", f, " (vertices ", v[0], ", ", v[1], ", ", v[2],
                    ") has zero area; the heat method needs non-degenerate triangles");
    normal /= twice_area;
    Eigen::Vector3d rc[3];
    for (int c = 0; c < 3; ++c) {
      rc[c] = 0.5 * normal.cross(x[(c + 2) % 3] - x[(c + 1) % 3]);
      for (int d = 0; d < 3; ++d) im.r[9 * f + 3 * c + d] = rc[c][d];
      mass[v[c]] += twice_area / 6;  // eq. (lumped mass): a third of each incident triangle
    }
    // L_ab = Σ_f A_f ∇ψ_a·∇ψ_b = Σ_f r_a·r_b / A_f: the cotangent Laplacian.
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) stiffness.emplace_back(v[a], v[b], rc[a].dot(rc[b]) / (0.5 * twice_area));
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

  // eq. (5): t = m h², h the mean edge length.
  Edges E = mesh_edges(mesh.F);
  const double h = edge_lengths(mesh.V, E).mean();
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
