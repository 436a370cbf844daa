// libFuzzer target for one mesh reader, chosen at compile time: -DCSHAPES_FUZZ_FORMAT="off" (or ply, obj,
// stl, xyz; "vert" for the TOSCA pair, whose input is the .vert text, a NUL byte, then the .tri text). Any
// cshapes::Error is the expected outcome for bad input; anything else (crash, sanitizer report, other
// exception, leak, huge allocation) is a finding. Built and run by tests/fuzz/run.sh.
#include <cstddef>
#include <cstdint>
#include <string>

#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"

#ifndef CSHAPES_FUZZ_FORMAT
#error "define CSHAPES_FUZZ_FORMAT"
#endif

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  const std::string format = CSHAPES_FUZZ_FORMAT;
  try {
    if (format == "vert") {
      size_t split = bytes.find('\0');
      std::string vert = bytes.substr(0, split);
      std::string tri = split == std::string::npos ? std::string() : bytes.substr(split + 1);
      cshapes::read_vert_tri_from_memory(vert, tri, "fuzz.vert", "fuzz.tri");
    } else {
      cshapes::read_mesh_file_from_memory(bytes, format, "fuzz." + format);
    }
  } catch (const cshapes::Error& e) {
    // Messages must stay on one line whatever the input holds.
    if (std::string(e.what()).find('\n') != std::string::npos) __builtin_trap();
  }
  return 0;
}
