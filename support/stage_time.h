// One stage of a run, for its profile: where the time went, and how busy the cores were. Measured with a
// Stopwatch (support/timing.h: stage_time); kept in results and written in reports.
#pragma once

#include <string>

namespace cshapes {

// The stage's name, the method it belongs to ("" for none), its wall seconds, and the CPU seconds of this
// process's threads and of the child processes it waited for: cpu / wall is the number of cores kept busy on
// average.
struct StageTime {
  std::string stage, method;
  double wall_seconds = 0, cpu_seconds = 0;
};

}  // namespace cshapes
