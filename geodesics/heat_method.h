// The heat method for geodesic distances (Crane, Weischedel & Wardetzky, "Geodesics in heat", 2013), with
// both sparse systems factorised once and many sources solved together in blocks of right-hand sides.
//
// Per source s (Crane et al. Algorithm 1):
//   1. heat flow, one backward Euler step:       (M + t L) u = δ_s          (eq. 5: t = m·h², h mean edge
//   length)
//   2. normalised gradient per face:             X = -∇u / |∇u|
//   3. Poisson equation:                         L φ = ∇·X                  (integrated divergence, eq. 6)
//   4. distances:                                φ - φ(s)
// L is the cotangent stiffness matrix (positive semi-definite, L·1 = 0), M the lumped (barycentric) mass
// matrix. With intrinsic_delaunay = false this is the "Direct" variant of CGAL's Heat_method_3 (same
// Laplacian, time step, gradient and divergence), so the two agree to solver rounding; with true (the
// default) all four steps run on the intrinsic Delaunay triangulation, as CGAL's "Intrinsic_Delaunay" mode
// does. CGAL solves one source at a time, this class solves `block_size` sources per sparse triangular solve
// and runs blocks in parallel (OpenMP), which is what makes all-pairs distances cheap. The Poisson system is
// made definite by pinning φ = 0 at one vertex per connected component (the divergence sums to zero there, so
// the solution is unchanged up to the constant removed in step 4).
//
// Factorisation (operators/sparse_cholesky.h): SuiteSparse CHOLMOD (simplicial LLᵀ, its fill-reducing ordering)
// when cshapes was built with it, Eigen's SimplicialLLT otherwise. The triangular solves are ours: one pass over the factor per block of
// right-hand sides stored row by row, so each nonzero of L is one k-wide vectorised AXPY (CHOLMOD's own solve
// handles at most 4 columns per pass, and its supernodal solve depends on the BLAS, the reference one here).
// Its cost per source against CGAL's: docs/design.md, "Measured figures behind choices in the code".
//
// Conventions: distances in the mesh's units; vertices in components without a source are +infinity, isolated
// vertices too. Mesh: any triangles, degenerate ones included: both modes work on edge lengths mollified so
// that every triangle holds its inequalities by 1e-6 of the mean edge (operators/intrinsic_delaunay.h), and the
// intrinsic Delaunay flips keep that margin, so every triangle the method uses has a positive area.
// Far from the source: u decays like exp(-d/√t) (faster on irregular triangles: a tube with split faces lost
// its heat at ~220 mean edge lengths), and a plain heat method breaks down where u underflows: the gradient
// of a zero u is undefined (NaN in CGAL's Heat_method_3; a plateau of wrong, finite distances in ours before
// the fix). Here the right-hand side is scaled so that u uses the whole double range (u ≤ 1e250 at the
// source, trusted down to 1e-280, ~1,250 mean edge lengths on a regular tube), the gradient is normalised
// without squaring (no under/overflow), and faces with a corner below 1e-280 get X = 0 (the Poisson problem
// ends there with ∇φ·n = X·n): the distances of the vertices beyond are then continued by fast marching
// (geodesics/fast_marching.h, FastMarching::continue_distances) seeded with the heat-method distances of the
// others. So every distance is finite on a connected mesh; beyond the heat's reach the error is fast
// marching's (first order, ~1-2%). Meshes short enough for the heat never pay for it.
// Coarse meshes: the heat method needs many vertices across the shape (errors measured against exact
// geodesics: regular tetrahedron 17% mean, 32% max; 162-vertex sphere 2.4%; 200-vertex torus 5.9%;
// 130-vertex capsule 4.8%); heat_method_warning says when a mesh is that coarse.
// Cost: factorisation ~O(n^1.5) once; per source two triangular solves (O(nnz(L factor))) plus O(m).
#pragma once

#include <Eigen/SparseCore>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "cshapes/mesh/mesh.h"
#include "cshapes/support/progress.h"

namespace cshapes {

struct HeatMethodOptions {
  double time_factor = 1.0;  // m in t = m·h² (Crane et al. recommend 1; larger is smoother and less accurate)
  // Work on the intrinsic Delaunay triangulation (operators/intrinsic_delaunay.h) instead of the mesh's own
  // triangles: same vertices and surface, non-negative cotangent weights. Essential on meshes with obtuse or
  // needle triangles (TOSCA's: mean error 1.5% instead of 10-25% on cat0). CGAL's "Intrinsic_Delaunay" mode.
  bool intrinsic_delaunay = true;
  int block_size = 32;  // right-hand sides per triangular solve (32-48 is fastest on AVX2 machines)
  // distances_each: called as blocks of sources finish. Also polled (support/progress.h) between the steps
  // of the constructor (the factorisations: operators/sparse_cholesky.h) and of each solve, so a stop is
  // heard within one step, never at the end of all sources.
  ProgressFn progress;
};

class HeatMethod {
 public:
  // Builds L and M and factorises M + tL and the pinned L. Throws on meshes without faces.
  explicit HeatMethod(const Mesh& mesh, const HeatMethodOptions& options = {});
  ~HeatMethod();
  HeatMethod(const HeatMethod&) = delete;
  HeatMethod& operator=(const HeatMethod&) = delete;

  // Distances to the nearest of `sources` (all sources heated together), n values.
  Eigen::VectorXd distances(const std::vector<int>& sources) const;

  // Single-source distances for each source: column k holds the distances from sources[k] (n × k).
  // Blocks of options.block_size sources are solved together, blocks in parallel.
  Eigen::MatrixXd distances_each(const std::vector<int>& sources) const;

  // As distances_each, but hands each finished column to `sink(k, column)` instead of storing n × k doubles;
  // `sink` is called from several threads at once (each k exactly once).
  void for_each_source(
      const std::vector<int>& sources,
      const std::function<void(Index k, const Eigen::Ref<const Eigen::VectorXd>& column)>& sink) const;

  double time_step() const { return time_step_; }
  Index intrinsic_flips() const {
    return flips_;
  }  // edges flipped to reach the intrinsic Delaunay triangulation
  // Non-Delaunay edges left unflipped because their flip would have made a degenerate triangle.
  Index skipped_flips() const { return skipped_flips_; }
  // The length added to every edge so that no triangle is degenerate (0 on a mesh without nearly degenerate
  // triangles; operators/intrinsic_delaunay.h).
  double mollification() const { return mollification_; }
  Index num_vertices() const { return num_vertices_; }
  // L and M as built (operators/cotangent_operator.h: the Laplace–Beltrami eigensolver's matrices on the same
  // triangulation).
  const Eigen::SparseMatrix<double>& laplacian() const;
  const Eigen::VectorXd& mass() const;
  // Source sets so far whose heat underflowed somewhere, their far distances continued by fast marching.
  Index fast_marching_continuations() const;
  // "cholmod" or "eigen-ldlt": which factorisation is used.
  static std::string backend();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  Index num_vertices_ = 0;
  double time_step_ = 0;
  Index flips_ = 0;
  Index skipped_flips_ = 0;
  double mollification_ = 0;
  HeatMethodOptions options_;
};

// One-shot: distances to the nearest of `sources`.
Eigen::VectorXd heat_method(const Mesh& mesh, const std::vector<int>& sources,
                            const HeatMethodOptions& options = {});

// A warning for a user about to run the heat method (ours or CGAL's) on `mesh`, empty when the mesh is fine:
// fewer than kHeatMethodMinVertices vertices, or a mean edge longer than kHeatMethodMaxEdgeFraction of the
// bounding box's diagonal (errors of 5-30% measured there, see above). Points at --method exact|fmm.
constexpr Index kHeatMethodMinVertices = 300;
constexpr double kHeatMethodMaxEdgeFraction = 0.05;
std::string heat_method_warning(const Mesh& mesh);

}  // namespace cshapes
