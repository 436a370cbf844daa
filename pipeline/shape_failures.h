// Per-shape failures: one shape never ends an experiment. A shape whose file cannot be used, or whose
// canonical form fails by any method, is left out of the run (by every method, so that methods are compared
// on the same shapes) with its reason; a geodesic method that fails on a shape falls back to the next one
// (heat → fast marching, pipeline/canonical_forms.h) and the shape stays. Every driver (`experiment paper`,
// `noise`, `topkids`, `pose`, `distmat`) carries these records in its result; the CLI ends a run that left a
// shape out with its own exit code (docs/cli.md), and `--strict` (CanonicalFormOptions::strict) stops
// at the first failure instead, as before.
//
// Never a shape's failure: IoError and FileError raised while computing forms (the run's own files: the
// cache, the outputs) and anything that is not a cshapes::Error (out of memory, ...): those end the run.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cshapes/data/dataset.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/support/progress.h"
#include "cshapes/data/cache.h"
#include "cshapes/pipeline/canonical_forms.h"
#include "cshapes/support/option_declaration.h"

namespace cshapes {

// `--strict` and strict= of every run over a dataset (the experiments), declared once
// (support/option_declaration.h).
inline const OptionDeclaration kStrictRunOption{
    "strict", "--strict",
    "stop at the first shape that fails (an error; exit code 1 on the command line) instead of leaving it "
    "out "
    "(named in the failures; exit code 3), with no geodesic fallback; and refuse a mesh a method would have "
    "to "
    "repair (non-manifold for MDS, several components, ...) instead of repairing it"};

struct ShapeFailure {
  std::string name;    // the shape (file stem, or the name of a shape made here)
  std::string path;    // its file
  std::string method;  // the method whose form failed or fell back; "" when the file itself failed
  std::string stage;   // "read" (the file: unreadable, too few vertices, ...), "canonical form",
                       // "geodesics" (a fallback), "form quality" (a form failing its check, kept),
                       // "dataset" (the same bytes as another entry, kept), "resample" (kept at its
                       // own resolution: pipeline/resampled_dataset.h), "alignment" (a form ICP cannot take)
  std::string reason;  // the error's message
  std::string
      fallback;  // "": the shape was left out; else the fallback that kept it (its geodesics_fallback)
  bool left_out() const { return fallback.empty(); }
};

// One line: "NAME left out: the METHOD canonical form failed: REASON", "NAME left out: FILE cannot be used:
// REASON" or "NAME: METHOD: heat geodesics failed (...); fmm instead".
std::string describe(const ShapeFailure& failure);
// How many shapes were left out (distinct name and path among the records that are not fallbacks): one shape
// that failed for several methods counts once ("3 shapes were left out" said so of one shape).
int count_left_out(const std::vector<ShapeFailure>& failures);
// As JSON: [{name, path, method, stage, reason, fallback}], fallback null for shapes left out.
nlohmann::json shape_failures_json(const std::vector<ShapeFailure>& failures);
// What a run leaves out when a form fails: the shape from every method's measurements (the experiments that
// compare methods on the same shapes), or only that form (`experiment invariance`: one case of a shape by one
// method, the shape's other forms measured).
enum class LeftOutScope { Shape, Form };
// report.md's section: "## Shapes left out and fallbacks", a table and a sentence on what it means (worded
// for `scope`); "" when there is no record (a report of a run where nothing failed is unchanged).
std::string shape_failures_markdown(const std::vector<ShapeFailure>& failures,
                                    LeftOutScope scope = LeftOutScope::Shape);

// One record per pair of entries whose files hold the same bytes (Dataset::same_content, stage "dataset"):
// the second entry, kept ("fallback" says so), so that the run says it on stderr, in report.md and the JSON
// while both stay queries. Drivers append them after reading the dataset.
std::vector<ShapeFailure> same_content_records(const Dataset& data);
// The same for the shapes a driver gathered or chose itself (the poses an experiment selected from its
// dataset, a TOPKIDS or TOSCA folder read with its truth files): the pairs of `entries` whose files hold the
// same bytes (data/dataset.h same_content_pairs). kept_as: what both stay in the run ("queries", "poses").
std::vector<ShapeFailure> same_content_records(const std::vector<DatasetEntry>& entries,
                                               const std::string& kept_as = "queries");

// One record per folder entry the dataset left out (Dataset::left_out: a loop of links, a dangling link, a
// FIFO, a second file of one shape name; stage "read", left out). Under strict, throws for the first.
std::vector<ShapeFailure> left_out_records(const std::vector<DatasetLeftOut>& left_out, bool strict = false);
// Appends kept records of the data (same_content_records, resample_records) to a run's failures, each said
// through `note` as it is added: with them in the failures, the CLI says them on stderr (exit_code_for) and
// the report and the JSON list them (shape_failures_markdown, shape_failures_json).
void add_records(std::vector<ShapeFailure>& failures, const std::vector<ShapeFailure>& records,
                 const NoteFn& note);

// The record of a file that cannot be used (stage "read"), for drivers that skip such files (under strict
// they rethrow instead).
ShapeFailure read_failure(const std::string& name, const std::string& path, const Error& error);

// One shape's canonical forms by every method of `options` (cached_canonical_forms). A cshapes::Error from
// any method is appended to `failures` as the shape's record and nullopt returned (the shape is left out by
// every method); IoError, FileError and everything under options[k].strict are rethrown. Forms computed on
// fallback geodesics are returned, each fallback appended to `failures` (once per shape and fallback text);
// so is each form that fails its quality check (stage "form quality": kept, not left out).
// name: the shape's name in the records (options carry its path).
std::optional<std::vector<CachedForm>> shape_canonical_forms(const DiskCache& cache, const Mesh& mesh,
                                                             const std::vector<CanonicalFormOptions>& options,
                                                             const std::string& name,
                                                             std::vector<ShapeFailure>& failures);

// The forms (indices into `forms`; null or empty entries skipped) too far in size from the others for ICP to
// align every pair at one scale (eval/pairwise_distances.h): their size (largest distance of a finite point
// from the centroid) differs from the median form size by more than kIncomparableSizeRatio, so that any two
// forms kept differ by at most its square. A whole set at any finite scale keeps every form; one shape at
// 1e-100 among shapes at 1 is left out. The reason text for such a form is incomparable_size_reason().
inline constexpr double kIncomparableSizeRatio = 1e70;
std::vector<size_t> forms_of_incomparable_size(const std::vector<const Points*>& forms);
std::string incomparable_size_reason();

}  // namespace cshapes
