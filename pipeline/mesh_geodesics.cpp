#include "cshapes/pipeline/mesh_geodesics.h"

#include "cshapes/support/error.h"
#include "cshapes/geodesics/heat_method.h"

namespace cshapes {

MeshGeodesics prepare_mesh_geodesics(const Mesh& mesh, const MeshGeodesicsOptions& options) {
  RepairOptions ro;
  ro.strict = options.strict;
  ro.name = options.name;
  ro.purpose = "geodesics (one manifold component, no zero-area faces)";
  ro.progress = polls_of(options.geodesics.progress);
  MeshGeodesics prepared;
  prepared.repaired = repair_for(mesh, MeshRequirements::manifold_surface(), ro);
  const GeodesicMethod method = options.geodesics.method;
  if (method == GeodesicMethod::Heat || method == GeodesicMethod::HeatCgal)
    prepared.warning = heat_method_warning(prepared.repaired.mesh);
  return prepared;
}

Eigen::MatrixXd geodesic_rows(const Mesh& mesh, const MeshGeodesics& prepared, const std::vector<int>& sources,
                              const MeshGeodesicsOptions& options) {
  const RepairedMesh& sub = prepared.repaired;
  Eigen::MatrixXd rows(static_cast<Index>(sources.size()), mesh.num_vertices());
  for (size_t k = 0; k < sources.size(); ++k) {
    const int source = sources[k];
    CSHAPES_REQUIRE(source >= 0 && source < mesh.num_vertices(), options.name, ": source ", source,
                    " is out of range 0..", mesh.num_vertices() - 1);
    const std::vector<int> copies = repaired_copies(sub.vertex_map, source);
    CSHAPES_REQUIRE(!copies.empty(), options.name, ": source ", source, " was dropped by the repair (",
                    sub.text, ")");
    rows.row(static_cast<Index>(k)) =
        distances_to_input_vertices(geodesic_distances(sub.mesh, copies, options.geodesics), sub.vertex_map,
                                    mesh.num_vertices())
            .transpose();
  }
  return rows;
}

DistanceMatrix geodesic_all_pairs(const Mesh& mesh, const MeshGeodesics& prepared,
                                  const MeshGeodesicsOptions& options) {
  const RepairedMesh& sub = prepared.repaired;
  DistanceMatrix D = all_pairs_geodesics(sub.mesh, options.geodesics);
  if (sub.changed()) D = distances_to_input_vertices(D, sub.vertex_map, mesh.num_vertices());
  return D;
}

}  // namespace cshapes
