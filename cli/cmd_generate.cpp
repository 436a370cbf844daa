// cshapes generate swissroll | articulated | hand | dataset: shapes made here (deterministic for a seed),
// written with fixed precision so that the same seed gives byte-identical files.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "core/articulated.h"
#include "core/atomic_file.h"
#include "core/dataset.h"
#include "core/synthetic.h"
#include "cli/command.h"

namespace cshapes::cli {
namespace {

namespace fs = std::filesystem;

std::string join(const std::string& dir, const std::string& file) {
  return (fs::path(dir) / file).string();
}

void write_pairs_json(const std::string& path, const std::vector<std::pair<int, int>>& pairs) {
  nlohmann::json j = nlohmann::json::array();
  for (auto [a, b] : pairs) j.push_back({a, b});
  write_file_atomically(path, [&](std::ostream& out) {
    out << nlohmann::json{{"pairs", j}}.dump(2) << '\n';
  });
}

// ---- swissroll ----
struct SwissArgs {
  std::string output = "swissroll.off";
  long vertices = 561;
} swiss;

int run_swissroll() {
  require_output_path(swiss.output, {"off"});
  SwissRollOptions o;
  std::tie(o.nu, o.nv) = swiss_roll_grid(swiss.vertices);
  Mesh m = swiss_roll(o);
  write_off_fixed(swiss.output, m);
  note("wrote " + swiss.output + " (" + std::to_string(o.nu) + " x " + std::to_string(o.nv) + " = " +
       std::to_string(m.num_vertices()) + " vertices)");
  return 0;
}

// ---- articulated ----
struct ArticulatedArgs {
  std::string class_name = "biped", output = ".";
  int poses = 5;
  std::uint64_t seed = 0;
  long vertices = 3500;
  double amplitude = 1.0;
  bool json = false;
} art;

int run_articulated() {
  require_output_directory(art.output);
  ArticulatedOptions o;
  o.poses = art.poses;
  o.seed = art.seed;
  o.amplitude = art.amplitude;
  o.rest.target_vertices = art.vertices;
  ArticulatedClass c = generate_articulated(art.class_name, o);
  nlohmann::json poses = nlohmann::json::array();
  write_off_fixed(join(art.output, art.class_name + "_rest.off"), c.rest);
  for (size_t p = 0; p < c.poses.size(); ++p) {
    std::string file = join(art.output, art.class_name + std::to_string(p) + ".off");
    write_off_fixed(file, c.poses[p]);
    poses.push_back(
        {{"file", file}, {"edge_change_mean", c.isometry[p].mean}, {"edge_change_max", c.isometry[p].max}});
  }
  nlohmann::json j = {{"class", art.class_name},
                      {"vertices", c.rest.num_vertices()},
                      {"faces", c.rest.num_faces()},
                      {"redraws", c.redraws},
                      {"poses", poses}};
  if (art.json) {
    std::cout << j.dump(2) << std::endl;
  } else {
    std::printf("%s: %ld vertices, %zu poses in %s (%d self-intersecting draws redrawn)\n",
                art.class_name.c_str(), static_cast<long>(c.rest.num_vertices()), c.poses.size(),
                art.output.c_str(), c.redraws);
    for (size_t p = 0; p < c.poses.size(); ++p)
      std::printf("  pose %zu: edge length change mean %.2f%%, max %.1f%%\n", p, 100 * c.isometry[p].mean,
                  100 * c.isometry[p].max);
  }
  return 0;
}

// ---- hand ----
struct HandArgs {
  std::string output = ".";
  std::uint64_t seed = 0;
  int glues = 3;
} hand;

int run_hand() {
  require_output_directory(hand.output);
  GluedHand h = generate_glued_hand(hand.seed, hand.glues);
  write_off_fixed(join(hand.output, "hand_separated.off"), h.separated);
  write_off_fixed(join(hand.output, "hand_glued.off"), h.glued);
  write_pairs_json(join(hand.output, "hand_glued_pairs.json"), h.glued_pairs);
  MeshInfo a = mesh_info(h.separated), b = mesh_info(h.glued);
  std::printf("hand_separated.off: %ld vertices, genus %ld; hand_glued.off: genus %ld (%zu glues) in %s\n",
              static_cast<long>(a.vertices), a.genus, b.genus, h.glued_pairs.size(), hand.output.c_str());
  return 0;
}

// ---- dataset ----
struct DatasetArgs {
  std::string output;
  int classes = 4, poses = 5, noisy = 1, glue = 2;
  std::uint64_t seed = 0;
  long vertices = 3500;
  bool json = false;
} data;

int run_dataset() {
  require_output_directory(data.output);
  ArticulatedDatasetOptions o;
  o.classes = data.classes;
  o.poses = data.poses;
  o.noisy = data.noisy;
  o.glue_count = data.glue;
  o.seed = data.seed;
  o.rest.target_vertices = data.vertices;
  std::vector<ArticulatedShape> shapes = make_articulated_dataset(o);
  std::vector<DatasetEntry> entries;
  nlohmann::json summary = nlohmann::json::array();
  for (const ArticulatedShape& s : shapes) {
    DatasetEntry e;
    e.path = join(data.output, s.name + ".off");
    e.name = s.name;
    e.class_name = s.class_name;
    e.pose = s.pose;
    e.noisy = s.noisy;
    write_off_fixed(e.path, s.mesh);
    if (s.noisy) write_pairs_json(join(data.output, s.name + "_glued_pairs.json"), s.glued_pairs);
    entries.push_back(e);
    MeshInfo info = mesh_info(s.mesh);
    summary.push_back({{"file", s.name + ".off"},
                       {"class", s.class_name},
                       {"noisy", s.noisy},
                       {"vertices", info.vertices},
                       {"genus", info.genus},
                       {"edge_change_mean", s.isometry.mean},
                       {"edge_change_max", s.isometry.max}});
  }
  write_manifest(join(data.output, "manifest.csv"), entries);
  if (data.json) {
    std::cout << summary.dump(2) << std::endl;
  } else {
    std::printf("%zu shapes (%d classes x %d poses, %d noisy each) and manifest.csv in %s\n", shapes.size(),
                data.classes, data.poses + data.noisy, data.noisy, data.output.c_str());
  }
  return 0;
}

const bool registered_swissroll = register_command(
    {{"generate", "swissroll"},
     "The Swiss roll of Table 1 (561 vertices by default)",
     [](CLI::App& app) {
       app.add_option("--vertices", swiss.vertices, "about this many vertices (nu x nv, aspect 5:1)")
           ->capture_default_str()
           ->check(within(generate_limits::kVertices));
       app.add_option("-o,--output", swiss.output, "output mesh")->capture_default_str();
     },
     run_swissroll});

const bool registered_articulated = register_command(
    {{"generate", "articulated"},
     "Poses of one synthetic articulated class (biped, quadruped, hand, spider), same vertex order",
     [](CLI::App& app) {
       app.add_option("--class", art.class_name, "class: biped, quadruped, hand, spider")
           ->capture_default_str()
           ->check(one_of({"biped", "quadruped", "hand", "spider"}));
       app.add_option("--poses", art.poses, "number of poses")
           ->capture_default_str()
           ->check(within(generate_limits::kPoses));
       app.add_option("--seed", art.seed, "random seed")->capture_default_str();
       app.add_option("--vertices", art.vertices, "vertices of the rest mesh")
           ->capture_default_str()
           ->check(within(generate_limits::kVertices));
       app.add_option("--amplitude", art.amplitude, "fraction of the joint ranges used (0..1)")
           ->capture_default_str()
           ->check(within(generate_limits::kAmplitude));
       app.add_option("-o,--output", art.output, "output folder")->capture_default_str();
       app.add_flag("--json", art.json, "print the summary as JSON");
     },
     run_articulated});

const bool registered_hand = register_command(
    {{"generate", "hand"},
     "The hand of Fig. 2: fingers together but separated, and the same pose with adjacent fingers glued",
     [](CLI::App& app) {
       app.add_option("--seed", hand.seed, "random seed of the gluing")->capture_default_str();
       app.add_option("--glue", hand.glues, "number of glues")
           ->capture_default_str()
           ->check(within(generate_limits::kGlue));
       app.add_option("-o,--output", hand.output, "output folder")->capture_default_str();
     },
     run_hand});

const bool registered_dataset = register_command(
    {{"generate", "dataset"},
     "A synthetic retrieval dataset (articulated classes, clean and noisy poses) with manifest.csv",
     [](CLI::App& app) {
       app.add_option("-o,--output", data.output, "output folder")->required();
       app.add_option("--classes", data.classes, "number of classes (1..4)")
           ->capture_default_str()
           ->check(within(generate_limits::kClasses));
       app.add_option("--poses", data.poses, "clean poses per class")
           ->capture_default_str()
           ->check(within(generate_limits::kPoses));
       app.add_option("--noisy", data.noisy, "noisy (glued) poses per class")
           ->capture_default_str()
           ->check(within(generate_limits::kNoisy));
       app.add_option("--glue", data.glue, "glues per noisy pose")
           ->capture_default_str()
           ->check(within(generate_limits::kGlue));
       app.add_option("--seed", data.seed, "random seed")->capture_default_str();
       app.add_option("--vertices", data.vertices, "vertices per shape")
           ->capture_default_str()
           ->check(within(generate_limits::kVertices));
       app.add_flag("--json", data.json, "print a per-shape summary as JSON");
     },
     run_dataset});

}  // namespace
}  // namespace cshapes::cli
