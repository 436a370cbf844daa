// Internal to the readers and writers of mesh/io.cpp and mesh/io_*.cpp: one parser per format and the text
// scanning they share. Not part of the library's interface (include mesh/io.h instead).
#pragma once

#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "cshapes/mesh/io.h"

namespace cshapes::io_detail {

// Each parser reads a whole file's contents; `name` (the path) starts every error message.
// They check structure, counts, indices and finiteness; validate_mesh checks the rest afterwards.
MeshFile parse_off(const std::string& name, std::string_view text);
MeshFile parse_ply(const std::string& name, std::string_view bytes);
MeshFile parse_obj(const std::string& name, std::string_view text);
MeshFile parse_stl(const std::string& name, std::string_view bytes);
MeshFile parse_xyz(const std::string& name, std::string_view text);
// The partner of a .vert or .tri path (same stem, the other extension).
std::string vert_tri_partner(const std::string& path);
MeshFile parse_vert_tri(const std::string& vert_name, std::string_view vert_text, const std::string& tri_name,
                        std::string_view tri_text);

void write_ply(std::ostream& out, const Mesh& mesh, const WriteOptions& options, const std::string& name);

// A token quoted for an error message: at most 32 characters, non-printable bytes shown as '?', so that the
// message stays on one line whatever the file holds.
std::string printable(std::string_view token);

// Whitespace-separated tokens with line numbers. With hash_comments, '#' starts a comment to the end of line.
class TextScanner {
 public:
  TextScanner(const std::string& name, std::string_view text, bool hash_comments, size_t start = 0,
              int first_line = 1)
      : name_(name),
        text_(text),
        hash_comments_(hash_comments),
        pos_(start),
        line_(first_line),
        token_line_(first_line) {}

  // The next token, on any line; false at the end of the text.
  bool next(std::string_view& token);
  // The next token on the line of the last token; false when that line has no more.
  bool next_on_line(std::string_view& token);
  // Drops the rest of the current line.
  void skip_line();
  // "NAME:LINE" for the last token (or the current position at the end of the text).
  std::string where() const;
  int line() const { return token_line_; }
  size_t position() const { return pos_; }
  size_t remaining_bytes() const { return text_.size() - pos_; }

  // Token readers that fail with "NAME:LINE: expected WHAT, found 'TOKEN'" (or "unexpected end of ...").
  std::string_view token(const char* what);
  std::string_view token_on_line(const char* what);
  double real(const char* what) { return to_real(token(what), what); }
  double real_on_line(const char* what) { return to_real(token_on_line(what), what); }
  long long integer(const char* what) { return to_integer(token(what), what); }
  long long integer_on_line(const char* what) { return to_integer(token_on_line(what), what); }
  double to_real(std::string_view token, const char* what) const;
  long long to_integer(std::string_view token, const char* what) const;

 private:
  const std::string& name_;
  std::string_view text_;
  bool hash_comments_;
  size_t pos_;
  int line_;        // line of pos_
  int token_line_;  // line of the last token
};

// Shortest decimal text that reads back as exactly the same double.
void put_real(std::ostream& out, double value);

// Parses a whole token as a number; false when it is not one (or out of range).
bool parse_real(std::string_view token, double& value);
bool parse_integer(std::string_view token, long long& value);

// Collects vertices and fan-triangulated polygons.
struct MeshBuilder {
  std::vector<double> coords;  // 3 per vertex
  std::vector<int> triangles;  // 3 per triangle
  size_t num_vertices() const { return coords.size() / 3; }
  void add_vertex(double x, double y, double z) { coords.insert(coords.end(), {x, y, z}); }
  // Fan triangulation (0, j, j+1) of a polygon with at least 3 corners.
  void add_polygon(const std::vector<int>& corners) {
    for (size_t j = 1; j + 1 < corners.size(); ++j)
      triangles.insert(triangles.end(), {corners[0], corners[j], corners[j + 1]});
  }
  Mesh mesh() const;
};

}  // namespace cshapes::io_detail
