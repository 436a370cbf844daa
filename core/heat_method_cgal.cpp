// CGAL::Heat_method_3 behind core/geodesics_cgal.h.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Heat_method_3/Surface_mesh_geodesic_distances_3.h>
#include <CGAL/Surface_mesh.h>

#include <variant>

#include "core/error.h"
#include "core/geodesics_cgal.h"

namespace cshapes {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
using VertexIndex = SurfaceMesh::Vertex_index;
using DirectSolver =
    CGAL::Heat_method_3::Surface_mesh_geodesic_distances_3<SurfaceMesh, CGAL::Heat_method_3::Direct>;
using IdtSolver =
    CGAL::Heat_method_3::Surface_mesh_geodesic_distances_3<SurfaceMesh,
                                                           CGAL::Heat_method_3::Intrinsic_Delaunay>;

SurfaceMesh to_surface_mesh(const Mesh& mesh) {
  SurfaceMesh sm;
  sm.reserve(static_cast<SurfaceMesh::size_type>(mesh.num_vertices()),
             static_cast<SurfaceMesh::size_type>(3 * mesh.num_faces() / 2),
             static_cast<SurfaceMesh::size_type>(mesh.num_faces()));
  for (Index i = 0; i < mesh.num_vertices(); ++i)
    sm.add_vertex(Kernel::Point_3(mesh.V(i, 0), mesh.V(i, 1), mesh.V(i, 2)));
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    auto face = sm.add_face(VertexIndex(mesh.F(f, 0)), VertexIndex(mesh.F(f, 1)), VertexIndex(mesh.F(f, 2)));
    CSHAPES_REQUIRE(face != SurfaceMesh::null_face(), "CGAL heat method: face ", f,
                    " cannot be added to a halfedge mesh (non-manifold edge or inconsistent orientation)");
  }
  return sm;
}

}  // namespace

CgalHeatMode parse_cgal_heat_mode(const std::string& name) {
  if (name == "direct") return CgalHeatMode::Direct;
  if (name == "idt") return CgalHeatMode::IntrinsicDelaunay;
  fail("unknown heat-method mode '", name, "'; known: direct, idt");
}

std::string to_string(CgalHeatMode mode) {
  return mode == CgalHeatMode::Direct ? "direct" : "idt";
}

struct CgalHeatMethod::Impl {
  SurfaceMesh sm;
  SurfaceMesh::Property_map<VertexIndex, double> distance;
  std::unique_ptr<DirectSolver> direct;
  std::unique_ptr<IdtSolver> idt;
};

CgalHeatMethod::CgalHeatMethod(const Mesh& mesh, CgalHeatMode mode) : impl_(std::make_unique<Impl>()) {
  CSHAPES_REQUIRE(mesh.num_faces() > 0, "CGAL heat method: the mesh has no faces");
  impl_->sm = to_surface_mesh(mesh);
  impl_->distance = impl_->sm.add_property_map<VertexIndex, double>("v:cshapes_distance", 0.0).first;
  try {
    if (mode == CgalHeatMode::Direct)
      impl_->direct = std::make_unique<DirectSolver>(impl_->sm);
    else
      impl_->idt = std::make_unique<IdtSolver>(impl_->sm);
  } catch (const std::exception& e) {
    fail("CGAL heat method failed to set up (", e.what(), ")");
  }
}

CgalHeatMethod::~CgalHeatMethod() = default;

Eigen::VectorXd CgalHeatMethod::distances(const std::vector<int>& sources) {
  const Index n = static_cast<Index>(impl_->sm.number_of_vertices());
  CSHAPES_REQUIRE(!sources.empty(), "CGAL heat method: no source vertex given");
  for (int s : sources)
    CSHAPES_REQUIRE(s >= 0 && s < n, "CGAL heat method: source ", s, " out of range 0..", n - 1);
  auto run = [&](auto& solver) {
    solver.clear_sources();
    for (int s : sources) solver.add_source(VertexIndex(s));
    solver.estimate_geodesic_distances(impl_->distance);
  };
  try {
    if (impl_->direct)
      run(*impl_->direct);
    else
      run(*impl_->idt);
  } catch (const std::exception& e) {
    fail("CGAL heat method failed (", e.what(), ")");
  }
  Eigen::VectorXd d(n);
  for (Index i = 0; i < n; ++i) d[i] = impl_->distance[VertexIndex(static_cast<SurfaceMesh::size_type>(i))];
  return d;
}

Eigen::VectorXd cgal_heat_method(const Mesh& mesh, const std::vector<int>& sources, CgalHeatMode mode) {
  return CgalHeatMethod(mesh, mode).distances(sources);
}

}  // namespace cshapes
