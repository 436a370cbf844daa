#include "cshapes/mesh/io.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/data/synthetic.h"
#include "tests/test_support.h"

namespace cshapes {
namespace io_test {

namespace fs = std::filesystem;

std::string write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

// A closed mesh whose coordinates need all 17 digits: a torus rotated by an irrational angle.
Mesh test_mesh() {
  Mesh m = torus(9, 7, 2.0, 0.7);
  Eigen::Matrix3d R = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  m.V = (m.V * R.transpose()).eval();
  return m;
}

// Reading `path` fails with a one-line message that names the file and contains every expected part.
// `named` is the file the message must start with (the partner file for a TOSCA pair).
std::string expect_refused(const std::string& path, std::initializer_list<std::string> parts,
                           const std::string& named = "") {
  try {
    read_mesh(path);
  } catch (const Error& e) {
    std::string message = e.what();
    EXPECT_EQ(message.rfind(named.empty() ? path : named, 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    for (const std::string& part : parts) EXPECT_NE(message.find(part), std::string::npos) << message;
    return message;
  }
  ADD_FAILURE() << path << " was accepted";
  return "";
}

void expect_same_mesh(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.V.rows(), b.V.rows());
  ASSERT_EQ(a.F.rows(), b.F.rows());
  EXPECT_TRUE(a.V == b.V) << "vertex positions differ";
  EXPECT_TRUE(a.F == b.F) << "faces differ";
}

// Triangle soups (STL) come back with merged corners in their own vertex order: compare corner positions.
void expect_same_corners(const Mesh& expected, const Mesh& read) {
  ASSERT_EQ(read.F.rows(), expected.F.rows());
  EXPECT_EQ(read.V.rows(), expected.V.rows());
  for (Index f = 0; f < expected.F.rows(); ++f)
    for (int c = 0; c < 3; ++c)
      ASSERT_TRUE(read.V.row(read.F(f, c)) == expected.V.row(expected.F(f, c)))
          << "face " << f << " corner " << c;
}

template <typename T>
void put(std::string& out, T value, bool big_endian) {
  unsigned char raw[sizeof value];
  std::memcpy(raw, &value, sizeof value);
  if (big_endian)  // this test assumes a little-endian host, like every machine cshapes targets
    for (size_t k = 0; k < sizeof value / 2; ++k) std::swap(raw[k], raw[sizeof value - 1 - k]);
  out.append(reinterpret_cast<const char*>(raw), sizeof value);
}

TEST(IoRoundTrip, WrittenFormatsGiveIdenticalMeshes) {
  std::string dir = test::scratch_dir("io");
  Mesh mesh = test_mesh();
  for (const char* name : {"m.off", "m.obj", "m.ply", "m.OFF"}) {
    std::string path = dir + "/" + name;
    write_mesh(path, mesh);
    SCOPED_TRACE(path);
    expect_same_mesh(mesh, read_mesh(path));
  }
  WriteOptions binary;
  binary.binary = true;
  write_mesh(dir + "/b.ply", mesh, binary);
  expect_same_mesh(mesh, read_mesh(dir + "/b.ply"));
  // XYZ keeps only the points.
  write_mesh(dir + "/p.xyz", mesh);
  Mesh cloud = read_mesh(dir + "/p.xyz");
  EXPECT_TRUE(cloud.is_point_cloud());
  EXPECT_TRUE(cloud.V == mesh.V);
  fs::remove_all(dir);
}

TEST(IoRoundTrip, PointCloudPlyHasNoFaceElement) {
  std::string dir = test::scratch_dir("io");
  Mesh cloud;
  cloud.V = test_mesh().V;
  for (bool binary : {false, true}) {
    WriteOptions options;
    options.binary = binary;
    write_mesh(dir + "/c.ply", cloud, options);
    Mesh read = read_mesh(dir + "/c.ply");
    EXPECT_TRUE(read.is_point_cloud());
    EXPECT_TRUE(read.V == cloud.V);
  }
  fs::remove_all(dir);
}

TEST(IoRoundTrip, PlyScalarsAndColours) {
  std::string dir = test::scratch_dir("io");
  Mesh mesh = test_mesh();
  const Index n = mesh.num_vertices();
  WriteOptions options;
  Eigen::VectorXd torn = Eigen::VectorXd::Zero(n), violation = Eigen::VectorXd::Zero(n);
  options.colors.resize(n, 3);
  for (Index i = 0; i < n; ++i) {
    torn[i] = i % 3 == 0;
    violation[i] = std::sqrt(static_cast<double>(i)) / 7.0;
    options.colors.row(i) << static_cast<unsigned char>(i % 256), static_cast<unsigned char>(255 - i % 256),
        17;
  }
  options.scalars = {{"torn", torn}, {"violation", violation}};
  for (bool binary : {false, true}) {
    options.binary = binary;
    SCOPED_TRACE(binary ? "binary" : "ascii");
    write_mesh(dir + "/s.ply", mesh, options);
    MeshFile file = read_mesh_file(dir + "/s.ply");
    expect_same_mesh(mesh, file.mesh);
    ASSERT_EQ(file.scalars.size(), 2u);
    EXPECT_EQ(file.scalars[0].name, "torn");
    EXPECT_EQ(file.scalars[1].name, "violation");
    EXPECT_TRUE(file.scalars[0].values == torn);
    EXPECT_TRUE(file.scalars[1].values == violation);
    EXPECT_TRUE(file.colors == options.colors);
  }
  // Other formats ignore scalars and colours.
  write_mesh(dir + "/s.off", mesh, options);
  expect_same_mesh(mesh, read_mesh(dir + "/s.off"));
  fs::remove_all(dir);
}

// What made a file, in its header's comment lines (`cshapes canon` records its method: `cshapes show` titles
// the form by it), read back in order after cshapes' own; a comment of two lines is refused.
TEST(IoRoundTrip, PlyCommentsAreWrittenAndReadBack) {
  std::string dir = test::scratch_dir("io-comments");
  const Mesh mesh = test_mesh();
  WriteOptions options;
  options.comments = {"method coulomb", "seed 7  "};
  for (bool binary : {false, true}) {
    options.binary = binary;
    write_mesh(dir + "/c.ply", mesh, options);
    const MeshFile file = read_mesh_file(dir + "/c.ply");
    expect_same_mesh(mesh, file.mesh);
    EXPECT_EQ(file.comments, (std::vector<std::string>{"cshapes", "method coulomb", "seed 7"}));
  }
  options.comments = {"two\nlines"};
  EXPECT_THROW(write_mesh(dir + "/bad.ply", mesh, options), Error);
  EXPECT_FALSE(fs::exists(dir + "/bad.ply"));
  fs::remove_all(dir);
}

TEST(IoWrite, RefusesInconsistentScalarsAndUnknownFormats) {
  std::string dir = test::scratch_dir("io");
  Mesh mesh = test_mesh();
  WriteOptions options;
  options.scalars = {{"bad name", Eigen::VectorXd::Zero(mesh.num_vertices())}};
  EXPECT_THROW(write_mesh(dir + "/a.ply", mesh, options), Error);
  options.scalars = {{"short", Eigen::VectorXd::Zero(3)}};
  EXPECT_THROW(write_mesh(dir + "/a.ply", mesh, options), Error);
  options.scalars = {{"x", Eigen::VectorXd::Zero(mesh.num_vertices())}};
  EXPECT_THROW(write_mesh(dir + "/a.ply", mesh, options), Error);
  EXPECT_THROW(write_mesh(dir + "/a.stl", mesh), Error);
  EXPECT_FALSE(fs::exists(dir + "/a.ply"));
  EXPECT_FALSE(fs::exists(dir + "/a.stl"));
  fs::remove_all(dir);
}

TEST(IoRead, BinaryBigEndianPlyWithOtherPropertiesAndElements) {
  std::string dir = test::scratch_dir("io");
  Mesh mesh = test_mesh();
  mesh.V = mesh.V.cast<float>().cast<double>();  // stored as float32 below
  const Index n = mesh.num_vertices();
  // Unusual but legal layout: a list and a scalar before x, a ushort-counted uint index list, an element
  // between vertex and face, and a per-face property after the indices.
  std::string bytes = "ply\nformat binary_big_endian 1.0\ncomment hand-written\n";
  bytes += "element vertex " + std::to_string(n) + "\n";
  bytes += "property list uchar short tags\nproperty float quality\nproperty float x\nproperty float y\n";
  bytes += "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n";
  bytes += "element material 2\nproperty int id\n";
  bytes += "element face " + std::to_string(mesh.num_faces()) + "\n";
  bytes += "property list ushort uint vertex_indices\nproperty double weight\nend_header\n";
  for (Index i = 0; i < n; ++i) {
    put<uint8_t>(bytes, 2, true);
    put<int16_t>(bytes, -5, true);
    put<int16_t>(bytes, 300, true);
    put<float>(bytes, 0.5f * i, true);
    for (int c = 0; c < 3; ++c) put<float>(bytes, static_cast<float>(mesh.V(i, c)), true);
    for (int c = 0; c < 3; ++c) put<uint8_t>(bytes, static_cast<uint8_t>(i + c), true);
  }
  put<int32_t>(bytes, 7, true);
  put<int32_t>(bytes, 8, true);
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    put<uint16_t>(bytes, 3, true);
    for (int c = 0; c < 3; ++c) put<uint32_t>(bytes, static_cast<uint32_t>(mesh.F(f, c)), true);
    put<double>(bytes, 1.25, true);
  }
  std::string path = write_bytes(dir + "/be.ply", bytes);
  MeshFile file = read_mesh_file(path);
  expect_same_mesh(mesh, file.mesh);
  ASSERT_EQ(file.scalars.size(), 1u);
  EXPECT_EQ(file.scalars[0].name, "quality");
  EXPECT_EQ(file.scalars[0].values[3], 1.5);
  ASSERT_EQ(file.colors.rows(), n);
  EXPECT_EQ(file.colors(4, 2), 6);

  // The same body truncated by one byte, and with one byte too many.
  write_bytes(path, bytes.substr(0, bytes.size() - 1));
  expect_refused(path, {"face " + std::to_string(mesh.num_faces() - 1), "truncated"});
  write_bytes(path, bytes + "x");
  expect_refused(path, {"1 bytes after the last element", "count mismatch"});
  fs::remove_all(dir);
}

TEST(IoRead, BinaryFormatsNameTheElement) {
  std::string dir = test::scratch_dir("io");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
      "property double z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  for (double v : {0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, nan}) put<double>(ply, v, false);
  std::string faces;
  put<uint8_t>(faces, 3, false);
  for (int32_t i : {0, 1, 2}) put<int32_t>(faces, i, false);
  std::string path = write_bytes(dir + "/nan.ply", ply + faces);
  expect_refused(path, {path + ": vertex 2", "non-finite z"});
  std::string stl(80, ' ');
  put<uint32_t>(stl, 1, false);
  for (float v :
       {0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, std::numeric_limits<float>::infinity()})
    put<float>(stl, v, false);
  put<uint16_t>(stl, 0, false);
  path = write_bytes(dir + "/inf.stl", stl);
  expect_refused(path, {path + ": triangle 0 corner 2", "non-finite"});
  fs::remove_all(dir);
}

TEST(IoRead, PlyRowsMarkedInvalidAreLeftOutWithTheirFaces) {
  // A canonical form with dropped vertices: NaN rows with valid = 0 (what write_mesh writes for them).
  const std::string dir = test::scratch_dir("io");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Mesh form = icosphere(1);  // 42 vertices, 80 faces
  const Index n = form.num_vertices();
  Eigen::VectorXd valid = Eigen::VectorXd::Ones(n), torn = Eigen::VectorXd::Zero(n);
  for (Index i : {3, 17, 40}) {
    form.V.row(i).setConstant(nan);
    valid[i] = 0;
  }
  torn[41] = 1;
  Index faces_on_invalid = 0;
  for (Index f = 0; f < form.num_faces(); ++f)
    faces_on_invalid += (valid[form.F(f, 0)] == 0 || valid[form.F(f, 1)] == 0 || valid[form.F(f, 2)] == 0);
  ASSERT_GT(faces_on_invalid, 0);
  for (bool binary : {false, true}) {
    SCOPED_TRACE(binary ? "binary" : "ascii");
    const std::string path = dir + (binary ? "/form_b.ply" : "/form_a.ply");
    WriteOptions wo;
    wo.binary = binary;
    wo.scalars = {{"valid", valid}, {"torn", torn}};
    write_mesh(path, form, wo);
    const MeshFile file = read_mesh_file(path);
    EXPECT_EQ(file.invalid_vertices, 3);
    EXPECT_EQ(file.invalid_faces, faces_on_invalid);
    ASSERT_EQ(file.mesh.num_vertices(), n - 3);
    EXPECT_EQ(file.mesh.num_faces(), form.num_faces() - faces_on_invalid);
    EXPECT_TRUE(file.mesh.V.allFinite());
    ASSERT_EQ(file.file_vertex.size(), static_cast<size_t>(n - 3));
    for (Index k = 0; k < file.mesh.num_vertices(); ++k) {
      const Index row = file.file_vertex[static_cast<size_t>(k)];
      EXPECT_EQ(file.mesh.V.row(k), form.V.row(row)) << k;
    }
    // Faces keep their vertices, renumbered.
    for (Index f = 0; f < file.mesh.num_faces(); ++f)
      for (int c = 0; c < 3; ++c) EXPECT_TRUE(file.mesh.V.row(file.mesh.F(f, c)).allFinite());
    // Scalars follow their rows: torn is 1 on the last vertex kept (row 41).
    ASSERT_EQ(file.scalars.size(), 2u);
    EXPECT_EQ(file.scalars[1].name, "torn");
    ASSERT_EQ(file.scalars[1].values.size(), n - 3);
    EXPECT_EQ(file.scalars[1].values[n - 4], 1);
    EXPECT_EQ(file.scalars[1].values.sum(), 1);
    EXPECT_EQ(read_mesh(path).num_vertices(), n - 3);  // read_mesh: the valid vertices
  }
  // NaN on a row the file does not mark invalid is refused, as before: valid = 1, or no valid property.
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
      "property double valid\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const std::string path = write_bytes(dir + "/marked.ply", header +
                                                                "0 0 0 1\n1 0 0 1\nnan nan nan 1\n0 1 0 1\n"
                                                                "3 0 1 3\n");
  expect_refused(path, {"vertex 2", "non-finite x"});
  write_bytes(path, header + "0 0 0 1\n1 0 0 1\nnan nan nan 0\n0 1 0 1\n3 0 1 3\n");
  const MeshFile ok = read_mesh_file(path);
  EXPECT_EQ(ok.invalid_vertices, 1);
  EXPECT_EQ(ok.invalid_faces, 0);
  EXPECT_EQ(ok.mesh.F.row(0), Eigen::RowVector3i(0, 1, 2));  // vertex 3 is now 2
  // valid = 0 on a finite row marks nothing to leave out: the row is kept as read.
  write_bytes(path, header + "0 0 0 1\n1 0 0 0\n1 1 0 1\n0 1 0 1\n3 0 1 3\n");
  EXPECT_EQ(read_mesh_file(path).invalid_vertices, 0);
  EXPECT_EQ(read_mesh(path).num_vertices(), 4);
  // Every row invalid: nothing left to read.
  write_bytes(path, header + "nan 0 0 0\nnan 0 0 0\nnan 0 0 0\nnan 0 0 0\n3 0 1 3\n");
  expect_refused(path, {"empty mesh"});
  fs::remove_all(dir);
}

TEST(IoRead, AsciiPlyPolygonsAndLineNumbers) {
  std::string dir = test::scratch_dir("io");
  std::string header =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
      "element face 1\nproperty list uint8 int32 vertex_index\nend_header\n";
  std::string path = write_bytes(dir + "/q.ply", header + "0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n");
  Mesh quad = read_mesh(path);
  ASSERT_EQ(quad.num_faces(), 2);  // fan-triangulated
  EXPECT_EQ(quad.F.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(quad.F.row(1), Eigen::RowVector3i(0, 2, 3));
  write_bytes(path, header + "0 0 0\n1 0 0\n1 1 nan\n0 1 0\n4 0 1 2 3\n");
  expect_refused(path, {path + ":12:", "vertex 2", "non-finite"});
  write_bytes(path, header + "0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 4\n");
  expect_refused(path, {path + ":14:", "face 0", "vertex index 4"});
  write_bytes(path, header + "0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n5\n");
  expect_refused(path, {path + ":15:", "count mismatch"});
  write_bytes(path, header + "0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1\n");
  expect_refused(path, {"truncated"});
  write_bytes(path,
              "ply\nformat ascii 1.0\nelement vertex 99999999\nproperty float x\nproperty float y\n"
              "property float z\nend_header\n1 2 3\n");
  expect_refused(path, {path + ":3:", "99999999", "truncated"});
  fs::remove_all(dir);
}

TEST(IoRead, OffVariantsAndPolygons) {
  std::string dir = test::scratch_dir("io");
  // COFF: colours after x y z; NOFF: normals; a quad and a face colour; comments.
  std::string coff =
      "COFF\n# a comment\n4 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n1 1 0 0 0 255 255\n"
      "0 1 0 9 9 9 255\n4 0 1 2 3 0.5 0.5 0.5\n";
  Mesh quad = read_mesh(write_bytes(dir + "/c.off", coff));
  ASSERT_EQ(quad.num_vertices(), 4);
  ASSERT_EQ(quad.num_faces(), 2);
  EXPECT_EQ(quad.V.row(2), Eigen::RowVector3d(1, 1, 0));
  EXPECT_EQ(quad.F.row(1), Eigen::RowVector3i(0, 2, 3));
  std::string noff = "NOFF 3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n";
  Mesh tri = read_mesh(write_bytes(dir + "/n.off", noff));
  EXPECT_EQ(tri.num_faces(), 1);
  EXPECT_EQ(tri.V.row(1), Eigen::RowVector3d(1, 0, 0));
  fs::remove_all(dir);
}

TEST(IoRead, ObjIndexFormsAndNegativeIndices) {
  std::string dir = test::scratch_dir("io");
  std::string obj =
      "# quad and triangle\nmtllib x.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0 0.5 0.5 0.5\nv 0 1 0\nvt 0 0\nvn 0 0 1\n"
      "g part\nusemtl m\nf 1/1/1 2/1/1 3/1/1 4/1/1\nv 0 0 1\ns off\nf -1//1 -5//1 -4//1\nf 5/1 2/1 4/1\nl 1 "
      "2\n";
  Mesh mesh = read_mesh(write_bytes(dir + "/m.obj", obj));
  ASSERT_EQ(mesh.num_vertices(), 5);
  ASSERT_EQ(mesh.num_faces(), 4);
  EXPECT_EQ(mesh.F.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(mesh.F.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(mesh.F.row(2), Eigen::RowVector3i(4, 0, 1));
  EXPECT_EQ(mesh.F.row(3), Eigen::RowVector3i(4, 1, 3));
  std::string path = write_bytes(dir + "/bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n");
  expect_refused(path, {path + ":4:", "vertex index -4"});
  write_bytes(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
  expect_refused(path, {path + ":4:", "vertex index 4"});
  write_bytes(path, "v 0 0 0\nv 1 0 inf\nv 0 1 0\nf 1 2 3\n");
  expect_refused(path, {path + ":2:", "non-finite"});
  write_bytes(path, "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n");
  expect_refused(path, {path + ":2:", "2 coordinates"});
  // A line the format does not know (binary junk) is refused by its line, not skipped.
  write_bytes(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n\x89PNG\x01\x02 junk\n");
  expect_refused(path, {path + ":5:", "unknown OBJ record"});
  write_bytes(path, "v 0 0 0\nv 1 0 0\n# fine\nvx 0 1 0\nf 1 2 3\n");
  expect_refused(path, {path + ":4:", "'vx'"});
  // Every legal record it can ignore is accepted.
  write_bytes(path,
              "# c\nmtllib a.mtl\no obj\ng grp\ns 1\nusemtl m\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n"
              "vp 0.5\nf 1 2 3\nl 1 2\np 3\ncstype bezier\ndeg 3\nend\nmg 1\nlod 1\n");
  EXPECT_EQ(read_mesh(path).num_faces(), 1);
  fs::remove_all(dir);
}

std::string ascii_stl(const Mesh& mesh) {
  std::ostringstream out;
  out.precision(17);
  out << "solid test\n";
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    out << "  facet normal 0 0 1\n    outer loop\n";
    for (int c = 0; c < 3; ++c)
      out << "      vertex " << mesh.V(mesh.F(f, c), 0) << ' ' << mesh.V(mesh.F(f, c), 1) << ' '
          << mesh.V(mesh.F(f, c), 2) << '\n';
    out << "    endloop\n  endfacet\n";
  }
  out << "endsolid test\n";
  return out.str();
}

std::string binary_stl(const Mesh& mesh) {
  std::string bytes(80, ' ');
  bytes.replace(0, 5, "solid");  // some writers do this; the size must still identify binary STL
  put<uint32_t>(bytes, static_cast<uint32_t>(mesh.num_faces()), false);
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) put<float>(bytes, 0.0f, false);
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) put<float>(bytes, static_cast<float>(mesh.V(mesh.F(f, c), k)), false);
    put<uint16_t>(bytes, 0, false);
  }
  return bytes;
}

TEST(IoRead, StlAsciiAndBinaryMergeCorners) {
  std::string dir = test::scratch_dir("io");
  Mesh mesh = test_mesh();
  mesh.V = mesh.V.cast<float>().cast<double>();
  expect_same_corners(mesh, read_mesh(write_bytes(dir + "/a.stl", ascii_stl(mesh))));
  std::string binary = binary_stl(mesh);
  expect_same_corners(mesh, read_mesh(write_bytes(dir + "/b.stl", binary)));
  std::string path = write_bytes(dir + "/t.stl", binary.substr(0, binary.size() - 10));
  expect_refused(path, {"declares " + std::to_string(mesh.num_faces()) + " triangles", "truncated"});
  std::string ascii = ascii_stl(mesh);
  write_bytes(path, ascii.substr(0, ascii.size() / 2));
  expect_refused(path, {"truncated"});
  fs::remove_all(dir);
}

TEST(IoRead, OnlyRegularFilesAreReadAndAStreamIsNeverFollowed) {
  // Issue 22: `info /dev/zero` read until the kernel killed it, a FIFO blocked forever, a loop of symbolic
  // links was "no such file".
  const std::string dir = test::scratch_dir("io-special");
  expect_refused("/dev/zero", {"/dev/zero", "character device", "regular file"});
  const std::string fifo = dir + "/pipe.off";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  expect_refused(fifo, {fifo, "FIFO"});
  const std::string loop = dir + "/loop.off";
  fs::create_symlink(dir + "/loop2.off", loop);
  fs::create_symlink(loop, dir + "/loop2.off");
  expect_refused(loop, {loop, "loop of symbolic links"});
  expect_refused(dir + "/absent.off", {"no such file"});
  // A link to a regular file is read through.
  write_mesh(dir + "/real.off", icosphere(0));
  fs::create_symlink(dir + "/real.off", dir + "/link.off");
  EXPECT_EQ(read_mesh(dir + "/link.off").num_vertices(), 12);
  fs::remove_all(dir);
}

TEST(IoRead, AUtf8ByteOrderMarkIsAccepted) {
  // Issue 22: a BOM was refused by every text reader; an ASCII STL with one was read as binary with
  // 1,702,130,277 triangles.
  const std::string dir = test::scratch_dir("io-bom");
  const std::string bom = "\xEF\xBB\xBF";
  Mesh mesh = test_mesh();
  mesh.V = mesh.V.cast<float>().cast<double>();
  write_mesh(dir + "/m.off", mesh);
  write_mesh(dir + "/m.obj", mesh);
  write_mesh(dir + "/m.ply", mesh);
  for (const char* ext : {"off", "obj", "ply"}) {
    const std::string plain = read_file(dir + "/m." + ext);
    const std::string path = write_bytes(dir + "/bom." + ext, bom + plain);
    const Mesh back = read_mesh(path);
    EXPECT_EQ(back.V, read_mesh(dir + "/m." + ext).V) << ext;
    EXPECT_EQ(back.F, mesh.F) << ext;
  }
  expect_same_corners(mesh, read_mesh(write_bytes(dir + "/bom.stl", bom + ascii_stl(mesh))));
  // A binary STL whose 80-byte header happens to start with those bytes stays binary.
  std::string binary = binary_stl(mesh);
  binary.replace(0, 3, bom);
  expect_same_corners(mesh, read_mesh(write_bytes(dir + "/header.stl", binary)));
  EXPECT_EQ(read_text_file(write_bytes(dir + "/t.txt", bom + "a,b\n")), "a,b\n");
  fs::remove_all(dir);
}

TEST(IoRead, PlyTriangleStripsAreRead) {
  // Issue 22: PLY 'tristrips' were silently dropped (0 faces).
  const std::string dir = test::scratch_dir("io-strips");
  const std::string path =
      write_bytes(dir + "/strip.ply",
                  "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\n"
                  "property float z\nelement tristrips 1\nproperty list int int vertex_indices\n"
                  "end_header\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 2 0\n1 2 0\n"
                  "8 0 1 2 3 -1 2 3 4\n");
  const Mesh m = read_mesh(path);
  ASSERT_EQ(m.num_faces(), 3);
  Faces expected(3, 3);
  expected << 0, 1, 2, 2, 1, 3, 2, 3, 4;  // every second triangle of a strip reversed: one orientation
  EXPECT_EQ(m.F, expected);
  write_bytes(
      path,
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element tristrips 1\nproperty list int int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n"
      "3 0 1 7\n");
  expect_refused(path, {"tristrips 0", "vertex index 7"});
  fs::remove_all(dir);
}

TEST(IoRead, ToscaVertTriPairFromEitherPath) {
  std::string dir = test::scratch_dir("io");
  Mesh mesh = test_mesh();
  std::ostringstream vert, tri;
  vert.precision(17);
  for (Index i = 0; i < mesh.num_vertices(); ++i)
    vert << mesh.V(i, 0) << ' ' << mesh.V(i, 1) << ' ' << mesh.V(i, 2) << '\n';
  for (Index f = 0; f < mesh.num_faces(); ++f)
    tri << mesh.F(f, 0) + 1 << ' ' << mesh.F(f, 1) + 1 << ' ' << mesh.F(f, 2) + 1 << '\n';
  write_bytes(dir + "/cat.vert", vert.str());
  write_bytes(dir + "/cat.tri", tri.str());
  expect_same_mesh(mesh, read_mesh(dir + "/cat.vert"));
  expect_same_mesh(mesh, read_mesh(dir + "/cat.tri"));
  write_bytes(dir + "/cat.tri", tri.str() + "1 2 " + std::to_string(mesh.num_vertices() + 1) + "\n");
  expect_refused(dir + "/cat.vert",
                 {dir + "/cat.tri:" + std::to_string(mesh.num_faces() + 1) + ":", "vertex index"},
                 dir + "/cat.tri");
  fs::remove(dir + "/cat.tri");
  expect_refused(dir + "/cat.vert", {"no such file"}, dir + "/cat.tri");
  fs::remove_all(dir);
}

TEST(IoRead, XyzPointCloudWithExtraColumns) {
  std::string dir = test::scratch_dir("io");
  Mesh cloud = read_mesh(write_bytes(dir + "/p.xyz", "# points\n0 0 0 0 0 1\n\n1 2 3 0 0 1\n-1e-3 4 5.5\n"));
  ASSERT_EQ(cloud.num_vertices(), 3);
  EXPECT_TRUE(cloud.is_point_cloud());
  EXPECT_EQ(cloud.V.row(2), Eigen::RowVector3d(-1e-3, 4, 5.5));
  std::string path = write_bytes(dir + "/bad.xyz", "0 0 0\n1 NaN 0\n");
  expect_refused(path, {path + ":2:", "point 1", "non-finite"});
  write_bytes(path, "\n\n");
  expect_refused(path, {"empty mesh"});
  fs::remove_all(dir);
}

// Each bad-input case of the issue, refused with the file named (and the line for text formats).
TEST(IoValidation, BadOffInputsAreRefusedWithFileAndLine) {
  std::string dir = test::scratch_dir("io");
  const std::string path = dir + "/bad.off";
  const std::string tetra_vertices = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  const std::string tetra_faces = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  ASSERT_NO_THROW(read_mesh(write_bytes(path, "OFF\n4 4 6\n" + tetra_vertices + tetra_faces)));

  expect_refused(dir + "/missing.off", {"no such file"});
  expect_refused(dir, {"directory"});
  write_bytes(dir + "/m.abc", "OFF\n");
  expect_refused(dir + "/m.abc", {"unknown mesh format '.abc'"});
  write_bytes(dir + "/noext", "OFF\n");
  expect_refused(dir + "/noext", {"unknown mesh format"});
  // truncated: a vertex line cut short, and missing faces
  write_bytes(path, "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1");
  expect_refused(path, {path + ":5:", "vertex 2", "2 coordinates"});
  write_bytes(path, "OFF\n4 4 6\n" + tetra_vertices + "3 0 2 1\n");
  expect_refused(path, {"end of file", "face 1 of 4"});
  write_bytes(path, "OFF\n4 4 6\n" + tetra_vertices + "3 0 2\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  expect_refused(path, {path + ":7:", "face 0 has 2 vertex indices, expected 3"});
  // count mismatch: more data than declared; counts larger than the file
  write_bytes(path, "OFF\n4 3 6\n" + tetra_vertices + tetra_faces);
  expect_refused(path, {path + ":10:", "count mismatch"});
  write_bytes(path, "OFF\n2000000000 2000000000 0\n0 0 0\n");
  expect_refused(path, {path + ":2:", "2000000000 vertices", "truncated"});
  write_bytes(path, "OFF\n-4 4 6\n" + tetra_vertices + tetra_faces);
  expect_refused(path, {"negative"});
  // face index out of range
  write_bytes(path, "OFF\n4 4 6\n" + tetra_vertices + "3 0 2 1\n3 0 1 4\n3 0 3 2\n3 1 2 3\n");
  expect_refused(path, {path + ":8:", "face 1", "vertex index 4", "0..3"});
  write_bytes(path, "OFF\n4 4 6\n" + tetra_vertices + "3 0 2 1\n3 0 1 -1\n3 0 3 2\n3 1 2 3\n");
  expect_refused(path, {path + ":8:", "vertex index -1"});
  // NaN / Inf coordinates
  write_bytes(path, "OFF\n4 4 6\n0 0 0\n1 nan 0\n0 1 0\n0 0 1\n" + tetra_faces);
  expect_refused(path, {path + ":4:", "vertex 1", "non-finite"});
  write_bytes(path, "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1e999\n" + tetra_faces);
  expect_refused(path, {path + ":6:", "vertex 3", "non-finite"});
  // empty mesh
  write_bytes(path, "OFF\n0 0 0\n");
  expect_refused(path, {"empty mesh"});
  write_bytes(path, "");
  expect_refused(path, {"end of file", "OFF header"});
  // Reading is lenient: a degenerate face, a zero-length edge, a non-manifold edge or a duplicate face are
  // what a file can legally hold (mesh/mesh_defects.h describes them) ...
  ReadOptions checked;
  checked.validate = true;
  auto expect_invalid = [&](std::initializer_list<std::string> parts) {
    EXPECT_NO_THROW(read_mesh(path));
    try {
      read_mesh(path, checked);
      ADD_FAILURE() << "validation accepted " << path;
    } catch (const Error& e) {
      for (const std::string& part : parts)
        EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  // ... and validate_mesh (ReadOptions::validate, for stages that cannot repair) names them.
  write_bytes(path, "OFF\n4 4 6\n" + tetra_vertices + "3 0 2 2\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  expect_invalid({"face 0", "degenerate"});
  write_bytes(path, "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 0\n" + tetra_faces);
  expect_invalid({"edge (0, 3)", "zero length"});
  write_bytes(path, "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0 -1 0\n3 0 1 2\n3 0 1 3\n3 0 1 4\n");
  expect_invalid({"edge (0, 1)", "non-manifold", "3 faces"});
  write_bytes(path, "OFF\n4 5 6\n" + tetra_vertices + tetra_faces + "3 1 0 2\n");
  expect_invalid({"face 4 duplicates face 0"});
  EXPECT_EQ(read_mesh(path).num_faces(), 5);
  // garbage
  std::string garbage;
  for (int i = 0; i < 300; ++i) garbage += static_cast<char>((i * 7919) % 256);
  write_bytes(path, garbage);
  expect_refused(path, {"expected an OFF header"});
  fs::remove_all(dir);
}

TEST(IoValidation, GarbageInEveryFormatIsRefused) {
  std::string dir = test::scratch_dir("io");
  std::string garbage = "\x01\x02garbage\x7f\n\xff\xfe 1 2 3 \n";
  for (const char* ext : {"off", "ply", "obj", "stl", "xyz", "vert", "tri"}) {
    std::string path = write_bytes(dir + "/g." + ext, garbage);
    if (std::string(ext) == "vert") write_bytes(dir + "/g.tri", garbage);
    if (std::string(ext) == "tri") write_bytes(dir + "/g.vert", garbage);
    SCOPED_TRACE(path);
    // The .vert/.tri pair names whichever file of the two is bad.
    try {
      read_mesh(path);
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      std::string message = e.what();
      EXPECT_NE(message.find(dir + "/g."), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  }
  fs::remove_all(dir);
}

TEST(IoFromMemory, MatchesReadingTheFile) {
  std::string dir = test::scratch_dir("io");
  Mesh mesh = test_mesh();
  write_mesh(dir + "/m.ply", mesh);
  std::string bytes = read_file(dir + "/m.ply");
  expect_same_mesh(mesh, read_mesh_from_memory(bytes, "ply", "memory"));
  try {
    read_mesh_from_memory(bytes.substr(0, 200), "ply", "memory");
    ADD_FAILURE() << "truncated PLY accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("memory", 0), 0u) << e.what();
  }
  Mesh pair = read_vert_tri_from_memory("0 0 0\n1 0 0\n0 1 0\n", "1 2 3\n", "a.vert", "a.tri");
  EXPECT_EQ(pair.F.row(0), Eigen::RowVector3i(0, 1, 2));
  fs::remove_all(dir);
}

TEST(IoTosca, Cat0LoadsWithItsKnownCounts) {
  CSHAPES_REQUIRE_DATA();
  Mesh cat = read_mesh(test::tosca5k("cat0"));
  EXPECT_EQ(cat.num_vertices(), 5000);
  EXPECT_EQ(cat.num_faces(), 9996);
}

}  // namespace io_test
}  // namespace cshapes
