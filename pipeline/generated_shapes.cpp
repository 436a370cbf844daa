#include "cshapes/pipeline/generated_shapes.h"

#include <filesystem>

#include "cshapes/support/atomic_file.h"
#include "cshapes/data/dataset.h"

namespace cshapes {

namespace {

std::string join(const std::string& folder, const std::string& file) {
  return (std::filesystem::path(folder) / file).string();
}

}  // namespace

void write_glued_pairs_json(const std::string& path, const std::vector<std::pair<int, int>>& pairs) {
  nlohmann::json j = nlohmann::json::array();
  for (auto [a, b] : pairs) j.push_back({a, b});
  write_file_atomically(path, [&](std::ostream& out) {
    out << nlohmann::json{{"pairs", j}}.dump(2) << '\n';
  });
}

nlohmann::json write_articulated_class(const ArticulatedClass& c, const std::string& folder) {
  const std::string& class_name = c.skeleton.class_name;
  nlohmann::json poses = nlohmann::json::array();
  write_off_fixed(join(folder, class_name + "_rest.off"), c.rest);
  for (size_t p = 0; p < c.poses.size(); ++p) {
    std::string file = join(folder, class_name + std::to_string(p) + ".off");
    write_off_fixed(file, c.poses[p]);
    poses.push_back(
        {{"file", file}, {"edge_change_mean", c.isometry[p].mean}, {"edge_change_max", c.isometry[p].max}});
  }
  return {{"class", class_name},
          {"vertices", c.rest.num_vertices()},
          {"faces", c.rest.num_faces()},
          {"redraws", c.redraws},
          {"poses", poses}};
}

void write_glued_hand(const GluedHand& hand, const std::string& folder) {
  write_off_fixed(join(folder, "hand_separated.off"), hand.separated);
  write_off_fixed(join(folder, "hand_glued.off"), hand.glued);
  write_glued_pairs_json(join(folder, "hand_glued_pairs.json"), hand.glued_pairs);
}

nlohmann::json write_articulated_dataset(const std::vector<ArticulatedShape>& shapes,
                                         const std::string& folder) {
  std::vector<DatasetEntry> entries;
  nlohmann::json summary = nlohmann::json::array();
  for (const ArticulatedShape& s : shapes) {
    DatasetEntry e;
    e.path = join(folder, s.name + ".off");
    e.name = s.name;
    e.class_name = s.class_name;
    e.pose = s.pose;
    e.noisy = s.noisy;
    write_off_fixed(e.path, s.mesh);
    if (s.noisy) write_glued_pairs_json(join(folder, s.name + "_glued_pairs.json"), s.glued_pairs);
    entries.push_back(e);
    const MeshInfo info = mesh_info(s.mesh);
    summary.push_back({{"file", s.name + ".off"},
                       {"class", s.class_name},
                       {"noisy", s.noisy},
                       {"vertices", info.vertices},
                       {"genus", info.genus},
                       {"edge_change_mean", s.isometry.mean},
                       {"edge_change_max", s.isometry.max}});
  }
  write_manifest(join(folder, "manifest.csv"), entries);
  return summary;
}

}  // namespace cshapes
