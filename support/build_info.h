// What this binary is: its version, how it was built, and the instruction set its kernels run with. Printed
// by `cshapes --version` and recorded in every bench JSON and experiment report, so a figure can be traced
// to the build and the kernels that produced it.
#pragma once

#include <string>

namespace cshapes {

// "0.1.0".
std::string version();

// "Release, g++ 12.2.0, OpenMP 4.5, CHOLMOD": build type, compiler and the optional parts compiled in.
std::string build_description();

// Several lines for --version: version, build, and the kernels' instruction set (support/simd.h).
std::string version_text();

}  // namespace cshapes
