#include "cshapes/pipeline/mesh_report.h"

namespace cshapes {

nlohmann::json mesh_info_json(const MeshInfo& i) {
  return {{"vertices", i.vertices},
          {"faces", i.faces},
          {"edges", i.edges},
          {"components", i.components},
          {"isolated_vertices", i.isolated_vertices},
          {"boundary_edges", i.boundary_edges},
          {"boundary_loops", i.boundary_loops},
          {"nonmanifold_edges", i.nonmanifold_edges},
          {"euler_characteristic", i.euler_characteristic},
          {"genus", i.genus},
          {"bbox_diagonal", i.bbox_diagonal},
          {"mean_edge_length", i.mean_edge_length},
          {"area", i.area}};
}

nlohmann::json mesh_defects_json(const MeshDefects& d) {
  using nlohmann::json;
  auto kind = [](Index count, const auto& examples) {
    return json{{"count", count}, {"examples", examples}};
  };
  return {{"summary", d.summary()},
          {"any", d.any()},
          {"nonmanifold_edges", kind(d.nonmanifold_edges, d.nonmanifold_edge_examples)},
          {"nonmanifold_vertices", kind(d.nonmanifold_vertices, d.nonmanifold_vertex_examples)},
          {"isolated_vertices", kind(d.isolated_vertices, d.isolated_vertex_examples)},
          {"duplicate_faces", kind(d.duplicate_faces, d.duplicate_face_examples)},
          {"repeated_vertex_faces", kind(d.repeated_vertex_faces, d.repeated_vertex_face_examples)},
          {"zero_area_faces", kind(d.zero_area_faces, d.zero_area_face_examples)},
          {"zero_length_edges", kind(d.zero_length_edges, d.zero_length_edge_examples)},
          {"components", d.components},
          {"component_sizes", d.component_sizes},
          {"boundary_edges", d.boundary_edges},
          {"boundary_loops", d.boundary_loops}};
}

nlohmann::json describe_mesh(const Mesh& mesh) {
  nlohmann::json j = mesh_info_json(mesh_info(mesh));
  j["defects"] = mesh_defects_json(mesh_defects(mesh));
  return j;
}

nlohmann::json topological_noise_json(const TopologicalNoiseResult& r) {
  nlohmann::json pairs = nlohmann::json::array(), rims = nlohmann::json::array(),
                 euclidean = nlohmann::json::array(), geodesic = nlohmann::json::array();
  for (const GluedPair& p : r.pairs) {
    pairs.push_back({p.a, p.b});
    rims.push_back({p.rim_a[0], p.rim_a[1], p.rim_a[2], p.rim_b[0], p.rim_b[1], p.rim_b[2]});
    euclidean.push_back(p.euclidean);
    geodesic.push_back(p.geodesic);
  }
  return {{"pairs", pairs},         {"rims", rims},           {"euclidean", euclidean},
          {"geodesic", geodesic},   {"max_gap", r.max_gap},   {"min_ratio", r.min_ratio},
          {"geodesic_diameter", r.geodesic_diameter}};
}

nlohmann::json canonical_form_summary(const CanonicalForm& form, const std::string& method) {
  nlohmann::json summary = form_summary_json(form);
  nlohmann::json repairs = nlohmann::json::array();
  for (const RepairAction& a : form.repairs) repairs.push_back({{"what", a.what}, {"count", a.count}});
  summary["method"] = method;
  summary["repairs"] = repairs;
  summary["repair"] = form.repair_text;
  summary["input_vertices"] = form.X.rows();
  summary["kept_input_vertices"] = static_cast<Index>(form.valid.sum());
  return summary;
}

}  // namespace cshapes
