// What the benchmarks (experiments/bench_*.h) share: the machine's state beside a timing, the shared TOSCA
// shapes they default to, and running an anchor (a reference implementation in Python: scikit-learn, Open3D)
// on the very inputs cshapes measured.
//
// An anchor that cannot run (no interpreter with its package, a failing script) is never an error: the
// benchmark reports it as skipped, with the reason (AnchorRun::skipped).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "cshapes/mesh/mesh.h"
#include "cshapes/pipeline/experiment_kit.h"

namespace cshapes {

// Peak resident memory of this process so far, in MB (2^20 bytes; getrusage's ru_maxrss).
double peak_rss_mb();
// The one-minute load average (/proc/loadavg's first field; 0 when unreadable): beside a wall time on a
// shared machine, it says how many other runnable tasks shared the cores.
double load_average();

// A shape of the shared TOSCA data: $CSHAPES_DATA/tosca5k/NAME.off, else ../shared/data/tosca5k/NAME.off
// relative to the working folder (the data beside a checkout, run from its root: docs/data.md). "" when that
// file does not exist.
std::string shared_tosca5k_shape(const std::string& name);

// The mesh a benchmark runs on: the file `path`, or (path "") a torus of about n vertices (n >= 16), a closed
// surface with TOSCA's degree (6) and no special symmetry. source: set to the file, or "torus NUxNV".
Mesh bench_mesh(const std::string& path, int n, std::string& source);

// A Python script that measures an anchor. It runs in a fresh temporary folder (removed afterwards), which
// write_inputs fills first and the script gets as sys.argv[1] (then `arguments`), and it prints its
// measurement on stdout. Inputs that cannot be written (a full disk) are the run's error: write_inputs'
// exception propagates.
struct AnchorScript {
  std::string package;                 // what the anchor needs, for messages ("scikit-learn")
  std::string imports;                 // modules the interpreter must import ("numpy, sklearn.manifold")
  std::string python;                  // interpreter; "": find_python(imports) (experiments/figures.h)
  std::string environment;             // assignments before the command ("OMP_NUM_THREADS=1"); may be ""
  std::string source;                  // the script's Python source
  std::vector<std::string> arguments;  // after the folder
  std::function<void(const std::string& folder)> write_inputs;  // may be empty
};
struct AnchorRun {
  bool ran = false;    // the script exited 0 and printed something
  std::string output;  // its stdout, when ran
  std::string
      skipped;  // why not, when not ran: no interpreter, or the script's exit status and last error line
};
AnchorRun run_python_anchor(const AnchorScript& script);

}  // namespace cshapes
