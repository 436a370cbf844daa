// Minimal first version: OFF only. The full set of formats is built on this file (see core/io.h).
#include "core/io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"

namespace cshapes {

std::string file_extension(const std::string& path) {
  auto slash = path.find_last_of('/');
  auto dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

namespace {

// Splits text into whitespace-separated tokens, skipping '#' comments, remembering each token's line.
class Tokenizer {
 public:
  Tokenizer(const std::string& path, const std::string& text) : path_(path), text_(text) {}
  bool next(std::string& token) {
    while (pos_ < text_.size()) {
      char c = text_[pos_];
      if (c == '\n') {
        ++line_;
        ++pos_;
      } else if (std::isspace(static_cast<unsigned char>(c))) {
        ++pos_;
      } else if (c == '#') {
        while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
      } else {
        size_t start = pos_;
        while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_])) && text_[pos_] != '#')
          ++pos_;
        token.assign(text_, start, pos_ - start);
        token_line_ = line_;
        return true;
      }
    }
    return false;
  }
  std::string where() const { return detail::concat(path_, ":", token_line_); }
  std::string token(const char* what) {
    std::string t;
    if (!next(t)) fail(path_, ":", line_, ": unexpected end of file, expected ", what);
    return t;
  }
  double real(const char* what) {
    std::string t = token(what);
    char* end = nullptr;
    double v = std::strtod(t.c_str(), &end);
    if (end == t.c_str() || *end != '\0') fail(where(), ": expected ", what, ", found '", t, "'");
    return v;
  }
  long integer(const char* what) {
    std::string t = token(what);
    char* end = nullptr;
    long v = std::strtol(t.c_str(), &end, 10);
    if (end == t.c_str() || *end != '\0') fail(where(), ": expected ", what, ", found '", t, "'");
    return v;
  }
  int line() const { return token_line_; }

 private:
  const std::string& path_;
  const std::string& text_;
  size_t pos_ = 0;
  int line_ = 1;
  int token_line_ = 1;
};

Mesh read_off(const std::string& path, const std::string& text) {
  Tokenizer tok(path, text);
  std::string header = tok.token("an OFF header");
  if (header != "OFF" && header != "COFF" && header != "NOFF" && header != "CNOFF")
    fail(tok.where(), ": expected an OFF header, found '", header.substr(0, 40), "'");
  long nv = tok.integer("the vertex count"), nf = tok.integer("the face count");
  tok.integer("the edge count");
  if (nv < 0 || nf < 0) fail(tok.where(), ": negative vertex or face count");
  Mesh mesh;
  mesh.V.resize(nv, 3);
  std::vector<Eigen::Vector3i> tris;
  for (long i = 0; i < nv; ++i)
    for (int c = 0; c < 3; ++c) mesh.V(i, c) = tok.real("a vertex coordinate");
  for (long f = 0; f < nf; ++f) {
    long k = tok.integer("a face's vertex count");
    int line = tok.line();
    if (k < 3) fail(path, ":", line, ": face ", f, " has ", k, " vertices, expected at least 3");
    std::vector<int> poly(k);
    for (long j = 0; j < k; ++j) {
      long idx = tok.integer("a face vertex index");
      if (idx < 0 || idx >= nv)
        fail(path, ":", line, ": face ", f, " has vertex index ", idx, ", expected 0..", nv - 1);
      poly[j] = static_cast<int>(idx);
    }
    for (long j = 1; j + 1 < k; ++j) tris.emplace_back(poly[0], poly[j], poly[j + 1]);
  }
  mesh.F.resize(tris.size(), 3);
  for (size_t f = 0; f < tris.size(); ++f) mesh.F.row(f) = tris[f];
  return mesh;
}

void write_off(std::ostream& out, const Mesh& mesh) {
  out << "OFF\n" << mesh.num_vertices() << ' ' << mesh.num_faces() << " 0\n" << std::setprecision(17);
  for (Index i = 0; i < mesh.num_vertices(); ++i)
    out << mesh.V(i, 0) << ' ' << mesh.V(i, 1) << ' ' << mesh.V(i, 2) << '\n';
  for (Index f = 0; f < mesh.num_faces(); ++f)
    out << "3 " << mesh.F(f, 0) << ' ' << mesh.F(f, 1) << ' ' << mesh.F(f, 2) << '\n';
}

}  // namespace

void validate_mesh(const Mesh& mesh, const std::string& name) {
  if (mesh.num_vertices() == 0) fail(name, ": empty mesh (no vertices)");
  for (Index i = 0; i < mesh.num_vertices(); ++i)
    if (!mesh.V.row(i).allFinite()) fail(name, ": vertex ", i, " has a non-finite coordinate (NaN or Inf)");
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c)
      if (mesh.F(f, c) < 0 || mesh.F(f, c) >= mesh.num_vertices())
        fail(name, ": face ", f, " has vertex index ", mesh.F(f, c), ", expected 0..", mesh.num_vertices() - 1);
    if (mesh.F(f, 0) == mesh.F(f, 1) || mesh.F(f, 1) == mesh.F(f, 2) || mesh.F(f, 0) == mesh.F(f, 2))
      fail(name, ": face ", f, " is degenerate (repeats vertex index)");
  }
  Edges E = mesh_edges(mesh.F);
  Eigen::VectorXd d = edge_lengths(mesh.V, E);
  for (Index e = 0; e < E.rows(); ++e)
    if (d[e] == 0) fail(name, ": edge (", E(e, 0), ", ", E(e, 1), ") has zero length (coincident vertices)");
  std::vector<int> counts = edge_face_counts(mesh.F, E);
  for (Index e = 0; e < E.rows(); ++e)
    if (counts[e] > 2)
      fail(name, ": edge (", E(e, 0), ", ", E(e, 1), ") is non-manifold (shared by ", counts[e], " faces)");
}

Mesh read_mesh(const std::string& path, const ReadOptions& options) {
  std::string ext = file_extension(path);
  std::string text = read_file(path);
  Mesh mesh;
  if (ext == "off") {
    mesh = read_off(path, text);
  } else {
    fail(path, ": unknown mesh format '.", ext, "', expected .off");
  }
  if (options.validate) validate_mesh(mesh, path);
  return mesh;
}

void write_mesh(const std::string& path, const Mesh& mesh, const WriteOptions&) {
  std::string ext = file_extension(path);
  if (ext != "off") fail(path, ": cannot write format '.", ext, "', expected .off");
  write_file_atomically(path, [&](std::ostream& out) { write_off(out, mesh); });
}

}  // namespace cshapes
