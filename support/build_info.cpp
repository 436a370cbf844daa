#include "cshapes/support/build_info.h"

#include <omp.h>

#include "cshapes/support/simd.h"

#ifndef CSHAPES_VERSION_STRING
#define CSHAPES_VERSION_STRING "unknown"
#endif
#ifndef CSHAPES_BUILD_TYPE
#define CSHAPES_BUILD_TYPE "unknown"
#endif

namespace cshapes {

std::string version() {
  return CSHAPES_VERSION_STRING;
}

std::string build_description() {
  std::string out = CSHAPES_BUILD_TYPE;
#if defined(__clang__)
  out += ", clang++ " __clang_version__;
#elif defined(__GNUC__)
  out += ", g++ " __VERSION__;
#endif
  // _OPENMP is the date of the specification: 201511 is OpenMP 4.5, 201811 5.0, 202011 5.1.
  const char* openmp = _OPENMP >= 202011   ? "5.1"
                       : _OPENMP >= 201811 ? "5.0"
                       : _OPENMP >= 201511 ? "4.5"
                                           : "< 4.5";
  out += std::string(", OpenMP ") + openmp;
#ifdef CSHAPES_HAVE_CHOLMOD
  out += ", CHOLMOD";
#endif
  return out;
}

std::string version_text() {
  return "cshapes " + version() + "\nbuild: " + build_description() + "\nkernels: " + simd_description();
}

}  // namespace cshapes
