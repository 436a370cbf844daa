// STL reader, ASCII and binary. STL stores each triangle with its own three corners; corners with identical
// coordinates are merged into one vertex (exact comparison: STL writers repeat the same float bits), so the
// result is an indexed mesh whose connectivity later stages can use.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <unordered_map>

#include "cshapes/support/error.h"
#include "cshapes/mesh/io_formats.h"

namespace cshapes::io_detail {

namespace {

struct CornerHash {
  size_t operator()(const std::array<double, 3>& p) const {
    size_t h = 0;
    for (double c : p) {
      uint64_t bits;
      std::memcpy(&bits, &c, sizeof bits);
      h ^= std::hash<uint64_t>()(bits) + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
    }
    return h;
  }
};

class CornerMerger {
 public:
  int index(double x, double y, double z) {
    // +0.0 turns -0.0 into +0.0, so both spellings of zero are one corner.
    std::array<double, 3> key{x + 0.0, y + 0.0, z + 0.0};
    auto [it, inserted] = ids_.emplace(key, static_cast<int>(builder.num_vertices()));
    if (inserted) builder.add_vertex(key[0], key[1], key[2]);
    return it->second;
  }
  MeshBuilder builder;

 private:
  std::unordered_map<std::array<double, 3>, int, CornerHash> ids_;
};

uint32_t little_endian_u32(const unsigned char* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

float little_endian_f32(const unsigned char* p) {
  uint32_t bits = little_endian_u32(p);
  float v;
  std::memcpy(&v, &bits, sizeof v);
  return v;
}

MeshFile parse_binary_stl(const std::string& name, std::string_view bytes, uint32_t count) {
  // Layout: 80-byte header, uint32 count, then per triangle: normal (3 float32), 3 corners (3 float32 each),
  // uint16 attribute byte count; all little endian.
  CornerMerger merger;
  std::vector<int> corners(3);
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data()) + 84;
  for (uint32_t t = 0; t < count; ++t) {
    const unsigned char* record = data + 50 * size_t(t) + 12;
    for (int c = 0; c < 3; ++c) {
      double xyz[3];
      for (int k = 0; k < 3; ++k) {
        xyz[k] = little_endian_f32(record + 12 * c + 4 * k);
        if (!std::isfinite(xyz[k]))
          fail(name, ": triangle ", t, " corner ", c, " has a non-finite coordinate (NaN or Inf)");
      }
      corners[c] = merger.index(xyz[0], xyz[1], xyz[2]);
    }
    merger.builder.add_polygon(corners);
  }
  MeshFile file;
  file.mesh = merger.builder.mesh();
  return file;
}

MeshFile parse_ascii_stl(const std::string& name, std::string_view text) {
  TextScanner scanner(name, text, false);
  CornerMerger merger;
  std::vector<int> corners;
  auto expect = [&](const char* keyword) {
    std::string_view t = scanner.token(keyword);
    if (t != keyword) fail(scanner.where(), ": expected '", keyword, "', found '", printable(t), "'");
  };
  std::string_view t;
  long long facet = 0;
  bool any_solid = false;
  while (scanner.next(t)) {
    // A file may hold several solids one after the other; all their facets make one mesh.
    if (t != "solid")
      fail(scanner.where(),
           any_solid ? ": expected 'solid' or the end of the file, found '"
                     : ": not an STL file: expected 'solid' or an 84-byte binary header, found '",
           printable(t), "'");
    any_solid = true;
    scanner.skip_line();  // the solid's name
    for (;;) {
      t = scanner.token("'facet' or 'endsolid' (truncated?)");
      if (t == "endsolid") {
        scanner.skip_line();
        break;
      }
      if (t != "facet") fail(scanner.where(), ": expected 'facet' or 'endsolid', found '", printable(t), "'");
      scanner.skip_line();  // the normal, recomputed by whoever needs it
      expect("outer");
      expect("loop");
      corners.clear();
      for (;;) {
        t = scanner.token("'vertex' or 'endloop' (truncated?)");
        if (t == "endloop") break;
        if (t != "vertex")
          fail(scanner.where(), ": expected 'vertex' or 'endloop', found '", printable(t), "'");
        double xyz[3];
        for (int k = 0; k < 3; ++k) {
          xyz[k] = scanner.real_on_line("a vertex coordinate");
          if (!std::isfinite(xyz[k]))
            fail(scanner.where(), ": facet ", facet, " has a non-finite coordinate");
        }
        corners.push_back(merger.index(xyz[0], xyz[1], xyz[2]));
      }
      if (corners.size() < 3)
        fail(scanner.where(), ": facet ", facet, " has ", corners.size(), " vertices, expected 3");
      expect("endfacet");
      merger.builder.add_polygon(corners);
      ++facet;
    }
  }
  if (!any_solid) fail(name, ": empty file, expected an STL mesh");
  MeshFile file;
  file.mesh = merger.builder.mesh();
  return file;
}

}  // namespace

MeshFile parse_stl(const std::string& name, std::string_view bytes) {
  if (bytes.size() >= 84) {
    uint64_t count = little_endian_u32(reinterpret_cast<const unsigned char*>(bytes.data()) + 80);
    if (84 + 50 * count == bytes.size()) return parse_binary_stl(name, bytes, static_cast<uint32_t>(count));
    // Some binary writers start their header with "solid" too: then the size, or control bytes, tell them
    // apart.
    bool ascii = false;
    size_t start = bytes.find_first_not_of(" \t\r\n");
    if (start != std::string_view::npos) ascii = bytes.substr(start, 5) == "solid";
    for (size_t i = 0; ascii && i < std::min<size_t>(bytes.size(), 1024); ++i) {
      unsigned char c = bytes[i];
      if (c < 9 || (c > 13 && c < 32) || c == 127) ascii = false;
    }
    if (!ascii)
      fail(name, ": binary STL header declares ", count, " triangles (", 84 + 50 * count,
           " bytes) but the file has ", bytes.size(), " bytes (truncated or not an STL file)");
  }
  return parse_ascii_stl(name, bytes);
}

}  // namespace cshapes::io_detail
