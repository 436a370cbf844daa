// Mesh I/O: format dispatch, validation, the shared text scanner, and the OFF/OBJ/XYZ writers.
//
// Why our own readers rather than CGAL's (CGAL::IO::read_OFF/read_PLY/read_OBJ/read_STL): CGAL's readers
// report failure as a bare `false` with no line number or element, accept malformed input silently (extra or
// missing tokens on a line, out-of-range indices in some paths, NaN coordinates), and allocate from header
// counts without checking them against the file size, so a hostile count is a huge allocation. The issue asks
// for a one-line error naming the file and the element, and the fuzzers require no crash and no huge
// allocation on any input; that is easier to guarantee in a few hundred lines we own. CGAL has no TOSCA
// .vert/.tri or XYZ mesh reader anyway.
#include "cshapes/mesh/io.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <ostream>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io_formats.h"
#include "cshapes/mesh/mesh_defects.h"

namespace cshapes {

std::string file_extension(const std::string& path) {
  auto slash = path.find_last_of('/');
  auto dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

namespace io_detail {

std::string printable(std::string_view token) {
  constexpr size_t max_shown = 32;
  std::string out;
  for (size_t i = 0; i < token.size() && i < max_shown; ++i) {
    unsigned char c = token[i];
    out += (c >= 32 && c < 127) ? static_cast<char>(c) : '?';
  }
  if (token.size() > max_shown) out += "...";
  return out;
}

namespace {
bool is_newline(char c) {
  return c == '\n';
}
bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}
}  // namespace

bool TextScanner::next(std::string_view& token) {
  while (pos_ < text_.size()) {
    char c = text_[pos_];
    if (is_newline(c)) {
      ++line_;
      ++pos_;
    } else if (is_blank(c)) {
      ++pos_;
    } else if (c == '#' && hash_comments_) {
      while (pos_ < text_.size() && !is_newline(text_[pos_])) ++pos_;
    } else {
      return next_on_line(token);
    }
  }
  token_line_ = line_;
  return false;
}

bool TextScanner::next_on_line(std::string_view& token) {
  while (pos_ < text_.size() && is_blank(text_[pos_])) ++pos_;
  if (pos_ >= text_.size() || is_newline(text_[pos_])) return false;
  if (text_[pos_] == '#' && hash_comments_) {
    skip_line();
    return false;
  }
  size_t start = pos_;
  while (pos_ < text_.size() && !is_newline(text_[pos_]) && !is_blank(text_[pos_]) &&
         !(hash_comments_ && text_[pos_] == '#'))
    ++pos_;
  token = text_.substr(start, pos_ - start);
  token_line_ = line_;
  return true;
}

void TextScanner::skip_line() {
  while (pos_ < text_.size() && !is_newline(text_[pos_])) ++pos_;
}

std::string TextScanner::where() const {
  return detail::concat(name_, ":", token_line_);
}

std::string_view TextScanner::token(const char* what) {
  std::string_view t;
  if (!next(t)) fail(name_, ":", line_, ": unexpected end of file (truncated?), expected ", what);
  return t;
}

std::string_view TextScanner::token_on_line(const char* what) {
  std::string_view t;
  if (!next_on_line(t)) {
    if (pos_ >= text_.size())
      fail(name_, ":", line_, ": unexpected end of file (truncated?), expected ", what);
    fail(name_, ":", line_, ": line ends early, expected ", what);
  }
  return t;
}

double TextScanner::to_real(std::string_view t, const char* what) const {
  double v = 0;
  if (!parse_real(t, v)) fail(where(), ": expected ", what, ", found '", printable(t), "'");
  return v;
}

long long TextScanner::to_integer(std::string_view t, const char* what) const {
  long long v = 0;
  if (!parse_integer(t, v)) fail(where(), ": expected ", what, " (an integer), found '", printable(t), "'");
  return v;
}

bool parse_real(std::string_view t, double& value) {
  if (!t.empty() && t[0] == '+') t.remove_prefix(1);
  if (t.empty()) return false;
  auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
  if (ec == std::errc::result_out_of_range && end == t.data() + t.size()) {
    // Overflow reads as +-Inf (then refused as non-finite, with its line), underflow as 0 or a denormal.
    value = std::strtod(std::string(t).c_str(), nullptr);
    return true;
  }
  return ec == std::errc() && end == t.data() + t.size();
}

bool parse_integer(std::string_view t, long long& value) {
  if (!t.empty() && t[0] == '+') t.remove_prefix(1);
  if (t.empty()) return false;
  auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
  return ec == std::errc() && end == t.data() + t.size();
}

Mesh MeshBuilder::mesh() const {
  Mesh m;
  m.V = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(coords.data(),
                                                                                    num_vertices(), 3);
  m.F = Eigen::Map<const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>>(triangles.data(),
                                                                                 triangles.size() / 3, 3);
  return m;
}

void put_real(std::ostream& out, double v) {
  char buffer[32];
  auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
  out.write(buffer, result.ptr - buffer);
}

}  // namespace io_detail

namespace {

using namespace io_detail;

void put_point(std::ostream& out, const Points& V, Index i) {
  put_real(out, V(i, 0));
  out << ' ';
  put_real(out, V(i, 1));
  out << ' ';
  put_real(out, V(i, 2));
}

void write_off(std::ostream& out, const Mesh& mesh) {
  out << "OFF\n" << mesh.num_vertices() << ' ' << mesh.num_faces() << " 0\n";
  for (Index i = 0; i < mesh.num_vertices(); ++i) {
    put_point(out, mesh.V, i);
    out << '\n';
  }
  for (Index f = 0; f < mesh.num_faces(); ++f)
    out << "3 " << mesh.F(f, 0) << ' ' << mesh.F(f, 1) << ' ' << mesh.F(f, 2) << '\n';
}

void write_obj(std::ostream& out, const Mesh& mesh) {
  out << "# cshapes: " << mesh.num_vertices() << " vertices, " << mesh.num_faces() << " triangles\n";
  for (Index i = 0; i < mesh.num_vertices(); ++i) {
    out << "v ";
    put_point(out, mesh.V, i);
    out << '\n';
  }
  // OBJ indices are 1-based.
  for (Index f = 0; f < mesh.num_faces(); ++f)
    out << "f " << mesh.F(f, 0) + 1 << ' ' << mesh.F(f, 1) + 1 << ' ' << mesh.F(f, 2) + 1 << '\n';
}

void write_xyz(std::ostream& out, const Mesh& mesh) {
  for (Index i = 0; i < mesh.num_vertices(); ++i) {
    put_point(out, mesh.V, i);
    out << '\n';
  }
}

// Text with a leading UTF-8 byte-order mark (some editors write one) is read without it; a binary STL's
// 80-byte header may start with any bytes, so there it is dropped only when the size does not say binary.
std::string_view without_bom(std::string_view bytes, const std::string& format) {
  if (!starts_with_utf8_bom(bytes)) return bytes;
  if (format == "stl" && bytes.size() >= 84) {
    uint32_t count = 0;
    std::memcpy(&count, bytes.data() + 80, 4);
    if (84 + 50 * static_cast<uint64_t>(count) == bytes.size()) return bytes;
  }
  return bytes.substr(3);
}

MeshFile parse_by_format(const std::string& raw_bytes, const std::string& format, const std::string& name) {
  const std::string_view bytes = without_bom(raw_bytes, format);
  if (format == "off") return parse_off(name, bytes);
  if (format == "ply") return parse_ply(name, bytes);
  if (format == "obj") return parse_obj(name, bytes);
  if (format == "stl") return parse_stl(name, bytes);
  if (format == "xyz") return parse_xyz(name, bytes);
  fail(name, ": unknown mesh format '", format.empty() ? "" : ".", printable(format),
       "', expected .off, .ply, .obj, .stl, .vert/.tri or .xyz");
}

// Rows with non-finite coordinates that the file marks invalid (PLY "valid" = 0; parse_ply lets no other
// through) are left out: of the mesh, with every face on them, and of the scalars and colours.
void drop_invalid_rows(MeshFile& file) {
  const Index n = file.mesh.num_vertices();
  const VertexScalar* valid = nullptr;
  for (const VertexScalar& s : file.scalars)
    if (s.name == "valid" && s.values.size() == n) valid = &s;
  if (!valid) return;
  std::vector<Index> kept;
  std::vector<int> new_index(static_cast<size_t>(n), -1);
  for (Index i = 0; i < n; ++i)
    if (file.mesh.V.row(i).allFinite() || valid->values[i] != 0) {
      new_index[static_cast<size_t>(i)] = static_cast<int>(kept.size());
      kept.push_back(i);
    }
  if (static_cast<Index>(kept.size()) == n) return;
  const Index m = static_cast<Index>(kept.size());
  Mesh mesh;
  mesh.V.resize(m, 3);
  for (Index k = 0; k < m; ++k) mesh.V.row(k) = file.mesh.V.row(kept[static_cast<size_t>(k)]);
  std::vector<Eigen::Vector3i> faces;
  for (Index f = 0; f < file.mesh.num_faces(); ++f) {
    Eigen::Vector3i face;
    bool on_valid = true;
    for (int c = 0; c < 3; ++c) {
      const int v = file.mesh.F(f, c);
      on_valid = on_valid && v >= 0 && v < n && new_index[static_cast<size_t>(v)] >= 0;
      face[c] = on_valid ? new_index[static_cast<size_t>(v)] : -1;
    }
    if (on_valid)
      faces.push_back(face);
    else
      ++file.invalid_faces;
  }
  mesh.F.resize(static_cast<Index>(faces.size()), 3);
  for (size_t f = 0; f < faces.size(); ++f) mesh.F.row(static_cast<Index>(f)) = faces[f].transpose();
  for (VertexScalar& s : file.scalars) {
    Eigen::VectorXd values(m);
    for (Index k = 0; k < m; ++k) values[k] = s.values[kept[static_cast<size_t>(k)]];
    s.values = std::move(values);
  }
  if (file.colors.rows() == n) {
    Colors colors(m, 3);
    for (Index k = 0; k < m; ++k) colors.row(k) = file.colors.row(kept[static_cast<size_t>(k)]);
    file.colors = std::move(colors);
  }
  file.invalid_vertices = n - m;
  file.file_vertex = std::move(kept);
  file.mesh = std::move(mesh);
}

MeshFile finish(MeshFile file, const std::string& name, const ReadOptions& options) {
  drop_invalid_rows(file);
  check_mesh_arrays(file.mesh, name);
  if (options.validate) validate_mesh(file.mesh, name);
  return file;
}

}  // namespace

// Indices and finiteness: what even an unvalidated load must guarantee, since every later array access
// relies on it. Parsers already report these with line numbers; this is the backstop for all formats and
// the check of meshes that come from memory (the Python module's arrays).
void check_mesh_arrays(const Mesh& mesh, const std::string& name) {
  if (mesh.num_vertices() == 0) fail(name, ": empty mesh (no vertices)");
  for (Index i = 0; i < mesh.num_vertices(); ++i)
    if (!mesh.V.row(i).allFinite()) fail(name, ": vertex ", i, " has a non-finite coordinate (NaN or Inf)");
  for (Index f = 0; f < mesh.num_faces(); ++f)
    for (int c = 0; c < 3; ++c)
      if (mesh.F(f, c) < 0 || mesh.F(f, c) >= mesh.num_vertices())
        fail(name, ": face ", f, " has vertex index ", mesh.F(f, c), ", expected 0..",
             mesh.num_vertices() - 1);
}

void validate_mesh(const Mesh& mesh, const std::string& name) {
  check_mesh_arrays(mesh, name);
  const MeshDefects d = mesh_defects(mesh);
  if (d.repeated_vertex_faces) {
    const int f = d.repeated_vertex_face_examples[0];
    fail(name, ": face ", f, " (", mesh.F(f, 0), " ", mesh.F(f, 1), " ", mesh.F(f, 2),
         ") is degenerate: it repeats a vertex index");
  }
  if (d.duplicate_faces)
    fail(name, ": face ", d.duplicate_face_examples[0][0], " duplicates face ",
         d.duplicate_face_examples[0][1], " (same vertices)");
  if (d.zero_length_edges)
    fail(name, ": edge (", d.zero_length_edge_examples[0][0], ", ", d.zero_length_edge_examples[0][1],
         ") has zero length (coincident vertices)");
  if (d.nonmanifold_edges)
    fail(name, ": edge (", d.nonmanifold_edge_examples[0][0], ", ", d.nonmanifold_edge_examples[0][1],
         ") is non-manifold (shared by ", d.nonmanifold_edge_examples[0][2], " faces)");
}

MeshFile read_mesh_file_from_memory(const std::string& bytes, const std::string& format,
                                    const std::string& name, const ReadOptions& options) {
  return finish(parse_by_format(bytes, format, name), name, options);
}

Mesh read_mesh_from_memory(const std::string& bytes, const std::string& format, const std::string& name,
                           const ReadOptions& options) {
  return read_mesh_file_from_memory(bytes, format, name, options).mesh;
}

Mesh read_vert_tri_from_memory(const std::string& vert_text, const std::string& tri_text,
                               const std::string& vert_name, const std::string& tri_name,
                               const ReadOptions& options) {
  return finish(parse_vert_tri(vert_name, without_bom(vert_text, "vert"), tri_name,
                               without_bom(tri_text, "tri")),
                vert_name, options)
      .mesh;
}

MeshFile read_mesh_file(const std::string& path, const ReadOptions& options) {
  std::string ext = file_extension(path);
  if (ext == "vert" || ext == "tri") {
    std::string partner = vert_tri_partner(path);
    const std::string& vert_path = ext == "vert" ? path : partner;
    const std::string& tri_path = ext == "vert" ? partner : path;
    std::string vert_text, tri_text;
    try {
      vert_text = read_file(vert_path);
      tri_text = read_file(tri_path);
    } catch (const Error& e) {
      fail(e.what(), " (TOSCA meshes are a .vert and a .tri file side by side)");
    }
    return finish(
        parse_vert_tri(vert_path, without_bom(vert_text, "vert"), tri_path, without_bom(tri_text, "tri")),
        path, options);
  }
  // A missing file is reported as such before its format.
  std::string bytes = read_file(path);
  return read_mesh_file_from_memory(bytes, ext, path, options);
}

Mesh read_mesh(const std::string& path, const ReadOptions& options) {
  return read_mesh_file(path, options).mesh;
}

void write_mesh(const std::string& path, const Mesh& mesh, const WriteOptions& options) {
  std::string ext = file_extension(path);
  // A result with dropped vertices (NaN rows, mesh/mesh_repair.h) keeps the input's vertex count in PLY,
  // where a "valid" property (0 on those rows) says which rows hold no position.
  const VertexScalar* valid = nullptr;
  for (const VertexScalar& s : options.scalars)
    if (s.name == "valid" && s.values.size() == mesh.num_vertices()) valid = &s;
  if (ext == "ply" && valid) {
    Mesh finite_rows;  // what check_mesh_arrays may see: the invalid rows' NaN replaced
    finite_rows.F = mesh.F;
    finite_rows.V = mesh.V;
    for (Index i = 0; i < mesh.num_vertices(); ++i)
      if (valid->values[i] == 0) finite_rows.V.row(i).setZero();
    check_mesh_arrays(finite_rows, path);
  } else {
    check_mesh_arrays(mesh, path);
  }
  if (ext == "off") {
    write_file_atomically(path, [&](std::ostream& out) { write_off(out, mesh); });
  } else if (ext == "obj") {
    write_file_atomically(path, [&](std::ostream& out) { write_obj(out, mesh); });
  } else if (ext == "xyz") {
    write_file_atomically(path, [&](std::ostream& out) { write_xyz(out, mesh); });
  } else if (ext == "ply") {
    write_file_atomically(
        path, [&](std::ostream& out) { write_ply(out, mesh, options, path); }, options.binary);
  } else {
    fail(path, ": cannot write format '", ext.empty() ? "" : ".", printable(ext),
         "', expected .off, .ply, .obj or .xyz");
  }
}

}  // namespace cshapes
