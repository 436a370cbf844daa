// Descriptions as JSON, one wording for every front end: `cshapes info --json` and `cshapes canon --json`
// print them, the Python module returns them as dicts (mesh_info(), CanonicalForm.summary).
#pragma once

#include <nlohmann/json.hpp>

#include "cshapes/mesh/mesh.h"
#include "cshapes/mesh/mesh_defects.h"
#include "cshapes/data/topological_noise.h"
#include "cshapes/pipeline/canonical_forms.h"

namespace cshapes {

// {vertices, faces, edges, components, isolated_vertices, boundary_edges, boundary_loops, nonmanifold_edges,
//  euler_characteristic, genus, bbox_diagonal, mean_edge_length, area}.
nlohmann::json mesh_info_json(const MeshInfo& info);
// {summary, any, nonmanifold_edges: {count, examples}, ..., components, component_sizes, boundary_edges,
//  boundary_loops}.
nlohmann::json mesh_defects_json(const MeshDefects& defects);
// Both for one mesh: mesh_info_json plus "defects".
nlohmann::json describe_mesh(const Mesh& mesh);

// What a gluing did: {pairs: [[a, b], ...], rims: [[a0, a1, a2, b0, b1, b2], ...], euclidean, geodesic,
// max_gap, min_ratio, geodesic_diameter}. Only vertex indices are integers in it (render_mesh.py
// --red-json reads every integer as a vertex).
nlohmann::json topological_noise_json(const TopologicalNoiseResult& result);

// A canonical form's summary: form_summary_json (its details and quality) plus method, repairs
// [{what, count}], repair (one line), input_vertices and kept_input_vertices.
nlohmann::json canonical_form_summary(const CanonicalForm& form, const std::string& method);

}  // namespace cshapes
