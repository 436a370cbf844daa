// Progress reporting for long computations. The library never prints: long-running functions take an
// optional callback in their options, and the CLI passes one that writes to stderr.
//
// A callback may also stop the computation by throwing (the Python module throws Cancelled on Ctrl-C): every
// long loop is written so that an exception from its callback ends it cleanly, also inside OpenMP regions
// (report_progress_in_parallel), and reaches the caller.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "cshapes/support/error.h"

namespace cshapes {

// stage: what is being done ("coulomb", "geodesics"); done / total: units of work finished so far.
using ProgressFn = std::function<void(const std::string& stage, double done, double total)>;
// One line of text for a front end (a stage's result, a repair, a warning "warning: …"); may be empty.
using NoteFn = std::function<void(const std::string&)>;
// One line on a note channel, when there is one: the one way the library speaks.
inline void say(const NoteFn& note, const std::string& line) {
  if (note) note(line);
}

// The seconds a stage has left, from its elapsed seconds and the fraction done, once an estimate means
// something: after 3 s and 5% of the stage (earlier ones swing widely); nullopt before, and when finished.
inline std::optional<double> seconds_left_estimate(double elapsed, double fraction) {
  if (fraction >= 1 || elapsed < 3 || fraction < 0.05) return std::nullopt;
  return elapsed * (1 / fraction - 1);
}

// What a progress callback throws to stop a computation at the user's request (Ctrl-C in Python). Not a
// cshapes::Error, nor a std::exception: the handlers that take an error for this input's failure (a geodesic
// method's fallback, an experiment's skipped shape, a glue spot tried in vain) must not take the user's stop
// for one and go on. Only catch (...) sees it, and every such handler rethrows.
class Cancelled {
 public:
  const char* what() const noexcept { return "stopped at the user's request"; }
};

// A progress call with an empty stage is a poll: it reports nothing (a printer ignores it) but may throw
// Cancelled. polls_of(fn) gives the inner stages of a run that reports its own progress (an experiment's
// per-shape forms, whose reports would interleave with the run's) the caller's stop without the reports;
// empty when fn is.
ProgressFn polls_of(const ProgressFn& fn);

// fn with every report under `stage` (a stage run once per method, or per shape, named so that its lines say
// which: "distances, classical MDS"); polls pass through as polls. Empty when fn is.
ProgressFn renamed_stage(const ProgressFn& fn, const std::string& stage);

// Calls fn (when set) from inside an OpenMP parallel region, one thread at a time. An exception it throws
// leaves the critical section before it propagates (an exception must not cross one), so the loop's own
// per-iteration catch takes it and rethrows it after the region.
void report_progress_in_parallel(const ProgressFn& fn, const std::string& stage, double done, double total);

}  // namespace cshapes
