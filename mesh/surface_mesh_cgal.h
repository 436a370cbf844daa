// Private to the CGAL translation units (mesh/*_cgal.cpp, geodesics/*_cgal.cpp), the only files that may include CGAL: the Surface_mesh
// type they share and the one conversion from cshapes::Mesh to it.
#pragma once

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

#include <string>

#include "cshapes/support/error.h"
#include "cshapes/mesh/mesh.h"

namespace cshapes::cgal {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point3 = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point3>;
using VertexIndex = SurfaceMesh::Vertex_index;

// A halfedge mesh with the same vertex indices as `mesh`. Throws, naming `what` and the face, where a face
// cannot be added (a non-manifold edge or inconsistent orientation).
inline SurfaceMesh to_surface_mesh(const Mesh& mesh, const std::string& what) {
  SurfaceMesh sm;
  sm.reserve(static_cast<SurfaceMesh::size_type>(mesh.num_vertices()),
             static_cast<SurfaceMesh::size_type>(3 * mesh.num_faces() / 2),
             static_cast<SurfaceMesh::size_type>(mesh.num_faces()));
  for (Index i = 0; i < mesh.num_vertices(); ++i) sm.add_vertex(Point3(mesh.V(i, 0), mesh.V(i, 1), mesh.V(i, 2)));
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    auto face = sm.add_face(VertexIndex(mesh.F(f, 0)), VertexIndex(mesh.F(f, 1)), VertexIndex(mesh.F(f, 2)));
    CSHAPES_REQUIRE(face != SurfaceMesh::null_face(), what, ": face ", f,
                    " cannot be added to a halfedge mesh (non-manifold edge or inconsistent orientation)");
  }
  return sm;
}

}  // namespace cshapes::cgal
