// Ctrl-C in long calls. The library runs without the GIL (Computing), so Python's own SIGINT handler can act
// only when the call returns (a Coulomb form of 469 s heard Ctrl-C at its end). So while a call computes,
// an InterruptScope (part of Computing) puts a SIGINT handler in front of Python's: it raises a flag and
// passes the signal on to Python's handler. The progress callback every long call gets
// (stop_on_python_signals) throws Cancelled when the flag is up, from whichever thread reports; the
// library's loops end cleanly on it, OpenMP regions included (support/progress.h), and the module's exception
// translator raises KeyboardInterrupt (running Python's handler first, so a handler the user installed is
// honoured). When SIGINT is ignored or left to its default in Python, nothing is installed.
#pragma once

#include "cshapes/support/progress.h"

namespace cshapes::python {

class InterruptScope {
 public:
  InterruptScope();
  ~InterruptScope();
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;
};

// A ProgressFn that throws Cancelled once Ctrl-C has been pressed during the current call (any thread).
ProgressFn stop_on_python_signals();

}  // namespace cshapes::python
