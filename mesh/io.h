// Reading and writing meshes and point clouds, with validation on load.
//
// Formats, chosen by the file extension (case-insensitive):
//   .off  OFF, COFF, NOFF, CNOFF, STOFF (colours, normals, texture coordinates ignored), polygons
//         fan-triangulated; one vertex and one face per line, as the format prescribes
//   .ply  ASCII, binary little and big endian; any property layout and list types; faces optional (no faces:
//         a point cloud). Vertex properties other than x, y, z come back as scalars, uchar red/green/blue as
//         colours
//   .obj  v and f records (f a/b/c, a/b, a//c; negative indices), polygons fan-triangulated; the format's
//   other
//         records (vt, vn, g, o, s, usemtl, mtllib, l, ...) skipped, an unknown record refused by its line
//   .stl  ASCII and binary; corners with identical coordinates are merged into shared vertices
//   .vert / .tri  TOSCA's pair: one "x y z" per line, and 1-based "i j k" per line; either path names the
//   pair .xyz  point cloud, "x y z" per line (further columns ignored)
// Every error is a cshapes::Error with a one-line message that starts with "PATH:" (then the line number for
// text formats, or the element index for binary ones) and says what was expected.
// Readers never trust counts in a header: a count larger than the file could hold is refused before any
// allocation, so any input (truncated, garbage, hostile) gives an error, never a crash or a huge allocation.
#pragma once

#include <string>
#include <vector>

#include "cshapes/mesh/mesh.h"

namespace cshapes {

// Reading is lenient, describing is exact: a reader refuses only what is malformed (syntax, counts, indices
// out of range, NaN/Inf coordinates — but for PLY rows marked valid = 0, see MeshFile —, truncation, an empty
// file), and accepts everything a mesh file can
// legally hold: non-manifold edges and vertices, isolated vertices, duplicate and degenerate faces, several
// components, boundaries. mesh/mesh_defects.h describes those; mesh/mesh_repair.h repairs them for a method.
struct ReadOptions {
  // Also refuse the defects validate_mesh names (for stages that cannot repair them); default: lenient.
  bool validate = false;
};

// Reads a mesh or point cloud (its valid vertices: see MeshFile; read_mesh_file tells how many were left
// out). Throws cshapes::Error naming the file (and line or element) on any problem.
Mesh read_mesh(const std::string& path, const ReadOptions& options = {});

// What every mesh the library takes must satisfy, files and arrays alike: at least one vertex, finite
// coordinates, face indices in 0..n−1. Throws cshapes::Error naming `name` and the first offending vertex or
// face ("NAME: face 7 has vertex index 12, expected 0..9").
void check_mesh_arrays(const Mesh& mesh, const std::string& name);

// Checks what stages that need a clean manifold input rely on (remeshing, gluing topological noise),
// throwing with `name` and the first offending element: at least one vertex, finite coordinates, face
// indices in range, no face repeating a vertex, no duplicate face, no zero-length edge, no edge shared by
// more than two faces.
void validate_mesh(const Mesh& mesh, const std::string& name);

// A per-vertex scalar written as a PLY property (e.g. "torn" 0/1, "violation").
struct VertexScalar {
  std::string name;
  Eigen::VectorXd values;  // one per vertex
};

// n×3 RGB colours in [0, 255].
using Colors = Eigen::Matrix<unsigned char, Eigen::Dynamic, 3>;

struct WriteOptions {
  std::vector<VertexScalar> scalars;  // PLY only; ignored (with no error) by other formats
  // n×3 RGB colours in [0, 255], PLY only; empty for none.
  Colors colors;
  bool binary = false;  // PLY: binary little endian instead of ASCII
  // PLY only: "comment" lines of the header, after cshapes' own, each one line of printable text (what made
  // the file: `cshapes canon` writes "method coulomb", which `cshapes show` names its panel by).
  std::vector<std::string> comments;
};

// Writes by extension (.off, .ply, .obj, .xyz). Written to a temporary file and renamed: never partial.
// Coordinates must be finite, except in PLY rows whose "valid" scalar is 0 (vertices a method dropped: their
// NaN is written as nan; reading such a file back leaves those rows out, see MeshFile).
// Coordinates are written with 17 significant digits (ASCII) or as doubles (binary PLY): reading the file
// back gives exactly the same V. PLY scalars are written as double properties, colours as uchar.
void write_mesh(const std::string& path, const Mesh& mesh, const WriteOptions& options = {});

// The lower-cased extension without the dot ("off"), or "" when there is none.
std::string file_extension(const std::string& path);

// What a file holds beyond the mesh: PLY vertex properties other than x, y, z (in file order) and colours
// (uchar red, green, blue; rows = vertices, or empty). Other formats give none.
//
// Invalid vertices: a PLY vertex row with NaN/Inf coordinates is read only when its "valid" property is 0 —
// how canonical forms mark the vertices a repair dropped (write_mesh; `cshapes canon`, `experiment paper`'s
// canon/*/*.ply). Such rows are left out of `mesh` (and of `scalars` and `colors`), with every face that
// uses one of them; `invalid_vertices` and `invalid_faces` count them and `file_vertex` maps the vertices
// kept to their rows in the file. A non-finite row without valid = 0 is refused, as in every other format.
struct MeshFile {
  Mesh mesh;
  std::vector<VertexScalar> scalars;
  Colors colors;
  Index invalid_vertices = 0;      // rows left out (NaN/Inf coordinates, valid = 0)
  Index invalid_faces = 0;         // faces left out because they use such a row
  std::vector<Index> file_vertex;  // mesh vertex k is row file_vertex[k] of the file; empty: the identity
  std::vector<std::string> comments;  // PLY: the header's comment lines, the text after "comment ", in order
};

// read_mesh, keeping PLY's per-vertex scalars and colours.
MeshFile read_mesh_file(const std::string& path, const ReadOptions& options = {});

// Parses a file's contents already in memory (the readers' entry point, used by the fuzzers).
// format: an extension as file_extension gives it ("off", "ply", "obj", "stl", "xyz"); name is used in
// error messages in place of the path. For the TOSCA pair use read_vert_tri_from_memory.
Mesh read_mesh_from_memory(const std::string& text_or_bytes, const std::string& format,
                           const std::string& name, const ReadOptions& options = {});
MeshFile read_mesh_file_from_memory(const std::string& text_or_bytes, const std::string& format,
                                    const std::string& name, const ReadOptions& options = {});

// TOSCA's pair from memory: the .vert text (one "x y z" per line) and the .tri text (1-based "i j k" per
// line).
Mesh read_vert_tri_from_memory(const std::string& vert_text, const std::string& tri_text,
                               const std::string& vert_name, const std::string& tri_name,
                               const ReadOptions& options = {});

}  // namespace cshapes
