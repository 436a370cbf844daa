// Readers of the line-oriented text formats: OFF (COFF, NOFF, ...), OBJ, XYZ and TOSCA's .vert/.tri pair.
// OBJ: v and f are read, the format's other records skipped, an unknown record (binary junk) refused.
// Errors name the file and line; counts in headers are checked against the file size before anything is
// reserved, and data after the declared counts is a count mismatch, not silently ignored.
#include <climits>
#include <cmath>

#include "cshapes/support/error.h"
#include "cshapes/mesh/io_formats.h"

namespace cshapes::io_detail {

namespace {

// Three coordinates: the first may start a new line (blank and comment lines are skipped), the other two
// must follow on the same line, so a short line is reported where it is instead of borrowing the next line.
void read_point(TextScanner& scanner, const char* element, long long index, bool first_on_new_line,
                double xyz[3]) {
  static const char* const axis[3] = {"x", "y", "z"};
  for (int c = 0; c < 3; ++c) {
    std::string_view t;
    bool found = (c == 0 && first_on_new_line) ? scanner.next(t) : scanner.next_on_line(t);
    if (!found) {
      if (c == 0)
        fail(scanner.where(), ": unexpected end of file (truncated?), expected ", element, " ", index);
      fail(scanner.where(), ": ", element, " ", index, " has ", c, " coordinate", c == 1 ? "" : "s",
           ", expected 3 (x y z)",
           scanner.remaining_bytes() == 0 ? "; the file ends there (truncated?)" : "");
    }
    if (!parse_real(t, xyz[c]))
      fail(scanner.where(), ": ", element, " ", index, ": expected the ", axis[c], " coordinate, found '",
           printable(t), "'");
    if (!std::isfinite(xyz[c]))
      fail(scanner.where(), ": ", element, " ", index, " has a non-finite ", axis[c], " coordinate (",
           printable(t), ")");
  }
}

// Records of the OBJ format (geometry, grouping, display and free-form statements) that carry nothing the
// surface needs: skipped. Anything else is refused.
bool is_ignored_obj_record(std::string_view keyword) {
  static const char* const known[] = {
      "vt",         "vn",        "vp",     "l",        "p",        "g",    "o",    "s",    "mg",    "usemtl",
      "mtllib",     "maplib",    "usemap", "cstype",   "deg",      "bmat", "step", "curv", "curv2", "surf",
      "parm",       "trim",      "hole",   "scrv",     "sp",       "end",  "con",  "lod",  "ctech", "stech",
      "shadow_obj", "trace_obj", "bevel",  "c_interp", "d_interp", "call", "csh",  "res"};
  for (const char* k : known)
    if (keyword == k) return true;
  return false;
}

void refuse_trailing_data(TextScanner& scanner, const char* what) {
  std::string_view t;
  if (scanner.next(t))
    fail(scanner.where(), ": unexpected data '", printable(t), "' after ", what, " (count mismatch)");
}

}  // namespace

MeshFile parse_off(const std::string& name, std::string_view text) {
  TextScanner scanner(name, text, true);
  std::string_view header = scanner.token("an OFF header");
  // [ST][C][N][4][n]OFF: texture coordinates, colours and normals follow x y z on each vertex line; 4 and n
  // mean other dimensions than 3, which a surface in space cannot have.
  std::string_view kind = header;
  for (std::string_view prefix : {"ST", "C", "N"})
    if (kind.substr(0, prefix.size()) == prefix) kind.remove_prefix(prefix.size());
  if (kind != "OFF") {
    if (kind == "4OFF" || kind == "nOFF")
      fail(scanner.where(), ": '", printable(header), "' (not 3-dimensional) is not supported, expected OFF");
    fail(scanner.where(), ": expected an OFF header (OFF, COFF, NOFF, ...), found '", printable(header), "'");
  }
  // The counts usually start the next line, but some writers put them after the header on its line.
  std::string_view t;
  long long nv = 0;
  if (scanner.next_on_line(t)) {
    if (t == "BINARY") fail(scanner.where(), ": binary OFF is not supported, expected ASCII OFF");
    nv = scanner.to_integer(t, "the vertex count");
  } else {
    nv = scanner.integer("the vertex count");
  }
  long long nf = scanner.integer_on_line("the face count");
  if (scanner.next_on_line(t)) scanner.to_integer(t, "the edge count");  // optional, unused
  if (nv < 0 || nf < 0) fail(scanner.where(), ": negative count (", nv, " vertices, ", nf, " faces)");
  if (nv > INT_MAX || nf > INT_MAX) fail(scanner.where(), ": too many vertices or faces for 32-bit indices");
  // Every vertex and face takes at least one token and a separator: larger counts cannot be right, and
  // refusing them here bounds what is reserved below by a small multiple of the file size.
  const long long room = static_cast<long long>(scanner.remaining_bytes()) + 1;
  if (nv > room / 2 || nf > room / 2 || nv + nf > room / 2)
    fail(scanner.where(), ": header declares ", nv, " vertices and ", nf, " faces, more than the remaining ",
         room - 1, " bytes can hold (truncated file or wrong counts)");

  MeshFile file;
  MeshBuilder builder;
  builder.coords.reserve(3 * nv);
  for (long long i = 0; i < nv; ++i) {
    double xyz[3];
    read_point(scanner, "vertex", i, true, xyz);
    builder.add_vertex(xyz[0], xyz[1], xyz[2]);
    scanner.skip_line();  // colour, normal or texture coordinates
  }
  std::vector<int> polygon;
  for (long long f = 0; f < nf; ++f) {
    std::string_view count_token;
    if (!scanner.next(count_token))
      fail(scanner.where(), ": unexpected end of file (truncated?), expected face ", f, " of ", nf,
           "; the header claims ", nv, " vertices and ", nf, " faces, the file holds ", f,
           " face lines after the vertices (truncated, or a count in the header is larger than the file's)");
    long long k = scanner.to_integer(count_token, "a face's vertex count");
    if (k < 3) fail(scanner.where(), ": face ", f, " has ", k, " vertices, expected at least 3");
    if (k > static_cast<long long>(scanner.remaining_bytes()) / 2)
      fail(scanner.where(), ": face ", f, " declares ", k, " vertices, more than the rest of the file holds");
    polygon.clear();
    for (long long j = 0; j < k; ++j) {
      if (!scanner.next_on_line(t))
        fail(scanner.where(), ": face ", f, " has ", j, " vertex indices, expected ", k);
      long long index = scanner.to_integer(t, "a vertex index");
      if (index < 0 || index >= nv)
        fail(scanner.where(), ": face ", f, " has vertex index ", index, ", expected 0..", nv - 1);
      polygon.push_back(static_cast<int>(index));
    }
    builder.add_polygon(polygon);
    scanner.skip_line();  // face colour
  }
  refuse_trailing_data(scanner, "the vertices and faces the header declares");
  file.mesh = builder.mesh();
  return file;
}

MeshFile parse_obj(const std::string& name, std::string_view text) {
  TextScanner scanner(name, text, true);
  MeshBuilder builder;
  // Positive indices may point forward (to vertices defined later); those are checked at the end.
  struct ForwardReference {
    int line;
    long long face;
    long long index;
  };
  std::vector<ForwardReference> forward;
  std::vector<int> polygon;
  long long num_faces = 0;
  std::string_view keyword, t;
  while (scanner.next(keyword)) {
    if (keyword == "v") {
      double xyz[3];
      read_point(scanner, "vertex", static_cast<long long>(builder.num_vertices()) + 1, false, xyz);
      if (builder.num_vertices() >= static_cast<size_t>(INT_MAX))
        fail(scanner.where(), ": too many vertices");
      builder.add_vertex(xyz[0], xyz[1], xyz[2]);
    } else if (keyword == "f") {
      polygon.clear();
      const long long nv = static_cast<long long>(builder.num_vertices());
      while (scanner.next_on_line(t)) {
        // v, v/vt, v//vn or v/vt/vn: the position index is the part before the first '/'.
        std::string_view position = t.substr(0, t.find('/'));
        long long index = 0;
        if (!parse_integer(position, index) || index == 0)
          fail(scanner.where(), ": face ", num_faces + 1,
               ": expected a vertex reference (v, v/vt, v//vn or v/vt/vn, ", "1-based or negative), found '",
               printable(t), "'");
        // OBJ indices are 1-based; negative ones count back from the last vertex defined so far.
        long long zero_based = index > 0 ? index - 1 : nv + index;
        if (zero_based < 0 || zero_based >= INT_MAX)
          fail(scanner.where(), ": face ", num_faces + 1, " has vertex index ", index, ", expected 1..", nv,
               " or -1..-", nv);
        if (zero_based >= nv) forward.push_back({scanner.line(), num_faces + 1, index});
        polygon.push_back(static_cast<int>(zero_based));
      }
      if (polygon.size() < 3)
        fail(scanner.where(), ": face ", num_faces + 1, " has ", polygon.size(),
             " vertices, expected at least 3");
      builder.add_polygon(polygon);
      ++num_faces;
    } else if (!is_ignored_obj_record(keyword)) {
      // Binary junk or another format: refused where it starts rather than read as an empty mesh.
      fail(scanner.where(), ": unknown OBJ record '", printable(keyword),
           "' (expected v, f or another OBJ keyword such as vt, vn, g, o, s, usemtl; not an OBJ file?)");
    }
    scanner.skip_line();
  }
  for (const ForwardReference& ref : forward)
    if (ref.index > static_cast<long long>(builder.num_vertices()))
      fail(name, ":", ref.line, ": face ", ref.face, " has vertex index ", ref.index, ", expected 1..",
           builder.num_vertices());
  MeshFile file;
  file.mesh = builder.mesh();
  return file;
}

MeshFile parse_xyz(const std::string& name, std::string_view text) {
  TextScanner scanner(name, text, true);
  MeshBuilder builder;
  std::string_view t;
  for (;;) {
    // Peek for the next line's first token by reading it as the x coordinate.
    TextScanner probe = scanner;
    if (!probe.next(t)) break;
    if (builder.num_vertices() >= static_cast<size_t>(INT_MAX)) fail(probe.where(), ": too many points");
    double xyz[3];
    read_point(scanner, "point", static_cast<long long>(builder.num_vertices()), true, xyz);
    builder.add_vertex(xyz[0], xyz[1], xyz[2]);
    scanner.skip_line();  // normals, colours, ...
  }
  MeshFile file;
  file.mesh = builder.mesh();
  return file;
}

std::string vert_tri_partner(const std::string& path) {
  auto dot = path.find_last_of('.');
  std::string stem = path.substr(0, dot);
  std::string ext = file_extension(path);
  if (ext == "vert") return stem + ".tri";
  if (ext == "tri") return stem + ".vert";
  fail(path, ": expected a .vert or .tri path");
}

MeshFile parse_vert_tri(const std::string& vert_name, std::string_view vert_text, const std::string& tri_name,
                        std::string_view tri_text) {
  MeshBuilder builder;
  {
    TextScanner scanner(vert_name, vert_text, false);
    std::string_view t;
    for (;;) {
      TextScanner probe = scanner;
      if (!probe.next(t)) break;
      if (builder.num_vertices() >= static_cast<size_t>(INT_MAX)) fail(probe.where(), ": too many vertices");
      double xyz[3];
      // .vert lines are numbered from 1 like the .tri indices that refer to them.
      read_point(scanner, "vertex", static_cast<long long>(builder.num_vertices()) + 1, true, xyz);
      if (scanner.next_on_line(t))
        fail(scanner.where(), ": unexpected '", printable(t), "' after x y z (expected 3 numbers per line)");
      builder.add_vertex(xyz[0], xyz[1], xyz[2]);
    }
  }
  const long long nv = static_cast<long long>(builder.num_vertices());
  TextScanner scanner(tri_name, tri_text, false);
  std::string_view t;
  std::vector<int> triangle(3);
  for (long long f = 1; scanner.next(t); ++f) {
    for (int c = 0; c < 3; ++c) {
      if (c > 0 && !scanner.next_on_line(t))
        fail(scanner.where(), ": triangle ", f, " has ", c, " indices, expected 3");
      long long index = scanner.to_integer(t, "a 1-based vertex index");
      if (index < 1 || index > nv)
        fail(scanner.where(), ": triangle ", f, " has vertex index ", index, ", expected 1..", nv, " (",
             vert_name, " has ", nv, " vertices)");
      triangle[c] = static_cast<int>(index - 1);
    }
    if (scanner.next_on_line(t))
      fail(scanner.where(), ": unexpected '", printable(t), "' after i j k (expected 3 indices per line)");
    builder.add_polygon(triangle);
  }
  MeshFile file;
  file.mesh = builder.mesh();
  return file;
}

}  // namespace cshapes::io_detail
