// The progress= keyword of the long calls (canonical forms, geodesics, distance matrices, experiments): the
// library's progress reports (support/progress.h, what the CLI prints as "[coulomb]  42.0% (about 12 s
// left)") handed to a Python callable progress(stage, fraction, seconds_left). cshapes/_api.py turns
// progress=True (or None on a terminal) into its one-line bar; here it is None (no reports) or a callable.
//
// The library reports from whichever thread runs, without the GIL (Computing): the callable is called with
// the GIL taken, one call at a time, at most about ten times a second per call (a stage's start and end
// always), with fractions that never decrease within a stage. seconds_left is None until the estimate means
// something (support/progress.h: seconds_left_estimate). KeyboardInterrupt raised by the callable stops the
// call as Ctrl-C does; any other exception stops it too and is raised by the call, as the callable raised it.
// Ctrl-C itself is heard as before (python/interrupt.h), with or without a callable.
#pragma once

#include <pybind11/pybind11.h>

#include <memory>

#include "cshapes/support/progress.h"
#include "python/convert.h"

namespace cshapes::python {

class PythonProgress {
 public:
  // callback: None or a callable (anything else is refused: TypeError naming `function`). GIL held.
  PythonProgress(const pybind11::object& callback, const std::string& function);
  // The reports to give the library's options: Ctrl-C polls, and the callable's calls when there is one.
  ProgressFn fn() const;
  // Runs compute() in a Computing scope (the GIL released, Ctrl-C heard). When it stopped because the
  // callable raised, that exception is raised instead of KeyboardInterrupt.
  template <class Compute>
  auto run(Compute&& compute) const -> decltype(compute()) {
    try {
      Computing computing;
      return compute();
    } catch (const Cancelled&) {
      raise_callback_error();
      throw;
    }
  }

 private:
  void raise_callback_error() const;  // GIL held
  struct State;
  std::shared_ptr<State> state_;
};

}  // namespace cshapes::python
