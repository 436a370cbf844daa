// Ctrl-C in long calls: the library runs without the GIL (Computing), so Python's SIGINT handler cannot run
// until the call returns (a Coulomb form of 469 s heard Ctrl-C at its end). The library reports progress
// often (each Coulomb or SMACOF iteration, each Lanczos product); this progress callback
// takes the GIL there for a moment and lets Python run its signal handlers. KeyboardInterrupt (or whatever a
// handler raises) then stops the computation and reaches the caller.
//
// Only for loops that call progress outside OpenMP constructs (Coulomb, SMACOF, classical MDS): an exception
// must not leave a parallel region or a critical section (the geodesics' and the pairwise distances' reports
// are inside them). Called from another thread than the caller's, it does nothing.
#pragma once

#include "core/progress.h"

namespace cshapes::python {

// A ProgressFn that raises Python's pending signal (py::error_already_set) on the calling thread.
ProgressFn stop_on_python_signals();

}  // namespace cshapes::python
