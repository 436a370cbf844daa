// The transformations of `cshapes experiment invariance` (experiments/invariance_experiment.h) and how a
// form's change under them is measured.
//
// Exact transformations: the same surface, so the same canonical form up to a rigid motion (and a
// reflection: MDS and spectral forms are defined only up to one), with a known vertex correspondence.
//   renumber    the vertices renumbered by a seeded random permutation, the faces remapped to them
//   face-order  the faces listed in a seeded random order, each face's corners turned cyclically by a seeded
//               random step (its orientation kept)
//   rigid       a seeded random rotation and a translation of about the bounding-box diagonal
//   scale-1e-6  every coordinate times 1e-6 (the form is divided by the scale before it is compared)
//   scale-1e3   every coordinate times 1e3 (likewise)
//   jitter      every coordinate moved by a seeded uniform amount in ±1e-9 × the bounding-box diagonal
// Each returns the moved mesh with, per vertex, the reference vertex it is (reference_vertex) and the factor
// its form is divided by (scale). Deterministic for a seed on every platform (std::mt19937_64, mapped to
// numbers by hand rather than by the standard library's distributions, whose algorithms are unspecified), so
// that a rerun meets the same meshes and so the forms cached for them.
//
// Measures, both as fractions of the reference form's bounding-box diagonal (finite rows):
//   exact_form_change    the RMS over corresponding vertices (rows finite in both) after the best rigid fit
//                        of the transformed form onto the reference (Kabsch, reflections allowed:
//                        mesh/rigid_transform.h), and the symmetric Hausdorff distance between the two point
//                        sets after that same fit (nearest neighbours, matching/shape_distance.h)
//   aligned_form_change  no correspondence (a remesh): the RMSE and Hausdorff distance after ICP
//                        (matching/shape_distance.h aligned_shape_distance), as `cshapes align` reports them
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cshapes/matching/icp.h"
#include "cshapes/mesh/mesh.h"

namespace cshapes {

enum class ExactTransform { Renumber, FaceOrder, Rigid, ScaleDown, ScaleUp, Jitter };

// In the order of the CSV files and the figure.
const std::vector<ExactTransform>& exact_transforms();
// "renumber", "face-order", "rigid", "scale-1e-6", "scale-1e3", "jitter".
std::string to_string(ExactTransform transform);
// Whether the transformation draws random numbers (its rows carry a seed).
bool is_seeded(ExactTransform transform);

inline constexpr double kInvarianceSmallScale = 1e-6;
inline constexpr double kInvarianceLargeScale = 1e3;
inline constexpr double kInvarianceJitter = 1e-9;  // × the bounding-box diagonal

struct TransformedMesh {
  Mesh mesh;
  // Row k of mesh (and of its form) is vertex reference_vertex[k] of the reference mesh; empty: vertex k.
  std::vector<int> reference_vertex;
  double scale = 1;  // the form is divided by this before it is compared with the reference form
};

// The reference mesh under `transform` (see above); seed: the random draws (ignored by the scales).
TransformedMesh transform_mesh(const Mesh& reference, ExactTransform transform, std::uint64_t seed);

// A seeded random permutation of 0..n−1 (Fisher–Yates on std::mt19937_64).
std::vector<int> random_permutation(Index n, std::uint64_t seed);

struct FormChange {
  double rmse = 0;       // fraction of the reference form's bounding-box diagonal
  double hausdorff = 0;  // likewise
  Index rows = 0;        // exact: vertices compared; aligned: points of the smaller set
};

// reference: the reference mesh's form (n×3); transformed: the form of transform_mesh's mesh (n×3, its vertex
// order). Throws cshapes::Error when the row counts differ or fewer than 4 rows are finite in both.
FormChange exact_form_change(const Points& reference, const Points& transformed, const TransformedMesh& how);

// The form of another mesh of the same surface (no correspondence) against the reference form: ICP with
// `icp` (reflections allowed by default), over the finite rows of each.
FormChange aligned_form_change(const Points& reference, const Points& other, const IcpOptions& icp = {});

}  // namespace cshapes
