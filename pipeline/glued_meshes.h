// Topologically noisy meshes (data/topological_noise.h) through one cache, shared by every experiment: the
// same pose glued with the same options is computed once and stored once, whichever experiment asks first.
#pragma once

#include <string>
#include <vector>

#include "cshapes/mesh/mesh.h"
#include "cshapes/data/topological_noise.h"
#include "cshapes/data/cache.h"

namespace cshapes {

struct GluedMesh {
  Mesh mesh;                 // the input's vertices, the glued faces; empty when the glue failed
  std::vector<int> glued;    // the glued pairs' vertices, a then b per pair
  int relax_steps_used = 0;  // TopologicalNoiseResult::relax_steps_used
  std::string error;         // why the glue failed ("" when it did not): too few admissible spots, ...
  bool cached = false;       // read from the cache
  bool ok() const { return error.empty(); }
};

// The key of a glued mesh: the input's content (mesh_content_key) and options_key of the options
// (support/option_fields.h): every field of TopologicalNoiseOptions that changes the result.
std::string glued_mesh_key(const Mesh& mesh, const TopologicalNoiseOptions& options);

// glue_topological_noise(mesh, options) through `cache` (a disabled cache computes every time). A glue that
// fails with a cshapes::Error is a result too (error set, cached, so a rerun does not try again); a failed
// write (WriteError) is thrown.
GluedMesh cached_glued_mesh(const DiskCache& cache, const Mesh& mesh, const TopologicalNoiseOptions& options);

}  // namespace cshapes
