// Synthetic articulated shapes: the project's own retrieval dataset, for machines without TOSCA.
//
// A class is a skeleton (joints in a tree; a bone joins a joint to its parent) with a radius at every joint.
// Its rest mesh is the zero level set of a smooth union of the bones' tapered capsules,
//   f(x) = -k log Σ_b exp(-d_b(x) / k),   d_b(x) = |x - closest point of bone b| - r_b(x)
// (soft minimum, blending radius k), extracted by marching tetrahedra and remeshed isotropically (CGAL) to
// about the wanted vertex count. Poses are made by dual-quaternion skinning of that one rest mesh: every
// joint gets random angles about its own axes within its limits, and a vertex follows the bones near it with
// weights w_b ∝ exp(-(d_b - min_b d_b) / k). So all poses of a class share vertex order and faces (vertex i
// of pose p corresponds to vertex i of pose q: ground truth), are near-isometric (bones are rigid; only the
// joints stretch a little), and are checked free of self-intersection (CGAL; a pose that intersects is
// redrawn). Everything is deterministic for a seed (std::mt19937_64 and distributions written here). Classes:
// biped, quadruped, hand, spider (eight legs), and more may be added; units are about a centimetre.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cshapes/mesh/mesh.h"
#include "cshapes/support/option_limits.h"
#include "cshapes/support/progress.h"

namespace cshapes {

struct Joint {
  std::string name;
  int parent = -1;           // index of the parent joint; -1 for the root
  Eigen::Vector3d position;  // rest position
  double radius = 1;         // capsule radius at this joint (bones taper linearly between their joints)
  // Rotations applied at this joint to everything below it: angle ∈ [lo, hi] (radians) about each axis, in
  // order.
  std::vector<Eigen::Vector3d> axes;
  std::vector<Eigen::Vector2d> limits;
};

struct Skeleton {
  std::string class_name;
  std::vector<Joint> joints;  // parents before children
  double blend = 1.5;         // soft-minimum blending radius k, in shape units
};

// The classes known: "biped", "quadruped", "hand", "spider".
std::vector<std::string> articulated_classes();
// The skeleton of a class; throws listing the known classes for an unknown name.
Skeleton articulated_skeleton(const std::string& class_name);

// The smooth-union field of the skeleton in rest pose (negative inside), and each bone's capsule distance
// d_b.
double skeleton_field(const Skeleton& skeleton, const Eigen::Vector3d& x);

struct RestMeshOptions {
  Index target_vertices =
      3500;  // about this many vertices (1% tolerance; 0: keep the marching-tetrahedra mesh)
  double cell_fraction = 0.5;  // marching-tetrahedra cell = this × the smallest joint radius
};

// Rest mesh of a skeleton: marching tetrahedra over the smooth union, then isotropic remeshing.
// progress: the remesh's, per attempt (mesh/remesh.h), and a poll after the surface is extracted: where a
// stop (Ctrl-C in Python) is heard.
Mesh articulated_rest_mesh(const Skeleton& skeleton, const RestMeshOptions& options = {},
                           const ProgressFn& progress = {});

// Skinning weights: |V| × |joints| (column j: the bone ending at joint j; the root's column weighs the root's
// own frame), rows summing to 1.
Eigen::MatrixXd skinning_weights(const Skeleton& skeleton, const Points& rest);

// Joint angles of one pose: angles[j][a] about joint j's axis a.
using PoseAngles = std::vector<std::vector<double>>;
// Uniform random angles within each joint's limits, scaled by `amplitude` toward the middle of the range
// (0: every angle at the middle of its range, 1: the full range).
PoseAngles random_pose(const Skeleton& skeleton, std::uint64_t seed, double amplitude = 1.0);
// All angles zero: the rest pose (the skeleton as given).
PoseAngles neutral_pose(const Skeleton& skeleton);

// Poses the rest mesh by dual-quaternion skinning (faces unchanged).
Points pose_mesh(const Skeleton& skeleton, const Points& rest, const Eigen::MatrixXd& weights,
                 const PoseAngles& angles);

// Edge-length change of a pose against the rest mesh: mean and max of |l'/l - 1| over edges.
struct IsometryError {
  double mean = 0;
  double max = 0;
};
IsometryError edge_length_change(const Mesh& rest, const Points& posed);

// The limits of the options a user sets (`cshapes generate`, generate(); support/option_limits.h).
namespace generate_limits {
inline constexpr Limit kVertices = integer_limit("vertices", 4, 1e7);
inline constexpr Limit kPoses = integer_limit("poses", 1, 1e5);
inline constexpr Limit kAmplitude = number_limit("amplitude", 0, 1);
inline constexpr Limit kClasses = integer_limit("classes", 1, 4);
inline constexpr Limit kNoisy = integer_limit("noisy", 0, 1e5);
inline constexpr Limit kGlue = integer_limit("glue", 0, 1000);
}  // namespace generate_limits

struct ArticulatedOptions {
  int poses = 5;           // poses to make
  std::uint64_t seed = 0;  // same seed, same poses
  double amplitude = 1.0;  // scales the joint ranges about their middles (see random_pose)
  int max_redraws = 30;    // self-intersecting poses redrawn at most this many times each
  RestMeshOptions rest;    // how the rest mesh is made
  // Stage "articulated": (poses done, poses), after every pose drawn and every redraw; also where a stop
  // (Ctrl-C in Python) is heard.
  ProgressFn progress;
};

struct ArticulatedClass {
  Skeleton skeleton;
  Mesh rest;                            // the rest mesh (neutral angles = the skeleton as given)
  std::vector<Mesh> poses;              // same faces as rest
  std::vector<PoseAngles> angles;       // the angles of each pose
  std::vector<IsometryError> isometry;  // per pose, against the rest mesh
  int redraws = 0;                      // poses rejected for self-intersection
};

// Rest mesh and poses of one class.
ArticulatedClass generate_articulated(const std::string& class_name, const ArticulatedOptions& options = {});

// The hand of Fig. 2: one pose with the fingers close together but separated, and the same pose with adjacent
// fingers glued (topological_noise), sharing vertices. glued_pairs: the glued vertex pairs.
struct GluedHand {
  Mesh separated;
  Mesh glued;
  std::vector<std::pair<int, int>> glued_pairs;
};
GluedHand generate_glued_hand(std::uint64_t seed = 0, int glues = 3);

// A whole dataset: `classes` classes (in the order of articulated_classes()), each with `poses` clean poses
// named CLASS0..CLASS{poses-1} and `noisy` more poses CLASS{poses}.. carrying topological noise (glue_count
// glues; the pose is redrawn, up to 60 times, when it offers too few almost-touching spots; after 10 and 20
// draws the gap is widened 1.5×, 2×, after 30 gluing may also relax its thresholds, topological_noise.h).
struct ArticulatedDatasetOptions {
  int classes = 4;         // first this many of articulated_classes()
  int poses = 5;           // clean poses per class
  int noisy = 1;           // noisy poses per class (after the clean ones)
  int glue_count = 2;      // glues per noisy pose
  std::uint64_t seed = 0;  // everything follows from it
  RestMeshOptions rest;    // rest mesh size
  // Stage "dataset": (shapes done, shapes), after every shape, every pose drawn and every gluing attempt (the
  // gluing's geodesics report per source); also where a stop (Ctrl-C in Python) is heard.
  ProgressFn progress;
};
struct ArticulatedShape {
  std::string name;        // "biped3"
  std::string class_name;  // "biped"
  int pose = 0;
  bool noisy = false;
  Mesh mesh;
  std::vector<std::pair<int, int>> glued_pairs;  // noisy shapes: the glued vertex pairs
  IsometryError isometry;                        // against the class's rest mesh (before gluing)
};
std::vector<ArticulatedShape> make_articulated_dataset(const ArticulatedDatasetOptions& options);

}  // namespace cshapes
