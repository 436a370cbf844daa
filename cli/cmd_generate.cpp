// cshapes generate swissroll | articulated | hand | dataset: shapes made here (deterministic for a seed),
// written with fixed precision (pipeline/generated_shapes.h): the same seed gives byte-identical files.
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cli/command.h"
#include "cshapes/data/articulated.h"
#include "cshapes/data/dataset.h"
#include "cshapes/data/synthetic.h"
#include "cshapes/pipeline/generated_shapes.h"
#include "cshapes/support/output_folder.h"

namespace cshapes::cli {
namespace cmd_generate {
namespace {

// --force, for every generate command: an existing file of the same name is replaced.
bool force = false;

// Writes a command's files into a staging folder inside `target`, then moves them into place together; an
// existing file of the same name is refused (unless --force) before any is moved.
template <class Write>
void write_staged(const std::string& target, const Write& write) {
  const std::string staging = make_staging_folder(target);
  try {
    write(staging);
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove_all(staging, ec);
    throw;
  }
  publish_staged_files(staging, target, force);
}

// An option with its default shown in --help and the library's limit applied (support/option_limits.h).
template <class T>
void add_limited(CLI::App& app, const std::string& name, T& value, const std::string& help,
                 const Limit& limit) {
  app.add_option(name, value, help)->capture_default_str()->check(within(limit));
}

// ---- swissroll ----
std::string swissroll_output = "swissroll.off";
long swissroll_vertices = 561;
bool swissroll_json = false;

int run_swissroll() {
  require_output_path(swissroll_output, {"off"});
  SwissRollOptions o;
  std::tie(o.nu, o.nv) = swiss_roll_grid(swissroll_vertices);
  Mesh m = swiss_roll(o);
  const std::filesystem::path output(swissroll_output);
  const std::string folder = output.has_parent_path() ? output.parent_path().string() : ".";
  write_staged(folder, [&](const std::string& staging) {
    write_off_fixed((std::filesystem::path(staging) / output.filename()).string(), m);
  });
  note("wrote " + swissroll_output + " (" + std::to_string(o.nu) + " x " + std::to_string(o.nv) + " = " +
       std::to_string(m.num_vertices()) + " vertices)");
  if (swissroll_json)
    std::cout << nlohmann::json{{"file", swissroll_output},
                                {"nu", o.nu},
                                {"nv", o.nv},
                                {"vertices", m.num_vertices()},
                                {"faces", m.num_faces()}}
                     .dump(2)
              << std::endl;
  return 0;
}

// ---- articulated ----
ArticulatedOptions articulated;
std::string articulated_class = "biped", articulated_output = ".";
bool articulated_json = false;

int run_articulated() {
  require_output_directory(articulated_output);
  const ArticulatedClass c = generate_articulated(articulated_class, articulated);
  nlohmann::json j;
  write_staged(articulated_output, [&](const std::string& staging) {
    j = write_articulated_class(c, staging);
    for (nlohmann::json& pose : j["poses"])  // named where they land, not where they were staged
      pose["file"] = (std::filesystem::path(articulated_output) /
                      std::filesystem::path(pose["file"].get<std::string>()).filename())
                         .string();
  });
  if (articulated_json) {
    std::cout << j.dump(2) << std::endl;
    return 0;
  }
  std::printf("%s: %ld vertices, %zu poses in %s (%d self-intersecting draws redrawn)\n",
              articulated_class.c_str(), static_cast<long>(c.rest.num_vertices()), c.poses.size(),
              articulated_output.c_str(), c.redraws);
  for (size_t p = 0; p < c.poses.size(); ++p)
    std::printf("  pose %zu: edge length change mean %.3g%%, max %.3g%%\n", p, 100 * c.isometry[p].mean,
                100 * c.isometry[p].max);
  return 0;
}

// ---- hand ----
std::string hand_output = ".";
std::uint64_t hand_seed = 0;
int hand_glues = 3;
bool hand_json = false;

int run_hand() {
  require_output_directory(hand_output);
  const GluedHand h = generate_glued_hand(hand_seed, hand_glues);
  write_staged(hand_output, [&](const std::string& staging) { write_glued_hand(h, staging); });
  MeshInfo a = mesh_info(h.separated), b = mesh_info(h.glued);
  if (hand_json) {
    const auto file = [](const char* name) { return (std::filesystem::path(hand_output) / name).string(); };
    std::cout << nlohmann::json{{"seed", hand_seed},
                                {"glues", h.glued_pairs.size()},
                                {"separated",
                                 {{"file", file("hand_separated.off")},
                                  {"vertices", a.vertices},
                                  {"faces", a.faces},
                                  {"genus", a.genus}}},
                                {"glued",
                                 {{"file", file("hand_glued.off")},
                                  {"vertices", b.vertices},
                                  {"faces", b.faces},
                                  {"genus", b.genus}}},
                                {"glued_pairs", file("hand_glued_pairs.json")}}
                     .dump(2)
              << std::endl;
    return 0;
  }
  std::printf("hand_separated.off: %ld vertices, genus %ld; hand_glued.off: genus %ld (%zu glues) in %s\n",
              static_cast<long>(a.vertices), a.genus, b.genus, h.glued_pairs.size(), hand_output.c_str());
  return 0;
}

// ---- dataset ----
ArticulatedDatasetOptions dataset;
std::string dataset_output;
bool dataset_json = false;

int run_dataset() {
  require_output_directory(dataset_output);
  // A dataset is its folder: a rerun into it replaces the previous dataset whole; other files are refused.
  OutputRun output(dataset_output, "generate dataset", {}, force);
  const std::vector<ArticulatedShape> shapes = make_articulated_dataset(dataset);
  const nlohmann::json summary = write_articulated_dataset(shapes, dataset_output);
  output.commit();
  if (dataset_json)
    std::cout << summary.dump(2) << std::endl;
  else
    std::printf("%zu shapes (%d classes x %d poses, %d noisy each) and manifest.csv in %s\n", shapes.size(),
                dataset.classes, dataset.poses + dataset.noisy, dataset.noisy, dataset_output.c_str());
  return 0;
}

const bool registered_swissroll = register_command(
    {{"generate", "swissroll"},
     "The Swiss roll of Table 1 (561 vertices by default)",
     [](CLI::App& app) {
       add_limited(app, "--vertices", swissroll_vertices, "about this many vertices (nu x nv, aspect 5:1)",
                   generate_limits::kVertices);
       app.add_option("-o,--output", swissroll_output, "output mesh (an existing file is refused: --force)")
           ->capture_default_str();
       add_force_flag(app, force);
       app.add_flag("--json", swissroll_json, "print the summary as JSON");
     },
     run_swissroll});

const bool registered_articulated = register_command(
    {{"generate", "articulated"},
     "Poses of one synthetic articulated class (biped, quadruped, hand, spider), same vertex order",
     [](CLI::App& app) {
       app.add_option("--class", articulated_class, "class: biped, quadruped, hand, spider")
           ->capture_default_str()
           ->check(one_of({"biped", "quadruped", "hand", "spider"}));
       add_limited(app, "--poses", articulated.poses, "number of poses", generate_limits::kPoses);
       app.add_option("--seed", articulated.seed, "random seed")->capture_default_str();
       add_limited(app, "--vertices", articulated.rest.target_vertices, "vertices of the rest mesh",
                   generate_limits::kVertices);
       add_limited(app, "--amplitude", articulated.amplitude, "fraction of the joint ranges used (0..1)",
                   generate_limits::kAmplitude);
       add_out_folder_option(app, articulated_output, "output folder")->capture_default_str();
       add_force_flag(app, force);
       app.add_flag("--json", articulated_json, "print the summary as JSON");
     },
     run_articulated});

const bool registered_hand = register_command(
    {{"generate", "hand"},
     "The hand of Fig. 2: fingers together but separated, and the same pose with adjacent fingers glued",
     [](CLI::App& app) {
       app.add_option("--seed", hand_seed, "random seed of the gluing")->capture_default_str();
       add_limited(app, "--glue", hand_glues, "number of glues", generate_limits::kGlue);
       add_out_folder_option(app, hand_output, "output folder")->capture_default_str();
       add_force_flag(app, force);
       app.add_flag("--json", hand_json, "print the summary as JSON");
     },
     run_hand});

const bool registered_dataset = register_command(
    {{"generate", "dataset"},
     "A synthetic retrieval dataset (articulated classes, clean and noisy poses) with manifest.csv",
     [](CLI::App& app) {
       add_out_folder_option(app, dataset_output, "output folder")->required();
       add_force_flag(app, force);
       add_limited(app, "--classes", dataset.classes, "number of classes (1..4)", generate_limits::kClasses);
       add_limited(app, "--poses", dataset.poses, "clean poses per class", generate_limits::kPoses);
       add_limited(app, "--noisy", dataset.noisy, "noisy (glued) poses per class", generate_limits::kNoisy);
       add_limited(app, "--glue", dataset.glue_count, "glues per noisy pose", generate_limits::kGlue);
       app.add_option("--seed", dataset.seed, "random seed")->capture_default_str();
       add_limited(app, "--vertices", dataset.rest.target_vertices, "vertices per shape",
                   generate_limits::kVertices);
       app.add_flag("--json", dataset_json, "print a per-shape summary as JSON");
     },
     run_dataset});

}  // namespace
}  // namespace cmd_generate
}  // namespace cshapes::cli
