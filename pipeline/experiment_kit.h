// The experiment kit: what every experiment driver (experiments/) is written with, so that a driver reads as
// a page of library calls.
//
//   ExperimentFolder  the output folder of a run: paths in it, atomic writes of text/JSON/CSV, its caches
//   Notes             the progress and note channels a front end listens to (say(), progress())
//   fixed, percent    numbers in reports, one wording for "not measured" ("—")
//   build_json        what produced a result (version, build, instruction set), for every report and JSON
//
// With pipeline/canonical_forms.h (methods and their cached forms), pipeline/glued_meshes.h (the one glued-
// mesh cache), pipeline/shape_failures.h (per-shape failures) and experiments/figures.h (drawing), this is
// all an experiment needs besides its own measurement. Drivers follow one shape: `run_X(options) → XResult`
// returns data (and writes the data files a rerun or a figure needs), `write_X_report(result, folder)` writes
// report.md from the result alone.
#pragma once

#include <functional>
#include <nlohmann/json_fwd.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "cshapes/support/progress.h"
#include "cshapes/data/cache.h"
#include "cshapes/support/stage_time.h"

namespace cshapes {

// A run's two channels to a front end (the CLI prints them; the Python module and tests may listen or not),
// for code that passes both around together; speaking is support/progress.h's say().
struct Notes {
  ProgressFn progress;  // (stage, done, total)
  NoteFn note;          // one line of text
  void say(const std::string& line) const { cshapes::say(note, line); }
  void report(const std::string& stage, double done, double total) const {
    if (progress) progress(stage, done, total);
  }
};

// The output folder of an experiment run. Every file is written atomically (a temporary file renamed into
// place, support/atomic_file.h): a run that is stopped leaves whole files or none, and a failed write throws
// cshapes::WriteError naming the path.
class ExperimentFolder {
 public:
  // Creates root (and its parents) when missing; throws WriteError when it cannot.
  explicit ExperimentFolder(std::string root);
  const std::string& root() const { return root_; }
  // root/relative.
  std::string path(const std::string& relative) const;
  void write(const std::string& relative, const std::function<void(std::ostream&)>& write) const;
  void write_text(const std::string& relative, const std::string& text) const;
  // Pretty-printed (2 spaces) with a final newline, as every JSON file of cshapes.
  void write_json(const std::string& relative, const nlohmann::json& value) const;
  // root/cache/name: the caches of a run (forms, pairs, misc), so a rerun resumes.
  DiskCache cache(const std::string& name) const;
  std::string cache_directory(const std::string& name) const;

 private:
  std::string root_;
};

// What produced a result: {"version", "build", "simd"} (support/build_info.h, support/simd.h), in every bench JSON
// and experiment JSON. Not the thread count: results do not depend on it, and it may change during a run
// (support/threads.h).
nlohmann::json build_json();
// The same for a report, one sentence: "Computed by cshapes 0.1.0 (Release, g++ 12.2.0, OpenMP 4.5,
// CHOLMOD) with the avx2 (the default; this CPU: baseline, avx2, avx512) kernels."
std::string build_sentence();

// A number in a report: printf-style `decimals` after the point; "—" when not finite (not measured).
std::string fixed(double value, int decimals);
// A fraction as a percentage, "12.34%"; "—" when not finite.
std::string percent(double fraction, int decimals = 2);
// value by a printf format of one double ("%.3f", "%+.3f"); "—" when NaN.
std::string format_number(const char* format, double value);

// A run's profile (support/stage_time.h) as JSON, one object per stage: {"stage", "method", "wall_seconds",
// "cpu_seconds"}.
nlohmann::json stage_times_json(const std::vector<StageTime>& profile);
// The same as a report's table: stage, method, wall and CPU seconds, the cores kept busy (CPU / wall) and the
// share of the `cores` left idle, with a total row; stages of less than a hundredth of the total wall time
// are summed into one row.
std::string stage_times_markdown(const std::vector<StageTime>& profile, int cores);

}  // namespace cshapes
