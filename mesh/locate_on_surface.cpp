// The parts of mesh/locate_on_surface.h that need no CGAL: the point-triangle kernel and the interpolation.
// The AABB tree is in locate_on_surface_cgal.cpp.
#include "cshapes/mesh/locate_on_surface.h"

#include <algorithm>
#include <cmath>

#include "cshapes/support/error.h"

namespace cshapes {

namespace {

// The closest point of segment [a, b] to p and its parameter t (the point is a + t (b − a)).
Eigen::Vector3d closest_point_on_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                         const Eigen::Vector3d& b, double* t) {
  const Eigen::Vector3d ab = b - a;
  const double length2 = ab.squaredNorm();
  *t = length2 > 0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return a + *t * ab;
}

// A triangle whose corners are collinear: the closest point of its longest side (which covers the others).
Eigen::Vector3d closest_point_on_degenerate(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                            const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                            Eigen::Vector3d* barycentric) {
  const double ab = (b - a).squaredNorm(), bc = (c - b).squaredNorm(), ca = (a - c).squaredNorm();
  double t = 0;
  Eigen::Vector3d w;
  Eigen::Vector3d q;
  if (ab >= bc && ab >= ca) {
    q = closest_point_on_segment(p, a, b, &t);
    w << 1 - t, t, 0;
  } else if (bc >= ca) {
    q = closest_point_on_segment(p, b, c, &t);
    w << 0, 1 - t, t;
  } else {
    q = closest_point_on_segment(p, c, a, &t);
    w << t, 0, 1 - t;
  }
  if (barycentric) *barycentric = w;
  return q;
}

}  // namespace

Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                          Eigen::Vector3d* barycentric) {
  auto weights = [barycentric](double wa, double wb, double wc) {
    if (barycentric) *barycentric << wa, wb, wc;
  };
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) {
    weights(1, 0, 0);
    return a;
  }
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) {
    weights(0, 1, 0);
    return b;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double t = d1 / (d1 - d3);
    weights(1 - t, t, 0);
    return a + t * ab;
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) {
    weights(0, 0, 1);
    return c;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double t = d2 / (d2 - d6);
    weights(1 - t, 0, t);
    return a + t * ac;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    weights(0, 1 - t, t);
    return b + t * (c - b);
  }
  // va + vb + vc = |ab × ac|²: zero (or lost to rounding) for collinear corners, whose face region is empty.
  if (!(va + vb + vc > 0)) return closest_point_on_degenerate(p, a, b, c, barycentric);
  const double denom = 1.0 / (va + vb + vc);
  if (barycentric) {  // clamped into the triangle: at its sides rounding may leave a weight of −1e-17
    const double wb = std::clamp(vb * denom, 0.0, 1.0), wc = std::clamp(vc * denom, 0.0, 1.0 - wb);
    weights(1 - wb - wc, wb, wc);
  }
  return a + ab * (vb * denom) + ac * (vc * denom);
}

SurfaceLocations locate_on_surface(const Points& V, const Faces& F, const Points& P) {
  return SurfaceLocator(V, F).locate(P);
}

Eigen::MatrixXd interpolate_on_surface(const Faces& F, const SurfaceLocations& at,
                                       const Eigen::Ref<const Eigen::MatrixXd>& values) {
  const Index count = at.face.size();
  CSHAPES_REQUIRE(at.barycentric.rows() == count, "interpolate_on_surface: ", count, " faces but ",
                  at.barycentric.rows(), " barycentric rows");
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(count, values.cols());
  for (Index i = 0; i < count; ++i) {
    const int f = at.face[i];
    CSHAPES_REQUIRE(f >= 0 && f < F.rows(), "interpolate_on_surface: location ", i, " is on face ", f,
                    ", not a face of the ", F.rows(), " given");
    for (int k = 0; k < 3; ++k) {
      const int v = F(f, k);
      CSHAPES_REQUIRE(v >= 0 && v < values.rows(), "interpolate_on_surface: face ", f, " has vertex ", v,
                      ", but values has ", values.rows(), " rows");
      const double w = at.barycentric(i, k);
      if (w != 0) out.row(i) += w * values.row(v);
    }
  }
  return out;
}

}  // namespace cshapes
