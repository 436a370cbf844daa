// Internal to the paper experiment's files: experiments/paper_experiment.cpp (shapes, canonical forms,
// retrieval, the run) and paper_experiment_stages.cpp (the retrieval, noise, point-map and figure stages). What the
// stages share.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "cshapes/data/cache.h"
#include "cshapes/experiments/paper_experiment.h"
#include "cshapes/experiments/paper_report.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/pipeline/canonical_forms.h"
#include "cshapes/support/communicator.h"

namespace cshapes::paper_detail {

struct Shape {
  std::string name;  // file stem, or SOURCE_noisy for shapes glued here
  std::string class_name;
  std::string source_path;  // the file read, or the file written for shapes made here
  std::string source_name;  // noisy shapes made here: the clean pose they were glued from
  bool noisy = false;
  bool in_retrieval = true;  // false: only a reference for the noise measurement
  Mesh mesh;
  std::vector<int> glued;                      // vertices of glued pairs (noisy shapes made here)
  std::string vts;                             // ground-truth correspondence file, when it exists
  std::string key;                             // mesh content key
  std::string defects = "none";                // mesh/mesh_defects.h summary of the mesh as read
  std::map<std::string, std::string> repairs;  // per method: what its repair did ("" when nothing)
  bool untouched = true;  // no method repairs it and it is a manifold surface (geodesics on it as read)
};

// Canonical forms of every shape by one method; MDS methods share one geodesic matrix per shape.
struct MethodForms {
  std::vector<CanonicalForm> forms;  // per shape
  std::vector<std::string> keys;     // per shape: cache key of the form (content key for the pair cache)
};

// What the stages of the experiment share: the options, the shapes, their canonical forms and the report.
struct ExperimentRun {
  explicit ExperimentRun(const PaperExperimentOptions& options)
      : o(options),
        comm(options.communicator ? *options.communicator : single_process()),
        form_cache((std::filesystem::path(options.out) / "cache" / "forms").string()),
        misc_cache((std::filesystem::path(options.out) / "cache" / "misc").string()) {}

  const PaperExperimentOptions& o;
  const Communicator& comm;  // rank 0 writes every output
  DiskCache form_cache, misc_cache;
  std::vector<Shape> shapes;
  std::vector<int> retrieval;               // indices of shapes in the retrieval set
  std::vector<std::string> names, classes;  // of the retrieval set
  std::vector<std::string> class_names;     // distinct classes, in label order
  std::vector<int> labels;
  std::map<std::string, MethodForms> forms;
  PaperReport report;
  PaperExperimentSummary summary;
};

// 3. Distances between canonical forms (ICP, cached), retrieval measures under each distance kind:
// distances/*.csv (Hausdorff), distances/{chamfer,rmse}/*.csv, metrics.json.
void retrieval_stage(ExperimentRun& run);

// 4. Topological noise: each noisy shape against its clean source, per method; noise_effect.csv.
void noise_stage(ExperimentRun& run);

// 5. Point maps induced by aligning canonical forms, against ground-truth correspondences (cached);
// correspondence_error.csv and point_map_pairs.csv.
void point_map_stage(ExperimentRun& run);

// 6. The figures' data (Figures 2-6 unless o.figures is off) and figures.json.
void figure_stage(ExperimentRun& run);

}  // namespace cshapes::paper_detail
