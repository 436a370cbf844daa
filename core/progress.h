// Progress reporting for long computations. The library never prints: long-running functions take an
// optional callback in their options, and the CLI passes one that writes to stderr.
#pragma once

#include <functional>
#include <string>

namespace cshapes {

// stage: what is being done ("coulomb", "geodesics"); done / total: units of work finished so far.
using ProgressFn = std::function<void(const std::string& stage, double done, double total)>;

}  // namespace cshapes
