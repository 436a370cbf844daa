// Form files of methods from outside (pipeline/outside_methods.h): the mesh formats and NumPy's .npy.
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cshapes/mesh/io.h"
#include "cshapes/pipeline/outside_methods.h"
#include "cshapes/support/error.h"

namespace fs = std::filesystem;

namespace cshapes {

namespace {

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  CSHAPES_REQUIRE(in, path, ": cannot be opened");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Reads a .npy array of n×3 doubles or floats.
Points read_npy(const std::string& path) {
  const std::string bytes = file_bytes(path);
  CSHAPES_REQUIRE(bytes.size() >= 10 && bytes.compare(0, 6, "\x93NUMPY") == 0, path,
                  ": not a .npy file (expected the magic \\x93NUMPY)");
  const int major = static_cast<unsigned char>(bytes[6]);
  size_t header_length = 0, at = 0;
  if (major == 1) {
    header_length = static_cast<unsigned char>(bytes[8]) | (static_cast<unsigned char>(bytes[9]) << 8);
    at = 10;
  } else {
    CSHAPES_REQUIRE(bytes.size() >= 12 && (major == 2 || major == 3), path, ": .npy version ", major,
                    " is not supported (expected 1, 2 or 3)");
    for (int k = 3; k >= 0; --k) header_length = (header_length << 8) | static_cast<unsigned char>(bytes[8 + k]);
    at = 12;
  }
  CSHAPES_REQUIRE(at + header_length <= bytes.size(), path, ": truncated .npy header");
  const std::string header = bytes.substr(at, header_length);
  at += header_length;
  auto value_of = [&](const std::string& key) {
    const size_t k = header.find("'" + key + "'");
    CSHAPES_REQUIRE(k != std::string::npos, path, ": .npy header without '", key, "': ", header);
    const size_t colon = header.find(':', k);
    return header.substr(colon + 1);
  };
  const std::string descr = value_of("descr");
  const bool f8 = descr.find("'<f8'") == 0 || descr.find(" '<f8'") == 0;
  const bool f4 = descr.find("'<f4'") == 0 || descr.find(" '<f4'") == 0;
  CSHAPES_REQUIRE(f8 || f4, path, ": .npy of ", descr.substr(0, descr.find(',')),
                  "; expected little-endian float64 ('<f8') or float32 ('<f4')");
  const bool fortran = value_of("fortran_order").find("True") < value_of("fortran_order").find(',');
  const std::string shape_text = value_of("shape");
  long long rows = -1, cols = -1;
  CSHAPES_REQUIRE(std::sscanf(shape_text.c_str(), " (%lld, %lld)", &rows, &cols) == 2 && rows >= 0 && cols == 3,
                  path, ": .npy of shape ", shape_text.substr(0, shape_text.find(')') + 1),
                  "; expected (n, 3)");
  const size_t width = f8 ? 8 : 4;
  CSHAPES_REQUIRE(bytes.size() - at >= static_cast<size_t>(rows) * 3 * width, path, ": .npy data holds ",
                  bytes.size() - at, " bytes; its shape needs ", rows * 3 * static_cast<long long>(width));
  Points X(rows, 3);
  for (long long i = 0; i < rows; ++i)
    for (int c = 0; c < 3; ++c) {
      const size_t k = fortran ? static_cast<size_t>(c) * rows + i : static_cast<size_t>(i) * 3 + c;
      if (f8) {
        double v;
        std::memcpy(&v, bytes.data() + at + k * 8, 8);
        X(i, c) = v;
      } else {
        float v;
        std::memcpy(&v, bytes.data() + at + k * 4, 4);
        X(i, c) = v;
      }
    }
  return X;
}

}  // namespace

Points read_form_file(const std::string& path) {
  if (file_extension(path) == ".npy" || fs::path(path).extension() == ".npy") return read_npy(path);
  const MeshFile file = read_mesh_file(path);
  CSHAPES_REQUIRE(file.invalid_vertices == 0, path, ": ", file.invalid_vertices,
                  " rows are not finite or marked invalid; every row of a form must be a finite point");
  return file.mesh.V;
}

}  // namespace cshapes
