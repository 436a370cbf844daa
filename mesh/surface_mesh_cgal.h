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
    const VertexIndex corner[3] = {VertexIndex(mesh.F(f, 0)), VertexIndex(mesh.F(f, 1)), VertexIndex(mesh.F(f, 2))};
    if (sm.add_face(corner[0], corner[1], corner[2]) != SurfaceMesh::null_face()) continue;
    // Why it was refused: an edge that already has a face on this side, or else a corner whose faces would
    // form two separate fans (parts that touch at one vertex, such as two cones joined at their tips).
    for (int k = 0; k < 3; ++k) {
      const auto h = sm.halfedge(corner[k], corner[(k + 1) % 3]);
      if (h != SurfaceMesh::null_halfedge() && !sm.is_border(h))
        fail(what, ": face ", f, " cannot be added to a halfedge mesh: its edge (", mesh.F(f, k), ", ",
             mesh.F(f, (k + 1) % 3), ") already has a face on the same side (a non-manifold edge, or a "
             "neighbour of opposite orientation)");
    }
    for (int k = 0; k < 3; ++k) {
      const VertexIndex v = corner[k];
      const bool in_edge_new = sm.halfedge(corner[(k + 2) % 3], v) == SurfaceMesh::null_halfedge() &&
                               sm.halfedge(v, corner[(k + 2) % 3]) == SurfaceMesh::null_halfedge();
      const bool out_edge_new = sm.halfedge(v, corner[(k + 1) % 3]) == SurfaceMesh::null_halfedge() &&
                                sm.halfedge(corner[(k + 1) % 3], v) == SurfaceMesh::null_halfedge();
      if (!sm.is_isolated(v) && in_edge_new && out_edge_new)
        fail(what, ": face ", f, " cannot be added to a halfedge mesh: at vertex ", mesh.F(f, k),
             " it would start a second fan of faces (a non-manifold vertex: parts that touch at one point)");
    }
    fail(what, ": face ", f, " cannot be added to a halfedge mesh (a non-manifold vertex or edge at its corners ",
         mesh.F(f, 0), ", ", mesh.F(f, 1), ", ", mesh.F(f, 2), ")");
  }
  return sm;
}

}  // namespace cshapes::cgal
