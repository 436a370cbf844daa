// CGAL::Heat_method_3 behind geodesics/geodesics_cgal.h.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Heat_method_3/Surface_mesh_geodesic_distances_3.h>
#include <CGAL/Surface_mesh.h>

#include <variant>

#include "cshapes/support/error.h"
#include "cshapes/geodesics/geodesics_cgal.h"
#include "cshapes/mesh/surface_mesh_cgal.h"

namespace cshapes {

namespace {

using cgal::Kernel;
using cgal::SurfaceMesh;
using cgal::VertexIndex;
using DirectSolver =
    CGAL::Heat_method_3::Surface_mesh_geodesic_distances_3<SurfaceMesh, CGAL::Heat_method_3::Direct>;
using IdtSolver =
    CGAL::Heat_method_3::Surface_mesh_geodesic_distances_3<SurfaceMesh,
                                                           CGAL::Heat_method_3::Intrinsic_Delaunay>;


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
  impl_->sm = cgal::to_surface_mesh(mesh, "CGAL heat method");
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
