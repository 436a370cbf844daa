// Points located on a triangle mesh: for each query point the closest point of the surface, as the face it
// lies on and its barycentric coordinates there, and per-vertex data (positions, a canonical form, a scalar
// field) evaluated at such locations by barycentric interpolation. What carries a sample of one
// triangulation to another of the same surface: a vertex of the original mesh onto its remesh
// (experiments/pose_invariance.h with --resample), where interpolating the remesh's canonical form gives
// the sample's position in that form.
//
// The closest point is exact (Euclidean, over every face; ties between faces at the same distance, e.g. a
// point nearest a shared edge, go to either). Search: CGAL's AABB tree (locate_on_surface_cgal.cpp, the only
// file that sees CGAL), built once per mesh in O(m log m) for m faces, then O(log m) per point on a typical
// mesh. Faces of zero area are left out of the search (every point of one is on its edges, which are also
// other faces' where the mesh is not a bare segment); a mesh of no face of positive area is refused. The
// mesh need not be manifold, closed or connected.
#pragma once

#include <memory>

#include "cshapes/support/types.h"

namespace cshapes {

// The closest point of triangle (a, b, c) to p (Ericson, "Real-Time Collision Detection", §5.1.5: the
// Voronoi regions of the vertices, then of the edges, then the face). barycentric, when given, receives the
// weights (wa, wb, wc) of the corners: each in [0, 1], summing to 1 (to rounding), the point ≈ wa·a + wb·b +
// wc·c. A degenerate triangle (collinear corners) gives the closest point of its longest side.
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                          Eigen::Vector3d* barycentric = nullptr);

// Where #P query points lie on a mesh (V, F).
struct SurfaceLocations {
  Eigen::VectorXi face;          // #P: row of F holding the closest point
  Eigen::MatrixX3d barycentric;  // #P×3: weights of the corners F(face, 0), F(face, 1), F(face, 2)
  Points closest;                // #P×3: the closest points themselves (the weights applied to V)
  Eigen::VectorXd distance;      // #P: ‖P_i − closest_i‖, in V's units (not squared)
};

// The search structure of one mesh, for locating several sets of points on it. Holds a copy of the mesh's
// triangles; locate() may run from several threads at once.
class SurfaceLocator {
 public:
  // V: #V×3 vertex positions, F: #F×3 vertex indices (0-based). Throws cshapes::Error for an index out of
  // range, a non-finite vertex of a face, or no face of positive area.
  SurfaceLocator(const Points& V, const Faces& F);
  ~SurfaceLocator();
  SurfaceLocator(SurfaceLocator&&) noexcept;
  SurfaceLocator& operator=(SurfaceLocator&&) noexcept;

  // The closest surface point of each row of P (#P×3, finite; throws naming the first row that is not).
  SurfaceLocations locate(const Points& P) const;

 private:
  struct Tree;
  std::unique_ptr<Tree> tree_;
};

// One-shot: SurfaceLocator(V, F).locate(P).
SurfaceLocations locate_on_surface(const Points& V, const Faces& F, const Points& P);

// Per-vertex data evaluated at the locations: row i = Σ_k barycentric(i, k) · values.row(F(face_i, k)).
// values: #V×d (d columns of anything defined per vertex of the mesh the locations are on: V itself gives
// back `closest`, a canonical form of the mesh gives the points' positions in it); F: that mesh's faces.
// Returns #P×d. A corner of weight 0 is left out of the sum, so a non-finite value there (a vertex a form
// dropped) does not reach a point on the opposite edge; a non-finite value of weight > 0 makes the row
// non-finite. Throws when a face index is out of F's range or a vertex index out of values' rows.
Eigen::MatrixXd interpolate_on_surface(const Faces& F, const SurfaceLocations& at,
                                       const Eigen::Ref<const Eigen::MatrixXd>& values);

}  // namespace cshapes
