// CGAL::Surface_mesh_shortest_path behind core/geodesics_cgal.h.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_shortest_path.h>

#include "core/error.h"
#include "core/geodesics_cgal.h"

namespace cshapes {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
using VertexIndex = SurfaceMesh::Vertex_index;
using Traits = CGAL::Surface_mesh_shortest_path_traits<Kernel, SurfaceMesh>;
using ShortestPath = CGAL::Surface_mesh_shortest_path<Traits>;

SurfaceMesh to_surface_mesh(const Mesh& mesh) {
  SurfaceMesh sm;
  for (Index i = 0; i < mesh.num_vertices(); ++i)
    sm.add_vertex(Kernel::Point_3(mesh.V(i, 0), mesh.V(i, 1), mesh.V(i, 2)));
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    auto face = sm.add_face(VertexIndex(mesh.F(f, 0)), VertexIndex(mesh.F(f, 1)), VertexIndex(mesh.F(f, 2)));
    CSHAPES_REQUIRE(face != SurfaceMesh::null_face(), "exact geodesics: face ", f,
                    " cannot be added to a halfedge mesh (non-manifold edge or inconsistent orientation)");
  }
  return sm;
}

}  // namespace

Eigen::VectorXd exact_geodesics(const Mesh& mesh, const std::vector<int>& sources) {
  const Index n = mesh.num_vertices();
  CSHAPES_REQUIRE(mesh.num_faces() > 0, "exact geodesics: the mesh has no faces");
  CSHAPES_REQUIRE(!sources.empty(), "exact geodesics: no source vertex given");
  for (int s : sources)
    CSHAPES_REQUIRE(s >= 0 && s < n, "exact geodesics: source ", s, " out of range 0..", n - 1);
  SurfaceMesh sm = to_surface_mesh(mesh);
  Eigen::VectorXd d(n);
  try {
    ShortestPath paths(sm);
    for (int s : sources) paths.add_source_point(VertexIndex(s));
    paths.build_sequence_tree();
    for (Index i = 0; i < n; ++i) {
      double di =
          paths.shortest_distance_to_source_points(VertexIndex(static_cast<SurfaceMesh::size_type>(i))).first;
      // CGAL reports unreachable vertices as -1.
      d[i] = di < 0 ? std::numeric_limits<double>::infinity() : di;
    }
  } catch (const std::exception& e) {
    fail("exact geodesics (CGAL) failed (", e.what(), ")");
  }
  for (int s : sources) d[s] = 0;
  return d;
}

}  // namespace cshapes
