// A dataset at one resolution: every mesh remeshed to about N vertices (mesh/remesh.h, CGAL's isotropic
// remeshing) before anything reads it, so that a collection of mixed resolutions runs as the paper's protocol
// does (the `--resample N` of every command that takes a dataset; Python's resample=N).
//
// Each remesh is cached by content (the input file's SHA-256 and the options' key, data/cache.h), so a rerun,
// another experiment on the same collection, or another rank reuses it. What a remesh changed is measured and
// kept with it: the symmetric Hausdorff distance between the input and the remeshed surface (sampled:
// mesh/remesh.h hausdorff_distance projects every vertex, edge midpoint and face centroid of each onto the
// other, a lower bound tight to about half an edge's sag), relative to the input's bounding-box diagonal, and
// the smallest triangle angle before and after.
//
// Imperfect inputs: remeshing needs a manifold triangle mesh, so non-manifold vertices are split and
// zero-area faces dropped first (mesh/mesh_repair.h; every component kept), said in the shape's note. A mesh
// that still cannot be remeshed, or a point cloud, is kept at its own resolution with the reason in its
// note; a file that cannot be read is listed as it is, so the reader downstream reports it as usual.
//
// Output folder: NAME.off per shape, manifest.csv (the input's classes, poses and noisy flags, in its
// order: data/dataset.h) and resample.csv (the measures per shape). Distributed (R > 1 ranks): each rank
// remeshes its share (the inputs by file size, largest first, dealt round-robin) into the cache, then rank 0
// writes the folder; every rank returns the same paths (the folder must be one that every rank sees).
//
// One process: several shapes are remeshed at once, one per thread, since CGAL's remeshing of one mesh is
// serial and remeshing is most of a large collection's first stage. The largest files go first (as the ranks
// deal them), in blocks with the thread count chosen again before each (support/threads.h: refresh_threads),
// and only as many at once as the memory holds (remesh_memory_bytes each): fewer threads, down to one, when
// it is short. A remesh is a function of its input alone, and entries of the same content are left to the
// end, where they read the first one's remesh from the cache; so the files, manifest.csv, resample.csv, the
// cache entries and the computed/cached counts are those of one shape after the other, for any thread count.
// The notes ("[k/N] NAME: ...", k the entries done so far) are said as shapes finish, so their order follows
// the threads; the folder's files keep the dataset's order. A note callback that throws (the user's stop)
// or a shape that fails stops the run: no thread starts another shape, a remesh under way is abandoned at
// its next poll (mesh/remesh.h polls within each attempt; nothing of it is cached), and the first failure
// is rethrown once every thread has stopped. manifest.csv and resample.csv are written only when every
// shape is done; the NAME.off files written by then are complete (written atomically) and their remeshes
// cached, so a rerun reuses them.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "cshapes/support/communicator.h"
#include "cshapes/data/dataset.h"
#include "cshapes/support/progress.h"
#include "cshapes/support/types.h"
#include "cshapes/data/cache.h"
#include "cshapes/pipeline/shape_failures.h"
#include "cshapes/support/option_declaration.h"

namespace cshapes {

// `--resample N` and resample= on every command and function that takes a dataset (declared once,
// support/option_declaration.h); 0 or a count from 4 to 100,000,000 (what the check below and the CLI
// accept).
inline const OptionDeclaration kResampleOption{
    "resample", "--resample",
    "remesh every shape to about N vertices first (CGAL isotropic remeshing, cached by content; the report "
    "gives each remesh's Hausdorff distance and smallest angle); 0: as they are"};

struct ResampleOptions {
  Index vertices = 0;       // vertices wanted per shape (about: within `tolerance`); 0: no resampling
  double tolerance = 0.01;  // accepted relative deviation from `vertices` (mesh/remesh.h)

  template <class Self, class Visit>
  static void for_each_field(Self& o, Visit&& visit) {
    visit("vertices", o.vertices);
    visit("tolerance", o.tolerance);
  }
};

struct ResampledShape {
  std::string name;    // the dataset entry's name
  std::string source;  // the file read
  std::string file;    // the file written (the source itself when it could not be read)
  Index input_vertices = 0, vertices = 0;
  double hausdorff = std::numeric_limits<double>::quiet_NaN();  // / the input's bbox diagonal
  double min_angle_in = std::numeric_limits<double>::quiet_NaN(), min_angle = min_angle_in;  // degrees
  double mean_min_angle = min_angle_in;  // mean over faces of each face's smallest angle, degrees
  bool remeshed = false;  // false: kept at its own resolution (see note)
  bool cached = false;    // this remesh was read from the cache
  std::string note;       // what was repaired first, or why it was not remeshed; "" when nothing to say
};

struct ResampledDataset {
  ResampleOptions options;
  std::string folder;
  std::string data;  // folder/manifest.csv: what to read instead of the input
  std::vector<ResampledShape> shapes;
  long computed = 0, cached = 0;  // remeshes computed here (over all ranks) and read from the cache
  std::vector<DatasetLeftOut> left_out;  // the input's folder entries that are no shape (data/dataset.h)
};

// Remeshes every shape of `data` (a folder, manifest.csv or .cla: data/dataset.h) into `folder`, through
// `cache`. options.vertices must be >= 4, and a remesh of that size must fit in the memory available
// (remesh_memory_bytes): refused before any work, never a fallback for every shape (several at once only as
// far as the memory holds them: above). Throws cshapes::Error for a dataset that cannot be read, and
// cshapes::WriteError for a folder or cache that cannot be written; what `note` throws stops the run.
ResampledDataset resample_dataset(const std::string& data, const ResampleOptions& options,
                                  const std::string& folder, const DiskCache& cache,
                                  const Communicator* communicator = nullptr, const NoteFn& note = {},
                                  bool allow_outside = false);
// The same for a dataset already read (e.g. the shapes an experiment chose from its folder: only those are
// remeshed); its source names it in errors.
ResampledDataset resample_dataset(const Dataset& data, const ResampleOptions& options,
                                  const std::string& folder, const DiskCache& cache,
                                  const Communicator* communicator = nullptr, const NoteFn& note = {});

// Each shape kept at its own resolution (a point cloud, a mesh remeshing fails on), as a kept record of the
// run (pipeline/shape_failures.h, stage "resample", the reason in `fallback`): the drivers append these to
// their failures, so that a fallback is said on stderr, in report.md and in the JSON, never silently. With
// them, the input folder's entries that are no shape (left out, stage "read"): the resampled manifest the
// drivers read next does not list them.
std::vector<ShapeFailure> resample_records(const ResampledDataset& r);

// The measures of a resampled dataset as report text: a summary line (vertex counts, largest Hausdorff
// distance, smallest angle) and a Markdown table, one row per shape. For the experiments' report.md.
std::string resampling_markdown(const ResampledDataset& resampled);

}  // namespace cshapes
