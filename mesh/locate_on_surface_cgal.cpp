// CGAL side of mesh/locate_on_surface.h: the AABB tree over the mesh's triangles that finds each point's
// closest face. The barycentric coordinates are then those of closest_point_on_triangle on that face, so the
// point, its face and its weights agree by construction.
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <vector>

#include "cshapes/support/error.h"
#include "cshapes/mesh/locate_on_surface.h"

namespace cshapes {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point3 = Kernel::Point_3;
using Triangle3 = Kernel::Triangle_3;
using TriangleIterator = std::vector<Triangle3>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, TriangleIterator>;
using AabbTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

}  // namespace

struct SurfaceLocator::Tree {
  Points V;
  Faces F;
  std::vector<Triangle3> triangles;  // the faces of positive area, in order
  std::vector<int> face_of;          // triangles[k] is face face_of[k] of F
  AabbTree tree;

  Tree(const Points& vertices, const Faces& faces) : V(vertices), F(faces) {
    for (Index f = 0; f < F.rows(); ++f) {
      for (int k = 0; k < 3; ++k) {
        const int v = F(f, k);
        CSHAPES_REQUIRE(v >= 0 && v < V.rows(), "locate_on_surface: face ", f, " has vertex ", v,
                        ", not one of the ", V.rows(), " vertices");
        CSHAPES_REQUIRE(V.row(v).allFinite(), "locate_on_surface: vertex ", v, " of face ", f,
                        " is not finite");
      }
      const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
      if ((b - a).cross(c - a).squaredNorm() == 0) continue;  // zero area: on its edges (see the header)
      triangles.emplace_back(Point3(a.x(), a.y(), a.z()), Point3(b.x(), b.y(), b.z()),
                             Point3(c.x(), c.y(), c.z()));
      face_of.push_back(static_cast<int>(f));
    }
    CSHAPES_REQUIRE(!triangles.empty(), "locate_on_surface: none of the ", F.rows(),
                    " faces has a positive area, so there is no surface to locate points on");
    tree.insert(triangles.cbegin(), triangles.cend());
    tree.build();
    // Built now, not lazily by the first query: locate() queries from several threads.
    tree.accelerate_distance_queries();
  }
};

SurfaceLocator::SurfaceLocator(const Points& V, const Faces& F) : tree_(std::make_unique<Tree>(V, F)) {}
SurfaceLocator::~SurfaceLocator() = default;
SurfaceLocator::SurfaceLocator(SurfaceLocator&&) noexcept = default;
SurfaceLocator& SurfaceLocator::operator=(SurfaceLocator&&) noexcept = default;

SurfaceLocations SurfaceLocator::locate(const Points& P) const {
  for (Index i = 0; i < P.rows(); ++i)
    CSHAPES_REQUIRE(P.row(i).allFinite(), "locate_on_surface: query point ", i, " is not finite");
  const Tree& t = *tree_;
  SurfaceLocations out;
  out.face.resize(P.rows());
  out.barycentric.resize(P.rows(), 3);
  out.closest.resize(P.rows(), 3);
  out.distance.resize(P.rows());
#pragma omp parallel for schedule(static)
  for (Index i = 0; i < P.rows(); ++i) {
    const Eigen::Vector3d p = P.row(i).transpose();
    const auto hit = t.tree.closest_point_and_primitive(Point3(p.x(), p.y(), p.z()));
    const int f = t.face_of[static_cast<size_t>(hit.second - t.triangles.cbegin())];
    Eigen::Vector3d weights;
    const Eigen::Vector3d q =
        closest_point_on_triangle(p, t.V.row(t.F(f, 0)).transpose(), t.V.row(t.F(f, 1)).transpose(),
                                  t.V.row(t.F(f, 2)).transpose(), &weights);
    out.face[i] = f;
    out.barycentric.row(i) = weights.transpose();
    out.closest.row(i) = q.transpose();
    out.distance[i] = (q - p).norm();
  }
  return out;
}

}  // namespace cshapes
