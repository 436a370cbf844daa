// A nanoflann KD-tree over the rows of an n×3 Points matrix, read in place through an adaptor (no copy into
// nanoflann's own format): the one adaptor for the kNN graph (mesh/knn_graph.h) and the multiresolution
// Coulomb prolongation (canon/coulomb_multiresolution.h). ICP's nearest neighbours have their own tree
// (matching/nearest_neighbors.h: SIMD-scanned leaves).
#pragma once

#include <cstddef>
#include <cstdint>
#include <nanoflann.hpp>

#include "cshapes/support/types.h"

namespace cshapes {

struct PointsKdAdaptor {
  const Points& P;  // must outlive the tree
  size_t kdtree_get_point_count() const { return static_cast<size_t>(P.rows()); }
  double kdtree_get_pt(size_t i, size_t dim) const {
    return P(static_cast<Index>(i), static_cast<Index>(dim));
  }
  template <class BoundingBox>
  bool kdtree_get_bbox(BoundingBox&) const {
    return false;  // let nanoflann compute it
  }
};

using PointsKdTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointsKdAdaptor, double, uint32_t>,
                                        PointsKdAdaptor, 3, uint32_t>;

}  // namespace cshapes
