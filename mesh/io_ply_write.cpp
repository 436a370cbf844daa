// PLY writer: ASCII or binary little endian, with per-vertex scalar properties, uchar colours and comment
// lines (mesh/io.h: WriteOptions).
#include <cstdint>
#include <cstring>
#include <utility>

#include "cshapes/support/error.h"
#include "cshapes/mesh/io_formats.h"

namespace cshapes::io_detail {

void write_ply(std::ostream& out, const Mesh& mesh, const WriteOptions& options, const std::string& name) {
  const Index n = mesh.num_vertices();
  const bool with_colors = options.colors.rows() > 0;
  if (with_colors && options.colors.rows() != n)
    fail(name, ": ", options.colors.rows(), " colours given for ", n, " vertices");
  for (size_t s = 0; s < options.scalars.size(); ++s) {
    const VertexScalar& scalar = options.scalars[s];
    if (scalar.values.size() != n)
      fail(name, ": scalar '", printable(scalar.name), "' has ", scalar.values.size(), " values for ", n,
           " vertices");
    bool plain = !scalar.name.empty();
    for (unsigned char c : scalar.name) plain = plain && c > 32 && c < 127;
    if (!plain)
      fail(name, ": scalar name '", printable(scalar.name), "' is not a PLY property name (no spaces)");
    bool taken = scalar.name == "x" || scalar.name == "y" || scalar.name == "z" ||
                 (with_colors && (scalar.name == "red" || scalar.name == "green" || scalar.name == "blue"));
    for (size_t r = 0; r < s; ++r) taken = taken || options.scalars[r].name == scalar.name;
    if (taken) fail(name, ": scalar name '", scalar.name, "' is used twice");
  }

  for (const std::string& comment : options.comments)
    for (unsigned char c : comment)
      if (c < 32 || c == 127)
        fail(name, ": comment '", printable(comment), "' is not one line of printable text");
  out << "ply\nformat " << (options.binary ? "binary_little_endian" : "ascii") << " 1.0\ncomment cshapes\n";
  for (const std::string& comment : options.comments) out << "comment " << comment << '\n';
  out << "element vertex " << n << "\nproperty double x\nproperty double y\nproperty double z\n";
  for (const VertexScalar& scalar : options.scalars) out << "property double " << scalar.name << '\n';
  if (with_colors) out << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (mesh.num_faces() > 0)
    out << "element face " << mesh.num_faces() << "\nproperty list uchar int vertex_indices\n";
  out << "end_header\n";

  if (options.binary) {
    const uint16_t probe = 1;  // the file is little endian: bytes swapped on a big-endian host
    const bool swap = *reinterpret_cast<const unsigned char*>(&probe) != 1;
    auto put = [&](auto value) {
      unsigned char raw[sizeof value];
      std::memcpy(raw, &value, sizeof value);
      if (swap)
        for (size_t k = 0; k < sizeof value / 2; ++k) std::swap(raw[k], raw[sizeof value - 1 - k]);
      out.write(reinterpret_cast<const char*>(raw), sizeof value);
    };
    for (Index i = 0; i < n; ++i) {
      for (int c = 0; c < 3; ++c) put(mesh.V(i, c));
      for (const VertexScalar& scalar : options.scalars) put(scalar.values[i]);
      if (with_colors)
        for (int c = 0; c < 3; ++c) put(options.colors(i, c));
    }
    for (Index f = 0; f < mesh.num_faces(); ++f) {
      put(static_cast<unsigned char>(3));
      for (int c = 0; c < 3; ++c) put(static_cast<int32_t>(mesh.F(f, c)));
    }
    return;
  }
  for (Index i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) {
      if (c) out << ' ';
      put_real(out, mesh.V(i, c));
    }
    for (const VertexScalar& scalar : options.scalars) {
      out << ' ';
      put_real(out, scalar.values[i]);
    }
    if (with_colors)
      for (int c = 0; c < 3; ++c) out << ' ' << static_cast<int>(options.colors(i, c));
    out << '\n';
  }
  for (Index f = 0; f < mesh.num_faces(); ++f)
    out << "3 " << mesh.F(f, 0) << ' ' << mesh.F(f, 1) << ' ' << mesh.F(f, 2) << '\n';
}

}  // namespace cshapes::io_detail
