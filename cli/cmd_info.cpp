// cshapes info MESH [--json]: counts, topology and size of a mesh or point cloud, and its defects
// (mesh/mesh_defects.h) for any readable file: only malformed files are refused.
#include <cstdio>
#include <iostream>

#include "cshapes/mesh/io.h"
#include "cshapes/mesh/mesh_defects.h"
#include "cli/command.h"
#include "cshapes/pipeline/mesh_report.h"

namespace cshapes::cli {
namespace cmd_info {
namespace {

struct InfoArgs {
  std::vector<std::string> paths;
  bool json = false;
} args;

int run() {
  nlohmann::json all = nlohmann::json::array();
  for (const std::string& path : args.paths) {
    // Lenient: only malformed files are refused. Rows a canonical form marks invalid (NaN, valid = 0) are
    // left out by the reader, and said.
    const MeshFile file = read_mesh_file(path);
    const Mesh& mesh = file.mesh;
    MeshInfo info = mesh_info(mesh);
    MeshDefects defects = mesh_defects(mesh);
    nlohmann::json j = {{"file", path}};
    j.update(mesh_info_json(info));
    j["defects"] = mesh_defects_json(defects);
    if (file.invalid_vertices > 0) {
      j["invalid_vertices"] = file.invalid_vertices;
      j["invalid_faces"] = file.invalid_faces;
    }
    if (args.json) {
      all.push_back(j);
      continue;
    }
    std::printf("%s\n", path.c_str());
    if (file.invalid_vertices > 0)
      std::printf(
          "  %ld invalid vertices (NaN rows, valid = 0) ignored, with the %ld faces on them; the "
          "counts below are of the valid part\n",
          static_cast<long>(file.invalid_vertices), static_cast<long>(file.invalid_faces));
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
    std::printf("  bbox diagonal         %.3g (the mesh's units)\n", info.bbox_diagonal);
    if (info.bbox_diagonal > 0)
      std::printf("  mean edge length      %.3g (%.3g%% of the diagonal)\n", info.mean_edge_length,
                  100 * info.mean_edge_length / info.bbox_diagonal);
    else
      std::printf("  mean edge length      %.3g\n", info.mean_edge_length);
    std::printf("  area                  %.3g (square units)\n", info.area);
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
     },
     run});

}  // namespace
}  // namespace cmd_info
}  // namespace cshapes::cli
