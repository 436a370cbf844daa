// Fast marching on triangulated domains (Kimmel & Sethian, PNAS 1998): first-order geodesic distances from
// a set of source vertices, propagated vertex by vertex in increasing distance (Dijkstra order) with a
// planar-wavefront update inside each triangle.
//
// Update (Kimmel & Sethian eq. 5-6, written here with the gradient): in a triangle C, P, Q with P, Q already
// accepted, the distance is taken linear with a unit gradient n: T(x) = T_C + n·(x - C). Solving
// n·(P - C) = T_P - T_C, n·(Q - C) = T_Q - T_C, |n| = 1 for T_C is a quadratic; the root is accepted only
// when the characteristic reaching C comes from inside the triangle (-n in the cone spanned by P - C and Q -
// C), otherwise T_C = min(T_P + |CP|, T_Q + |CQ|) (Dijkstra along the edges).
//
// Obtuse triangles: at an obtuse corner C the cone of characteristics that can reach C through the triangle
// misses directions the wavefront really comes from, and the edge fallback is not first-order accurate. As in
// Kimmel & Sethian §"obtuse triangles", the neighbouring triangles are unfolded into the plane of C, P, Q
// (across PQ, then across whichever edge the cone of C crosses) until a vertex D falls inside the section of
// directions making acute angles with both CP and CQ; the triangle is then split by the virtual edge CD
// (its length measured in the unfolding) into two acute ones, C P D and C D Q, used for updates of C.
// The unfolding is precomputed once per mesh (FastMarching), so repeated sources cost only the marching.
//
// Conventions: distances in the mesh's units; vertices not reachable from any source (other components,
// isolated vertices) get +infinity. Sources get 0. Non-manifold edges are allowed (every face is used).
// Complexity: O(n log n) per source set (binary heap), plus O(m) precomputation for m faces.
// Accuracy: first order in the edge length h; on smooth meshes mean relative errors are about 0.5-2%.
#pragma once

#include <vector>

#include "cshapes/mesh/mesh.h"

namespace cshapes {

struct FastMarchingOptions {
  bool unfold_obtuse =
      true;  // split obtuse corners by unfolding (Kimmel & Sethian); false: edge fallback only
  int max_unfold_steps =
      12;  // triangles crossed at most while searching the split vertex of an obtuse corner
};

// Precomputed update stencils of a mesh; distances() may be called concurrently from several threads.
class FastMarching {
 public:
  explicit FastMarching(const Mesh& mesh, const FastMarchingOptions& options = {});

  // Distances from the nearest source to each vertex (n values). Thread-safe.
  Eigen::VectorXd distances(const std::vector<int>& sources) const;

  // As above, writing into `out` (resized to n) to reuse its storage across calls.
  void distances(const std::vector<int>& sources, Eigen::VectorXd& out) const;

  // Continues a partial distance field (n values): vertices with known[i] != 0 keep dist[i] and act as an
  // initial front (marched in increasing order of their values); every other vertex is computed by marching
  // from them, +infinity where no known vertex reaches. Known values must be finite. Thread-safe.
  // The heat method uses it where its heat underflowed (geodesics/heat_method.h).
  void continue_distances(Eigen::VectorXd& dist, const std::vector<char>& known) const;

  Index num_vertices() const { return num_vertices_; }
  // Obtuse corners found, and how many of them were split by unfolding (the others fall back to edges).
  Index obtuse_corners() const { return obtuse_corners_; }
  Index split_corners() const { return split_corners_; }

  // One triangle update of `target` from the just-accepted vertex and one other vertex, in the plane of the
  // triangle with `target` at the origin: p = position of the accepted vertex, q = of the other one.
  struct Stencil {
    int target;
    int other;                          // -1: an edge update only (T_target <= T_accepted + |p|)
    double p_len, q_len;                // |p|, |q|
    double inv00, inv01, inv10, inv11;  // inverse of the 2×2 matrix with rows p and q
  };

 private:
  Index num_vertices_ = 0;
  Index obtuse_corners_ = 0;
  Index split_corners_ = 0;
  // Stencils triggered when vertex i is accepted: stencils_[offsets_[i] .. offsets_[i+1]).
  std::vector<int> offsets_;
  std::vector<Stencil> stencils_;
};

// One-shot: builds the stencils and marches once.
Eigen::VectorXd fast_marching(const Mesh& mesh, const std::vector<int>& sources,
                              const FastMarchingOptions& options = {});

}  // namespace cshapes
