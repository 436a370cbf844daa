#include "cshapes/pipeline/glued_meshes.h"

#include <nlohmann/json.hpp>
#include <optional>

#include "cshapes/support/error.h"
#include "cshapes/pipeline/canonical_forms.h"

namespace cshapes {

using nlohmann::json;

std::string glued_mesh_key(const Mesh& mesh, const TopologicalNoiseOptions& options) {
  // The options' own field list (support/option_fields.h) names every field. The tag's version changes with
  // what the key covers: entries under an older key are not found and are glued again, once (docs/design.md,
  // "Caches").
  return cache_key({"glued-mesh-v2", mesh_content_key(mesh), options_key(options)});
}

GluedMesh cached_glued_mesh(const DiskCache& cache, const Mesh& mesh,
                            const TopologicalNoiseOptions& options) {
  const std::string key = glued_mesh_key(mesh, options);
  GluedMesh g;
  json value;
  if (std::optional<json> hit = cache.get_json(key)) {
    value = *hit;
    g.cached = true;
  } else {
    try {
      TopologicalNoiseResult r = glue_topological_noise(mesh, options);
      std::vector<int> vertices;
      for (const GluedPair& p : r.pairs) {
        vertices.push_back(p.a);
        vertices.push_back(p.b);
      }
      value =
          json{{"F", faces_to_json(r.mesh.F)}, {"glued", vertices}, {"relax_steps_used", r.relax_steps_used}};
    } catch (const WriteError&) {
      throw;
    } catch (const Error& e) {
      value = json{{"error", e.what()}};
    }
    cache.put_json(key, value);
  }
  if (value.contains("error")) {
    g.error = value.at("error").get<std::string>();
    return g;
  }
  g.mesh.V = mesh.V;
  g.mesh.F = faces_from_json(value.at("F"));
  g.glued = value.at("glued").get<std::vector<int>>();
  g.relax_steps_used = value.value("relax_steps_used", 0);
  return g;
}

}  // namespace cshapes
