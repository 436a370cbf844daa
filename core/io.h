// Reading and writing meshes and point clouds, with validation on load.
//
// Formats, chosen by the file extension (case-insensitive):
//   .off  OFF, COFF, NOFF (colours/normals ignored), polygons fan-triangulated
//   .ply  ASCII, binary little and big endian; faces optional (no faces: a point cloud)
//   .obj  v and f records (f a/b/c, a/b, a//c; negative indices), polygons fan-triangulated
//   .stl  ASCII and binary; coincident corners are merged into shared vertices
//   .vert (with .tri beside it) TOSCA's pair: one "x y z" per line, and 1-based "i j k" per line
//   .xyz  point cloud, "x y z" per line
// Every error is a cshapes::Error whose message starts with "PATH:" (and the line number for text formats)
// and says what was expected.
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"

namespace cshapes {

struct ReadOptions {
  // Check the loaded mesh (see validate_mesh); false only loads and checks indices and finiteness.
  bool validate = true;
};

// Reads a mesh or point cloud. Throws cshapes::Error naming the file (and line or element) on any problem.
Mesh read_mesh(const std::string& path, const ReadOptions& options = {});

// Checks what later stages rely on, throwing with `name` and the first offending element:
// at least one vertex, finite coordinates, face indices in range, no face repeating a vertex,
// no zero-length edge, no edge shared by more than two faces.
void validate_mesh(const Mesh& mesh, const std::string& name);

// A per-vertex scalar written as a PLY property (e.g. "torn" 0/1, "violation").
struct VertexScalar {
  std::string name;
  Eigen::VectorXd values;  // one per vertex
};

struct WriteOptions {
  std::vector<VertexScalar> scalars;  // PLY only; ignored (with no error) by other formats
  // n×3 RGB colours in [0, 255], PLY only; empty for none.
  Eigen::Matrix<unsigned char, Eigen::Dynamic, 3> colors;
  bool binary = false;  // PLY: binary little endian instead of ASCII
};

// Writes by extension (.off, .ply, .obj, .xyz). Written to a temporary file and renamed: never partial.
void write_mesh(const std::string& path, const Mesh& mesh, const WriteOptions& options = {});

// The lower-cased extension without the dot ("off"), or "" when there is none.
std::string file_extension(const std::string& path);

}  // namespace cshapes
