// cshapes info MESH [--json]: counts, topology and size of a mesh or point cloud, and its defects
// (core/mesh_defects.h) for any readable file: only malformed files are refused.
#include <cstdio>
#include <iostream>

#include "core/io.h"
#include "core/mesh_defects.h"
#include "experiments/command.h"

namespace cshapes::cli {
namespace {

struct InfoArgs {
  std::vector<std::string> paths;
  bool json = false;
  bool no_validate = false;
} args;

nlohmann::json to_json(const std::string& path, const MeshInfo& i) {
  return {{"file", path},
          {"vertices", i.vertices},
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

nlohmann::json to_json(const MeshDefects& d) {
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

int run() {
  nlohmann::json all = nlohmann::json::array();
  for (const std::string& path : args.paths) {
    Mesh mesh = read_mesh(path);  // lenient: only malformed files are refused
    MeshInfo info = mesh_info(mesh);
    MeshDefects defects = mesh_defects(mesh);
    nlohmann::json j = to_json(path, info);
    j["defects"] = to_json(defects);
    if (args.json) {
      all.push_back(j);
      continue;
    }
    std::printf("%s\n", path.c_str());
    std::printf("  vertices              %ld\n", static_cast<long>(info.vertices));
    std::printf("  faces                 %ld\n", static_cast<long>(info.faces));
    std::printf("  edges                 %ld\n", static_cast<long>(info.edges));
    std::printf("  components            %d\n", info.components);
    if (info.isolated_vertices)
      std::printf("  isolated vertices     %ld\n", static_cast<long>(info.isolated_vertices));
    std::printf("  boundary edges        %ld (%d loops)\n", static_cast<long>(info.boundary_edges),
                info.boundary_loops);
    if (info.nonmanifold_edges)
      std::printf("  non-manifold edges    %ld\n", static_cast<long>(info.nonmanifold_edges));
    std::printf("  euler characteristic  %ld\n", info.euler_characteristic);
    if (info.genus >= 0) std::printf("  genus                 %ld\n", info.genus);
    std::printf("  bbox diagonal         %.6g\n", info.bbox_diagonal);
    std::printf("  mean edge length      %.6g\n", info.mean_edge_length);
    std::printf("  area                  %.6g\n", info.area);
    std::printf("  defects               %s\n", defects.summary().c_str());
  }
  if (args.json) std::cout << (all.size() == 1 ? all[0] : all).dump(2) << std::endl;
  return 0;
}

const bool registered = register_command(
    {{"info"},
     "Print counts, topology (components, boundary, Euler characteristic, genus) and size of meshes",
     [](CLI::App& app) {
       app.add_option("MESH", args.paths, "mesh or point-cloud files")->required();
       app.add_flag("--json", args.json, "print JSON (an object, or an array for several files)");
       app.add_flag("--no-validate", args.no_validate,
                    "accepted for old scripts: every readable mesh is described, defects included");
     },
     run});

}  // namespace
}  // namespace cshapes::cli
