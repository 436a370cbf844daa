// What every experiment does for methods from outside (pipeline/outside_methods.h), before and after its run.
#pragma once

#include <string>
#include <vector>

#include "cshapes/support/progress.h"

namespace cshapes {

// The top-level entries of an experiment's output folder kept between runs: its cache, and the output of
// outside commands (kept with the forms the cache keeps, so that a resumed run still has their logs).
std::vector<std::string> experiment_kept_folders();

// Before the run: outside command methods keep their stdout and stderr in OUT/method-logs/NAME/SHAPE.*.
void start_outside_methods(const std::string& out);

// After the run, before its outputs are committed: OUT/forms-needed/NAME.csv for each forms-door method that
// lacked forms (said through `note`), OUT/outside-methods.json (name, door, command or folder of each outside
// method), and a section "Methods from outside" appended to OUT/REPORT (the run's report.md or pose.md) when it
// exists. Nothing when `methods` holds none from outside.
void finish_outside_methods(const std::vector<std::string>& methods, const std::string& out, const NoteFn& note,
                            const std::string& report = "report.md");

}  // namespace cshapes
