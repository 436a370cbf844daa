// Geodesic distances on a user's mesh, given at its own vertices: what `cshapes geodesics` writes and the
// Python module's geodesics() returns.
//
// Geodesics need one manifold component without zero-area faces. A mesh that is not is repaired first
// (mesh/mesh_repair.h: the largest component, non-manifold edges cut, ...) unless options.strict, which
// refuses it naming the defects. Distances are then placed back at the input's vertices: NaN where the
// repair dropped a vertex, the nearer copy where it split one; a split source uses all its copies.
// Cost: that of geodesics/geodesics.h for the method (all pairs: n single-source solves, n² floats of memory).
#pragma once

#include <string>
#include <vector>

#include "cshapes/geodesics/geodesics.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/mesh/mesh_repair.h"
#include "cshapes/support/option_declaration.h"

namespace cshapes {

// `cshapes geodesics --strict` and geodesics(strict=) (declared once, support/option_declaration.h).
inline const OptionDeclaration kStrictGeodesicsOption{
    "strict", "--strict",
    "refuse a mesh that needs repair (non-manifold, several components, ...) instead of repairing it: an "
    "error "
    "names its defects"};

struct MeshGeodesicsOptions {
  GeodesicOptions geodesics;  // method (heat by default), heat mode, progress
  bool strict = false;        // refuse a mesh that needs repair instead of repairing it
  std::string name = "mesh";  // the mesh's name (its path) in messages
};

struct MeshGeodesics {
  RepairedMesh repaired;  // the mesh the distances were computed on, and what the repair did (text)
  std::string warning;    // heat methods on a mesh too coarse for them (geodesics/heat_method.h); "" otherwise
};

// The repair for geodesics (throws under strict when one is needed), and the heat method's warning.
MeshGeodesics prepare_mesh_geodesics(const Mesh& mesh, const MeshGeodesicsOptions& options);

// Row k: the distances from sources[k] (input numbering) to every input vertex. Throws, naming the
// source, for one out of range or dropped by the repair.
Eigen::MatrixXd geodesic_rows(const Mesh& mesh, const MeshGeodesics& prepared, const std::vector<int>& sources,
                              const MeshGeodesicsOptions& options);

// All pairs at the input's vertices (n×n float32, symmetric; NaN rows and columns at dropped vertices).
DistanceMatrix geodesic_all_pairs(const Mesh& mesh, const MeshGeodesics& prepared,
                                  const MeshGeodesicsOptions& options);

}  // namespace cshapes
