// Imperfect meshes made in the tests, one defect each, with the defect's elements known by construction.
// Shared by mesh_defects_test, mesh_repair_test, canonical_forms_test and imperfect_meshes_cli_test.
#pragma once

#include "cshapes/mesh/mesh.h"
#include "cshapes/data/synthetic.h"

namespace cshapes::test {

// Vertices a and b of mesh, and a neighbour of a: the vertex of largest x, and its first neighbour in a face.
struct EdgeAt {
  int a = 0, b = 0;
};
inline EdgeAt rightmost_edge(const Mesh& m) {
  EdgeAt e;
  m.V.col(0).maxCoeff(&e.a);
  for (Index f = 0; f < m.num_faces(); ++f)
    for (int c = 0; c < 3; ++c)
      if (m.F(f, c) == e.a) {
        e.b = m.F(f, (c + 1) % 3);
        return e;
      }
  return e;
}

// Two icospheres: the second the first mirrored through the plane x = max x, so the rightmost vertex
// touches. shared = 1: they share that vertex (a non-manifold vertex); shared = 2: also the edge to its
// first neighbour (a non-manifold edge of 4 faces). The second sphere's copies of the shared vertices are
// not created: its faces use the first sphere's.
inline Mesh two_spheres_sharing(int shared, int subdivisions = 2) {
  const Mesh a = icosphere(subdivisions);
  const EdgeAt e = rightmost_edge(a);
  const Index n = a.num_vertices();
  const double x0 = a.V(e.a, 0);
  std::vector<int> index_in_b(n, -1);
  Mesh m;
  std::vector<Eigen::RowVector3d> extra;
  for (Index v = 0; v < n; ++v) {
    if (v == e.a || (shared == 2 && v == e.b)) {
      index_in_b[v] = static_cast<int>(v);
    } else {
      index_in_b[v] = static_cast<int>(n + extra.size());
      Eigen::RowVector3d p = a.V.row(v);
      p[0] = 2 * x0 - p[0];
      extra.push_back(p);
    }
  }
  m.V.resize(n + extra.size(), 3);
  m.V.topRows(n) = a.V;
  for (size_t k = 0; k < extra.size(); ++k) m.V.row(n + k) = extra[k];
  m.F.resize(2 * a.num_faces(), 3);
  m.F.topRows(a.num_faces()) = a.F;
  for (Index f = 0; f < a.num_faces(); ++f)  // mirrored: reversed orientation keeps normals outward
    m.F.row(a.num_faces() + f) << index_in_b[a.F(f, 0)], index_in_b[a.F(f, 2)], index_in_b[a.F(f, 1)];
  return m;
}

// An icosphere with one vertex in no face, appended last.
inline Mesh sphere_with_isolated_vertex() {
  Mesh m = icosphere(2);
  m.V.conservativeResize(m.num_vertices() + 1, 3);
  m.V.row(m.num_vertices() - 1) << 3, 0, 0;
  return m;
}

// A large icosphere (162 vertices) and a small one (42) beside it.
inline Mesh two_components() {
  const Mesh a = icosphere(2), b = icosphere(1, 0.3);
  Mesh m;
  m.V.resize(a.num_vertices() + b.num_vertices(), 3);
  m.V << a.V, (b.V.rowwise() + Eigen::RowVector3d(3, 0, 0));
  m.F.resize(a.num_faces() + b.num_faces(), 3);
  m.F << a.F, (b.F.array() + static_cast<int>(a.num_vertices())).matrix();
  return m;
}

// An icosphere whose face 0 appears again at the end, with the opposite orientation.
inline Mesh sphere_with_duplicate_face() {
  Mesh m = icosphere(2);
  const Eigen::RowVector3i f0 = m.F.row(0);
  m.F.conservativeResize(m.num_faces() + 1, 3);
  m.F.row(m.num_faces() - 1) << f0[0], f0[2], f0[1];
  return m;
}

}  // namespace cshapes::test
