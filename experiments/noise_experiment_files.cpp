// The noise experiment's files: noise.csv, noise.json and report.md, from a NoiseExperimentResult.
#include "cshapes/experiments/noise_experiment.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>
#include <sstream>

#include "cshapes/support/atomic_file.h"
#include "cshapes/data/dataset.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"
#include "cshapes/mesh/rigid_transform.h"
#include "cshapes/support/timing.h"
#include "cshapes/data/topological_noise.h"
#include "cshapes/data/cache.h"
#include "cshapes/eval/pairwise_distances.h"
#include "cshapes/eval/retrieval.h"
#include "cshapes/experiments/figures.h"
#include "cshapes/experiments/paper_report.h"
#include "cshapes/matching/shape_distance.h"
#include "cshapes/pipeline/experiment_kit.h"
#include "cshapes/pipeline/glued_meshes.h"
#include "cshapes/pipeline/shape_failures.h"

namespace cshapes {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// "How it was made": the poses, the glue and its χ check, the methods, the retrieval protocol.
void how_it_was_made(std::ostringstream& md, const NoiseExperimentResult& r) {
  const NoiseExperimentOptions& o = r.options;
  const std::vector<NoisePose>& poses = r.pose_list;
  md << "## How it was made\n\n";
  md << "- Poses: " << r.poses << " clean poses in " << r.classes << " classes (";
  for (size_t k = 0; k < poses.size(); ++k) md << (k ? ", " : "") << poses[k].name;
  md << ")" << (o.poses_per_class > 0 ? ", at most " + std::to_string(o.poses_per_class) + " per class" : "")
     << "; shapes the data marks noisy are not used.\n";
  md << "- Noise: every pose glued at ";
  for (size_t k = 0; k < o.levels.size(); ++k) md << (k ? ", " : "") << o.levels[k];
  md << " spots (data/topological_noise.h, the glue of `experiment paper`: a short tube between two spots "
        "close in space and far along the surface; up to "
     << o.relax_steps
     << " relaxations of the gap and ratio where a pose offers too few spots). Seed of pose P at level K: "
        "SHA-256 of (`--seed` "
     << o.seed
     << ", P, K), so every pose and level is its own draw (noise.json lists them). Level 0 is the "
        "clean pose. Glued meshes: `shapes/*_glueK.off`.\n";
  md << "- χ check: each glue adds a handle, so χ must drop by 2 per glue. " << r.glues.size()
     << " glued meshes, " << r.chi_mismatches << " with a χ mismatch, " << r.glue_failures
     << " where the pose offered too few admissible spots; those are left out of every measurement";
  if (r.chi_mismatches + r.glue_failures > 0) {
    md << ":\n\n| pose | glues | χ before | χ after | expected | why left out |\n| --- | --- | --- | --- | "
          "--- | "
          "--- |\n";
    for (const NoiseGlue& g : r.glues)
      if (!g.ok)
        md << "| " << g.shape << " | " << g.level << " | " << g.chi_before << " | "
           << (g.error.rfind("glue failed", 0) == 0 ? std::string("—") : std::to_string(g.chi_after)) << " | "
           << g.chi_expected << " | " << g.error << " |\n";
    md << "\n";
  } else {
    md << " (none here).\n";
  }
  md << "- Methods: ";
  for (size_t k = 0; k < o.methods.size(); ++k) md << (k ? ", " : "") << method_title(o.methods[k]);
  md << "; MDS geodesics by `" << to_string(o.canon.geodesics.method)
     << "`; Coulomb with the options of `canon` (defaults unless given).\n";
  md << "- Retrieval: each glued pose is a query; the database is every clean pose but the query's own, "
        "relevant = same class. Distance: ICP alignment of the canonical forms (reflections allowed), then "
        "Hausdorff (the paper's), Chamfer or RMSE between nearest points. mAP and NN over the queries whose "
        "class has another pose. Level 0 is clean leave-one-out retrieval.\n";
  md << "- Form distance: the glued pose's canonical form against its clean pose's form at the same "
        "vertices, "
        "RMS after the best rigid fit (reflections allowed), in % of the clean form's bbox diagonal.\n";
  for (const std::string& s : r.skipped) md << "- Skipped: " << s << "\n";
  md << "\n";
  md << shape_failures_markdown(r.failures);
}

// What the numbers say about the paper's claim (Coulomb flat, MDS falling), when both kinds of method ran.
void change_to_the_highest_level(std::ostringstream& md, const NoiseExperimentResult& r) {
  const NoiseExperimentOptions& o = r.options;
  const bool has_coulomb = std::find(o.methods.begin(), o.methods.end(), "coulomb") != o.methods.end();
  if (has_coulomb && o.methods.size() > 1 && o.levels.size() > 1) {
    auto find = [&](const std::string& m, int level) -> const NoiseRow* {
      for (const NoiseRow& row : r.rows)
        if (row.method == m && row.level == level && row.distance == "hausdorff") return &row;
      return nullptr;
    };
    // The highest level that at least half of the poses reached with every method: above it a level is a
    // handful of poses (on TOSCA, 8 glues fit one pose of 24), too few to read a trend from.
    int top = -1;
    for (int level : o.levels) {
      bool enough = true;
      for (const std::string& m : o.methods) {
        const NoiseRow* row = find(m, level);
        enough = enough && row && row->queries > 0 && 2 * row->form_poses >= r.poses;
      }
      if (enough && level > 0) top = level;
    }
    if (top > 0) {
      md << "## Change from the clean poses to " << top << " glues\n\n"
         << "The highest level that at least half of the poses reached; mAP against the same queries "
            "without glue.\n\n| method | poses | mAP (Hausdorff), clean → glued | form RMS median |\n"
         << "| --- | --- | --- | --- |\n";
      for (const std::string& m : o.methods) {
        const NoiseRow* b = find(m, top);
        md << "| " << method_title(m) << " | " << b->form_poses << " | "
           << format_number("%.3f", b->map_clean_same_poses) << " → " << format_number("%.3f", b->map) << " ("
           << format_number("%+.3f", b->map - b->map_clean_same_poses) << ") | "
           << "0 → " << percent(b->form_rms_median) << " |\n";
      }
      md << "\nThe paper's claim predicts a flat Coulomb curve and falling mAP / growing form distance for "
            "MDS. With few queries per level a single retrieval moves mAP by 1/queries: read small "
            "differences "
            "as ties.\n\n";
    }
  }
}

}  // namespace

void write_noise_report(const NoiseExperimentResult& r, const std::string& folder) {
  const NoiseExperimentOptions& o = r.options;
  const std::map<std::string, double>& pose_variation = r.pose_variation;
  std::ostringstream md;
  md << "# Topological noise: retrieval and canonical forms against the number of glues\n\n";
  md << build_sentence() << "\n\n";
  md << "Generated by `cshapes experiment noise` from `" << o.data << "` in "
     << format_number("%.0f", r.seconds) << " s (" << r.canonical_forms_computed
     << " canonical forms computed, " << r.canonical_forms_cached << " from the cache; " << r.pairs_computed
     << " ICP pairs computed, " << r.pairs_cached << " cached; " << r.glued_computed
     << " glued meshes computed, " << r.glued_cached << " cached).\n\n";

  how_it_was_made(md, r);
  if (r.resampled) md << "## Resampling\n\n" << resampling_markdown(r.resampling) << '\n';
  md << "## Results\n\n";
  md << "| method | glues | poses | queries | mAP Hausdorff | same poses clean | mAP Chamfer | mAP RMSE | NN "
        "Hausdorff | form RMS median | form RMS mean |\n| --- | --- | --- | --- | --- | --- | --- | --- | "
        "--- | --- "
        "| --- |\n";
  for (const std::string& m : o.methods)
    for (int level : o.levels) {
      std::map<std::string, const NoiseRow*> by;
      for (const NoiseRow& row : r.rows)
        if (row.method == m && row.level == level) by[row.distance] = &row;
      if (!by.count("hausdorff")) continue;
      const NoiseRow& h = *by.at("hausdorff");
      md << "| " << method_title(m) << " | " << level << " | " << h.form_poses << " | " << h.queries << " | "
         << format_number("%.3f", h.map) << " | " << format_number("%.3f", h.map_clean_same_poses) << " | "
         << format_number("%.3f", by.at("chamfer")->map) << " | " << format_number("%.3f", by.at("rmse")->map)
         << " | " << format_number("%.3f", h.nn) << " | " << percent(h.form_rms_median) << " | "
         << percent(h.form_rms_mean) << " |\n";
    }
  md << "\n`poses`: the poses measured at that level (glued as often, χ as expected); `queries`: those whose "
        "class has another pose in the database; `same poses clean`: the Hausdorff mAP of the same queries "
        "without glue (level 0), the baseline a level with fewer poses is to be read against.";
  if (r.glue_failures + r.chi_mismatches > 0)
    md << " **Not every pose could be glued at every level** (table above): a level with fewer poses is "
          "measured on those poses only, a smaller and different set, so compare its numbers with the other "
          "levels with care.";
  md << "\n\nFor scale, the median ICP RMSE between the canonical forms of two clean poses of one class: ";
  {
    bool first = true;
    for (const std::string& m : o.methods)
      if (pose_variation.count(m)) {
        md << (first ? "" : ", ") << method_title(m) << " " << percent(pose_variation.at(m));
        first = false;
      }
    if (first) md << "— (no class has two poses)";
  }
  md << ".\n\n";
  if (r.figure)
    md << figure_markdown("mAP and form distance against the number of glues",
                          figure_file_name("noise", o.figure_format))
       << "\n\n";
  else
    md << "No figure: " << r.figure_note << "\n\n";

  change_to_the_highest_level(md, r);
  md << "Data: `noise.csv` (one row per method, level and distance), `noise.json` (also every glued mesh's "
        "seed and χ, and every query's average precision). Figure: `experiments/plots/noise_figure.py "
        "OUT`.\n";
  ExperimentFolder(folder).write_text("report.md", md.str());
}

void write_noise_outputs(const NoiseExperimentResult& r, const std::string& out) {
  const NoiseExperimentOptions& o = r.options;
  const ExperimentFolder folder(out);
  folder.write("noise.csv", [&](std::ostream& out) {
    out.precision(10);
    out << "method,level,distance,queries,map,nn,form_rms_median,form_rms_mean,form_poses,"
           "map_clean_same_poses\n";
    for (const NoiseRow& row : r.rows)
      out << row.method << ',' << row.level << ',' << row.distance << ',' << row.queries << ',' << row.map
          << ',' << row.nn << ',' << row.form_rms_median << ',' << row.form_rms_mean << ',' << row.form_poses
          << ',' << row.map_clean_same_poses << '\n';
  });
  {
    json j;
    j["data"] = o.data;
    j["methods"] = o.methods;
    j["levels"] = o.levels;
    j["seed"] = o.seed;
    j["relax_steps"] = o.relax_steps;
    j["distances"] = {"hausdorff", "chamfer", "rmse"};
    for (const std::string& m : o.methods) {
      CanonicalFormOptions co = o.canon;
      co.method = m;
      j["canonical_form_options"][m] = canonical_form_key(co);
    }
    j["poses"] = json::array();
    for (const NoisePose& p : r.pose_list)
      j["poses"].push_back({{"name", p.name},
                            {"class", p.class_name},
                            {"file", p.file},
                            {"vertices", p.vertices},
                            {"chi", p.chi}});
    j["glues"] = json::array();
    for (const NoiseGlue& g : r.glues)
      j["glues"].push_back({{"shape", g.shape},
                            {"level", g.level},
                            {"seed", g.seed},
                            {"chi_before", g.chi_before},
                            {"chi_after", g.chi_after},
                            {"chi_expected", g.chi_expected},
                            {"ok", g.ok},
                            {"error", g.error},
                            {"relax_steps_used", g.relax_steps_used}});
    j["chi_mismatches"] = r.chi_mismatches;
    j["glue_failures"] = r.glue_failures;
    j["rows"] = json::array();
    for (const NoiseRow& row : r.rows)
      j["rows"].push_back({{"method", row.method},
                           {"level", row.level},
                           {"distance", row.distance},
                           {"queries", row.queries},
                           {"map", row.map},
                           {"nn", row.nn},
                           {"form_rms_median", row.form_rms_median},
                           {"form_rms_mean", row.form_rms_mean},
                           {"form_poses", row.form_poses},
                           {"map_clean_same_poses", row.map_clean_same_poses}});
    j["pose_variation"] = r.pose_variation;
    j["queries"] = r.per_query;
    j["form_rms"] = r.form_rms;
    if (!r.failures.empty()) j["failures"] = shape_failures_json(r.failures);
    j["build"] = build_json();
    folder.write_json("noise.json", j);
  }
}

}  // namespace cshapes
