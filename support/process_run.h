// One run of a shell command (/bin/sh -c) in its own process group, for a program from outside the library
// (pipeline/outside_methods.h): stdout and stderr into files, stdin from /dev/null, stopped past
// timeout_seconds (the whole group killed: SIGTERM, then SIGKILL two seconds later), `progress` polled while it
// runs (a stop kills the group and rethrows). No process of the group outlives the call.
#pragma once

#include <sys/resource.h>

#include <string>

#include "cshapes/support/progress.h"

namespace cshapes {

struct ProcessRun {
  int status = 0;  // waitpid's
  bool timed_out = false;
  struct rusage usage {};  // the shell's and its children's (peak memory: ru_maxrss, KiB)
  double seconds = 0;
};

// Throws cshapes::Error naming `where` when the process cannot be started or waited for. `stage` is the
// progress stage polled.
ProcessRun run_process(const std::string& command, const std::string& out_path, const std::string& err_path,
                       double timeout_seconds, const ProgressFn& progress, const std::string& stage,
                       const std::string& where);

}  // namespace cshapes
