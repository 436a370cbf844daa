// CGAL's geodesic distance algorithms behind plain Eigen types (only the *_cgal.cpp files see CGAL):
//   - the heat method, CGAL::Heat_method_3 (Crane et al. 2013), in its Direct and Intrinsic Delaunay modes,
//     one source set at a time: the reference for our own heat method (geodesics/heat_method.h) and the anchor of
//     `cshapes bench geodesics`;
//   - exact polyhedral geodesics, CGAL::Surface_mesh_shortest_path (Xin & Wang's improvement of
//     Chen & Han): the ground truth against which the approximations are measured. Cost grows roughly as
//     O(n² log n) per source set in the worst case (seconds per source at 20K vertices).
// Conventions: distances in the mesh's units, one value per vertex, to the nearest source. The mesh must be a
// connected, manifold triangle mesh (geodesics/geodesics.h splits disconnected meshes per component); CGAL's
// own failures are rethrown as cshapes::Error.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "cshapes/mesh/mesh.h"

namespace cshapes {

enum class CgalHeatMode {
  Direct,             // cotangent Laplacian of the mesh itself
  IntrinsicDelaunay,  // Laplacian of the intrinsic Delaunay triangulation: robust to poor triangles
};
CgalHeatMode parse_cgal_heat_mode(const std::string& name);  // "direct" or "idt"
std::string to_string(CgalHeatMode mode);

// CGAL's heat method with its factorisations kept for repeated source sets. Not thread-safe: use one object
// per thread (each holds a copy of the mesh and two factorisations).
class CgalHeatMethod {
 public:
  CgalHeatMethod(const Mesh& mesh, CgalHeatMode mode = CgalHeatMode::IntrinsicDelaunay);
  ~CgalHeatMethod();
  CgalHeatMethod(const CgalHeatMethod&) = delete;
  CgalHeatMethod& operator=(const CgalHeatMethod&) = delete;

  // Distances to the nearest of `sources` (n values): CGAL's solve, gradient, divergence and solve per call.
  Eigen::VectorXd distances(const std::vector<int>& sources);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One-shot CGAL heat method.
Eigen::VectorXd cgal_heat_method(const Mesh& mesh, const std::vector<int>& sources,
                                 CgalHeatMode mode = CgalHeatMode::IntrinsicDelaunay);

// Exact geodesic distances (CGAL::Surface_mesh_shortest_path) from the nearest of `sources`.
// Thread-safe (each call builds its own structure).
Eigen::VectorXd exact_geodesics(const Mesh& mesh, const std::vector<int>& sources);

}  // namespace cshapes
