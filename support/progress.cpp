#include "cshapes/support/progress.h"

#include <exception>

namespace cshapes {

void report_progress_in_parallel(const ProgressFn& fn, const std::string& stage, double done, double total) {
  if (!fn) return;
  std::exception_ptr stop;
#pragma omp critical(cshapes_progress)
  {
    try {
      fn(stage, done, total);
    } catch (...) {
      stop = std::current_exception();
    }
  }
  if (stop) std::rethrow_exception(stop);
}

ProgressFn polls_of(const ProgressFn& fn) {
  if (!fn) return {};
  return [fn](const std::string&, double, double) { fn("", 0, 0); };
}

ProgressFn renamed_stage(const ProgressFn& fn, const std::string& stage) {
  if (!fn) return {};
  return [fn, stage](const std::string& s, double done, double total) { fn(s.empty() ? s : stage, done, total); };
}

}  // namespace cshapes
