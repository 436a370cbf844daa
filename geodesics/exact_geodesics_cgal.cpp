// CGAL::Surface_mesh_shortest_path behind geodesics/geodesics_cgal.h.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_shortest_path.h>

#include "cshapes/support/error.h"
#include "cshapes/geodesics/geodesics_cgal.h"
#include "cshapes/mesh/surface_mesh_cgal.h"

namespace cshapes {

namespace {

using cgal::Kernel;
using cgal::SurfaceMesh;
using cgal::VertexIndex;
using Traits = CGAL::Surface_mesh_shortest_path_traits<Kernel, SurfaceMesh>;
using ShortestPath = CGAL::Surface_mesh_shortest_path<Traits>;


}  // namespace

Eigen::VectorXd exact_geodesics(const Mesh& mesh, const std::vector<int>& sources) {
  const Index n = mesh.num_vertices();
  CSHAPES_REQUIRE(mesh.num_faces() > 0, "exact geodesics: the mesh has no faces");
  CSHAPES_REQUIRE(!sources.empty(), "exact geodesics: no source vertex given");
  for (int s : sources)
    CSHAPES_REQUIRE(s >= 0 && s < n, "exact geodesics: source ", s, " out of range 0..", n - 1);
  SurfaceMesh sm = cgal::to_surface_mesh(mesh, "exact geodesics");
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
