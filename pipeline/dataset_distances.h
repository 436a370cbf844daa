// The distance matrix of a whole dataset: each shape's canonical form (cached), ICP between every pair
// (cached per pair), the paper's distances. `cshapes distmat` is this call and a CSV writer; the Python
// module and MPI runs call the same function.
//
// Each shape is repaired for the method (pipeline/canonical_forms.h) or, with canon.strict, refused (the
// error is thrown). A file no method can use (unreadable, too few vertices after repair) is skipped with its
// reason unless strict; at least two usable shapes are needed.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "eval/pairwise_distances.h"
#include "pipeline/canonical_forms.h"

namespace cshapes {

struct DatasetDistanceOptions {
  std::string data;            // folder of meshes (class = name without trailing digits) or manifest.csv
  CanonicalFormOptions canon;  // the method and its options (canon.name is set per shape)
  std::string cache_dir;  // canonical forms under cache_dir/forms, pairs under cache_dir/pairs; empty: none
  PairwiseDistanceOptions pairs;                 // ICP options; cache_dir and progress are set here
  ProgressFn progress;                           // stage "distances"
  std::function<void(const std::string&)> note;  // one line per shape (and per repair or skipped file)
};

struct DatasetDistances {
  std::vector<std::string> names;    // usable shapes, in the dataset's order
  std::vector<std::string> classes;  // their classes
  std::vector<std::string> skipped;  // files skipped (not under strict)
  std::vector<std::string> skipped_reasons;
  long forms_computed = 0, forms_cached = 0;
  PairwiseDistanceResult distances;  // N×N over `names`: hausdorff (the paper's), chamfer, rmse
};

DatasetDistances dataset_distances(const DatasetDistanceOptions& options);

}  // namespace cshapes
