#include "cshapes/data/articulated.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cshapes/support/deterministic_random.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/marching_tetrahedra.h"
#include "cshapes/mesh/remesh.h"
#include "cshapes/data/topological_noise.h"

namespace cshapes {

namespace {

// Builds a skeleton joint by joint; mirror() adds the left/right copy of a limb (x -> -x, axes mirrored so
// that the same angle moves both sides symmetrically).
struct SkeletonBuilder {
  Skeleton s;
  int add(const std::string& name, int parent, Eigen::Vector3d position, double radius,
          std::vector<std::pair<Eigen::Vector3d, Eigen::Vector2d>> rotations = {}) {
    Joint j;
    j.name = name;
    j.parent = parent;
    j.position = position;
    j.radius = radius;
    for (auto& [axis, limit] : rotations) {
      j.axes.push_back(axis.normalized());
      j.limits.push_back(limit);
    }
    s.joints.push_back(j);
    return static_cast<int>(s.joints.size()) - 1;
  }
};

const Eigen::Vector3d kX(1, 0, 0), kY(0, 1, 0), kZ(0, 0, 1);
Eigen::Vector2d range(double lo, double hi) {
  return {lo, hi};
}

// Mirror of an axis through the plane x = 0, as a rotation axis (a pseudovector): (x, y, z) -> (x, -y, -z).
Eigen::Vector3d mirror_axis(const Eigen::Vector3d& a) {
  return {a.x(), -a.y(), -a.z()};
}

// A limb: a chain of joints, added for side +1 (x > 0) or -1 (mirrored).
struct LimbJoint {
  std::string name;
  Eigen::Vector3d position;  // for the +x side
  double radius;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector2d>> rotations;  // for the +x side
};
void add_limb(SkeletonBuilder& b, int parent, const std::vector<LimbJoint>& chain, bool both_sides) {
  for (int side : {1, -1}) {
    if (side < 0 && !both_sides) break;
    int p = parent;
    for (const LimbJoint& j : chain) {
      Eigen::Vector3d pos = j.position;
      auto rotations = j.rotations;
      if (side < 0) {
        pos.x() = -pos.x();
        for (auto& r : rotations) r.first = mirror_axis(r.first);
      }
      p = b.add(j.name + (both_sides ? (side > 0 ? "_l" : "_r") : ""), p, pos, j.radius, rotations);
    }
  }
}

Skeleton biped() {
  SkeletonBuilder b;
  b.s.class_name = "biped";
  b.s.blend = 1.5;
  int pelvis = b.add("pelvis", -1, {0, 0, 95}, 11);
  int spine = b.add("spine", pelvis, {0, 0, 115}, 10.5, {{kX, range(-0.15, 0.3)}, {kZ, range(-0.3, 0.3)}});
  int chest = b.add("chest", spine, {0, 0, 135}, 12, {{kX, range(-0.1, 0.2)}, {kY, range(-0.12, 0.12)}});
  int neck = b.add("neck", chest, {0, 0, 152}, 5.5, {{kX, range(-0.3, 0.4)}, {kZ, range(-0.6, 0.6)}});
  int head = b.add("head", neck, {0, 2, 165}, 9);
  b.add("crown", head, {0, 1, 175}, 8);
  add_limb(b, chest,
           {{"shoulder", {17, 0, 146}, 5.5, {{kY, range(-0.5, 0.2)}, {kX, range(-0.6, 0.9)}}},
            {"elbow", {24, 0, 121}, 4.5, {{kX, range(0, 1.2)}}},
            {"wrist", {28, 0, 97}, 3.5, {{kX, range(-0.4, 0.4)}}},
            {"hand", {30, 0, 87}, 4, {}}},
           true);
  add_limb(b, pelvis,
           {{"hip", {9, 0, 92}, 8.5, {{kX, range(-0.6, 0.5)}, {kY, range(-0.25, 0.08)}}},
            {"knee", {10, 1, 50}, 6, {{kX, range(-1.1, 0)}}},
            {"ankle", {10, -1, 9}, 4.5, {{kX, range(-0.3, 0.3)}}},
            {"toe", {10, 13, 4}, 3.5, {}}},
           true);
  return b.s;
}

Skeleton quadruped() {
  SkeletonBuilder b;
  b.s.class_name = "quadruped";
  b.s.blend = 1.2;
  int pelvis = b.add("pelvis", -1, {0, -30, 48}, 10);
  int back = b.add("back", pelvis, {0, -5, 50}, 10.5, {{kX, range(-0.12, 0.12)}, {kZ, range(-0.25, 0.25)}});
  int chest = b.add("chest", back, {0, 22, 50}, 11.5, {{kX, range(-0.1, 0.1)}, {kZ, range(-0.2, 0.2)}});
  int neck = b.add("neck", chest, {0, 36, 60}, 6, {{kX, range(-0.5, 0.4)}, {kZ, range(-0.6, 0.6)}});
  int head = b.add("head", neck, {0, 46, 68}, 7.5, {{kX, range(-0.3, 0.3)}});
  b.add("snout", head, {0, 58, 65}, 3.5);
  add_limb(b, pelvis,
           {{"tail1", {0, -42, 52}, 3, {{kX, range(-0.6, 0.6)}, {kZ, range(-0.8, 0.8)}}},
            {"tail2", {0, -54, 54}, 2.5, {{kX, range(-0.5, 0.5)}, {kZ, range(-0.6, 0.6)}}},
            {"tail3", {0, -65, 55}, 2, {}}},
           false);
  add_limb(b, pelvis,
           {{"hindhip", {7, -32, 42}, 6, {{kX, range(-0.6, 0.6)}, {kY, range(-0.2, 0.08)}}},
            {"hindknee", {8, -26, 24}, 4, {{kX, range(-1.0, 0.2)}}},
            {"hindpaw", {8, -32, 4}, 3, {{kX, range(-0.4, 0.4)}}},
            {"hindtoe", {8, -26, 2.5}, 2.5, {}}},
           true);
  add_limb(b, chest,
           {{"fronthip", {7, 24, 42}, 6, {{kX, range(-0.6, 0.6)}, {kY, range(-0.2, 0.08)}}},
            {"frontknee", {8, 26, 24}, 4, {{kX, range(-0.2, 1.0)}}},
            {"frontpaw", {8, 24, 4}, 3, {{kX, range(-0.4, 0.4)}}},
            {"fronttoe", {8, 30, 2.5}, 2.5, {}}},
           true);
  return b.s;
}

Skeleton hand() {
  SkeletonBuilder b;
  b.s.class_name = "hand";
  b.s.blend = 1.0;
  int wrist = b.add("wrist", -1, {0, 0, 0}, 7);
  b.add("forearm", wrist, {0, -18, 0}, 7.5);
  const double xs[4] = {-15, -5, 5, 15};
  const char* names[4] = {"index", "middle", "ring", "pinky"};
  const double lengths[4] = {1.0, 1.08, 1.02, 0.85};
  for (int f = 0; f < 4; ++f) {
    const double x = xs[f], l = lengths[f];
    int knuckle = b.add(std::string(names[f]) + "_knuckle", wrist, {x, 38, 0}, 5);
    int p1 = b.add(std::string(names[f]) + "_1", knuckle, {1.25 * x, 38 + 17 * l, 0}, 4.2,
                   {{kX, range(-0.9, 0.2)}, {kZ, range(-0.15, 0.15)}});
    int p2 = b.add(std::string(names[f]) + "_2", p1, {1.4 * x, 38 + 29 * l, 0}, 3.8, {{kX, range(-1.0, 0)}});
    b.add(std::string(names[f]) + "_tip", p2, {1.5 * x, 38 + 37 * l, 0}, 3.4, {{kX, range(-0.7, 0)}});
  }
  int cmc = b.add("thumb_0", wrist, {-13, 8, -2}, 6, {{kZ, range(-0.3, 0.3)}, {kY, range(-0.3, 0.3)}});
  int mcp = b.add("thumb_1", cmc, {-26, 20, -4}, 5, {{kX, range(-0.5, 0.2)}});
  int ip = b.add("thumb_2", mcp, {-34, 30, -5}, 4.2, {{kX, range(-0.6, 0)}});
  b.add("thumb_tip", ip, {-39, 38, -5}, 3.8);
  return b.s;
}

Skeleton spider() {
  SkeletonBuilder b;
  b.s.class_name = "spider";
  b.s.blend = 0.8;
  int thorax = b.add("thorax", -1, {0, 8, 14}, 9);
  int abdomen = b.add("abdomen", thorax, {0, -16, 16}, 13, {{kX, range(-0.2, 0.2)}, {kZ, range(-0.2, 0.2)}});
  b.add("abdomen_end", abdomen, {0, -30, 17}, 9);
  b.add("head", thorax, {0, 21, 13}, 6);
  const double angles[4] = {1.05, 0.35, -0.35, -1.05};  // leg directions from +x, radians
  for (int i = 0; i < 4; ++i) {
    Eigen::Vector3d d(std::cos(angles[i]), std::sin(angles[i]), 0);
    Eigen::Vector3d lift = kZ.cross(d);  // horizontal, perpendicular to the leg: raising and lowering
    Eigen::Vector3d hip = Eigen::Vector3d(0, 8, 14) + 7 * d;
    Eigen::Vector3d knee = hip + 16 * d + Eigen::Vector3d(0, 0, 12);
    Eigen::Vector3d foot = knee + 22 * d + Eigen::Vector3d(0, 0, -24);
    Eigen::Vector3d tip = foot + 4 * d + Eigen::Vector3d(0, 0, -3);
    add_limb(b, thorax,
             {{"hip" + std::to_string(i), hip, 3.2, {{kZ, range(-0.16, 0.16)}, {lift, range(-0.25, 0.25)}}},
              {"knee" + std::to_string(i), knee, 2.6, {{lift, range(-0.3, 0.3)}}},
              {"foot" + std::to_string(i), foot, 2.0, {}},
              {"tip" + std::to_string(i), tip, 1.8, {}}},
             true);
  }
  return b.s;
}

// Distance from x to the tapered capsule of the bone (parent(j) -> j), minus its radius there.
double bone_distance(const Skeleton& s, int j, const Eigen::Vector3d& x) {
  const Joint& child = s.joints[j];
  const Joint& parent = s.joints[child.parent];
  const Eigen::Vector3d ab = child.position - parent.position;
  double t = std::clamp((x - parent.position).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  double r = (1 - t) * parent.radius + t * child.radius;
  return (x - (parent.position + t * ab)).norm() - r;
}

// Rigid transforms of the joints' frames for a pose (forward kinematics): G_j = G_parent · (rotation R_j
// about x_j).
std::vector<Eigen::Isometry3d> joint_transforms(const Skeleton& s, const PoseAngles& angles) {
  std::vector<Eigen::Isometry3d> G(s.joints.size(), Eigen::Isometry3d::Identity());
  for (size_t j = 0; j < s.joints.size(); ++j) {
    const Joint& joint = s.joints[j];
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    for (size_t a = 0; a < joint.axes.size(); ++a)
      R = R * Eigen::AngleAxisd(angles[j][a], joint.axes[a]).toRotationMatrix();
    Eigen::Isometry3d local = Eigen::Isometry3d::Identity();
    local.linear() = R;
    local.translation() = joint.position - R * joint.position;
    G[j] = joint.parent < 0 ? local : G[joint.parent] * local;
  }
  return G;
}

}  // namespace

std::vector<std::string> articulated_classes() {
  return {"biped", "quadruped", "hand", "spider"};
}

Skeleton articulated_skeleton(const std::string& name) {
  if (name == "biped") return biped();
  if (name == "quadruped") return quadruped();
  if (name == "hand") return hand();
  if (name == "spider") return spider();
  fail("unknown articulated class '", name, "'; known: biped, quadruped, hand, spider");
}

double skeleton_field(const Skeleton& s, const Eigen::Vector3d& x) {
  // Soft minimum, shifted by the hard minimum so that the exponentials never underflow.
  double hard = std::numeric_limits<double>::infinity();
  double d[128];
  const int n = static_cast<int>(s.joints.size());
  for (int j = 1; j < n; ++j) hard = std::min(hard, d[j] = bone_distance(s, j, x));
  double sum = 0;
  for (int j = 1; j < n; ++j) {
    const double excess = (d[j] - hard) / s.blend;
    if (excess < 36) sum += std::exp(-excess);  // e^-36 < 1e-15: below rounding of the leading term
  }
  return hard - s.blend * std::log(sum);
}

Mesh articulated_rest_mesh(const Skeleton& s, const RestMeshOptions& o, const ProgressFn& progress) {
  CSHAPES_REQUIRE(s.joints.size() >= 2 && s.joints.size() <= 128,
                  "articulated: a skeleton needs 2..128 joints");
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  double min_radius = std::numeric_limits<double>::infinity(), max_radius = 0;
  for (const Joint& j : s.joints) {
    lo = lo.cwiseMin(j.position);
    hi = hi.cwiseMax(j.position);
    min_radius = std::min(min_radius, j.radius);
    max_radius = std::max(max_radius, j.radius);
  }
  const double margin = max_radius + 2 * s.blend + 2;
  MarchingTetrahedraOptions mt;
  mt.cell_size = o.cell_fraction * min_radius;
  Mesh raw = marching_tetrahedra([&](const Eigen::Vector3d& x) { return skeleton_field(s, x); },
                                 lo.array() - margin, hi.array() + margin, mt);
  // Marching tetrahedra may leave tiny bubbles where the field grazes zero; keep the main surface.
  Components comps = connected_components(raw.num_vertices(), mesh_edges(raw.F));
  if (comps.count > 1) raw = extract_component(raw, comps, comps.largest()).mesh;
  if (progress) progress("", 0, 0);  // a poll (support/progress.h) between the two long steps
  if (o.target_vertices <= 0) return raw;
  RemeshOptions ro;
  ro.progress = progress;
  ro.target_vertices = o.target_vertices;
  ro.feature_angle_deg = 0;  // a smooth surface: the slivers' creases are not features
  return remesh(raw, ro).mesh;
}

Eigen::MatrixXd skinning_weights(const Skeleton& s, const Points& rest) {
  const Index n = rest.rows();
  const int m = static_cast<int>(s.joints.size());
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(n, m);
#pragma omp parallel for schedule(static)
  for (Index i = 0; i < n; ++i) {
    Eigen::Vector3d x = rest.row(i);
    double hard = std::numeric_limits<double>::infinity();
    for (int j = 1; j < m; ++j) hard = std::min(hard, W(i, j) = bone_distance(s, j, x));
    double sum = 0;
    for (int j = 1; j < m; ++j) {
      double excess = (W(i, j) - hard) / s.blend;
      W(i, j) = excess > 8 ? 0 : std::exp(-excess);
      sum += W(i, j);
    }
    W.row(i) /= sum;
  }
  return W;
}

PoseAngles neutral_pose(const Skeleton& s) {
  PoseAngles angles(s.joints.size());
  for (size_t j = 0; j < s.joints.size(); ++j) angles[j].assign(s.joints[j].limits.size(), 0.0);
  return angles;
}

PoseAngles random_pose(const Skeleton& s, std::uint64_t seed, double amplitude) {
  DeterministicRandom rng(seed);
  PoseAngles angles(s.joints.size());
  for (size_t j = 0; j < s.joints.size(); ++j)
    for (const auto& l : s.joints[j].limits) {
      double mid = 0.5 * (l[0] + l[1]), half = 0.5 * (l[1] - l[0]) * amplitude;
      angles[j].push_back(rng.uniform(mid - half, mid + half));
    }
  return angles;
}

Points pose_mesh(const Skeleton& s, const Points& rest, const Eigen::MatrixXd& W, const PoseAngles& angles) {
  CSHAPES_REQUIRE(W.rows() == rest.rows() && W.cols() == static_cast<Index>(s.joints.size()),
                  "pose_mesh: weights are ", W.rows(), "x", W.cols(), ", expected ", rest.rows(), "x",
                  s.joints.size());
  const std::vector<Eigen::Isometry3d> G = joint_transforms(s, angles);
  // Dual quaternion of each bone (parent(j) -> j moves with its parent's frame): real part q, dual part ½ t
  // q.
  const int m = static_cast<int>(s.joints.size());
  std::vector<Eigen::Quaterniond> real(m), dual(m);
  for (int j = 1; j < m; ++j) {
    const Eigen::Isometry3d& T = G[s.joints[j].parent];
    real[j] = Eigen::Quaterniond(T.linear());
    Eigen::Quaterniond t(0, T.translation().x(), T.translation().y(), T.translation().z());
    dual[j] = t * real[j];
    dual[j].coeffs() *= 0.5;
  }
  Points out(rest.rows(), 3);
#pragma omp parallel for schedule(static)
  for (Index i = 0; i < rest.rows(); ++i) {
    // Blend in the hemisphere of the most weighted bone (q and -q are the same rotation).
    Index main;
    W.row(i).maxCoeff(&main);
    Eigen::Vector4d br = Eigen::Vector4d::Zero(), bd = Eigen::Vector4d::Zero();
    for (int j = 1; j < m; ++j) {
      double w = W(i, j);
      if (w == 0) continue;
      if (real[j].coeffs().dot(real[main].coeffs()) < 0) w = -w;
      br += w * real[j].coeffs();
      bd += w * dual[j].coeffs();
    }
    const double norm = br.norm();
    Eigen::Quaterniond qr(br / norm), qd(bd / norm);
    // Translation = 2 · vec(q_d q_r*) (Kavan et al. 2008, dual-quaternion skinning).
    Eigen::Vector3d t = 2 * (qd * qr.conjugate()).vec();
    out.row(i) = (qr * Eigen::Vector3d(rest.row(i)) + t).transpose();
  }
  return out;
}

IsometryError edge_length_change(const Mesh& rest, const Points& posed) {
  Edges E = mesh_edges(rest.F);
  Eigen::VectorXd before = edge_lengths(rest.V, E), after = edge_lengths(posed, E);
  IsometryError e;
  Eigen::ArrayXd change = (after.array() / before.array() - 1).abs();
  e.mean = change.mean();
  e.max = change.maxCoeff();
  return e;
}

ArticulatedClass generate_articulated(const std::string& class_name, const ArticulatedOptions& o) {
  check_limit(generate_limits::kPoses, o.poses, "articulated");
  check_limit(generate_limits::kAmplitude, o.amplitude, "articulated");
  check_limit(generate_limits::kVertices, static_cast<double>(o.rest.target_vertices), "articulated");
  ArticulatedClass c;
  c.skeleton = articulated_skeleton(class_name);
  c.rest = articulated_rest_mesh(c.skeleton, o.rest, polls_of(o.progress));
  const Eigen::MatrixXd W = skinning_weights(c.skeleton, c.rest.V);
  for (int p = 0; p < o.poses; ++p) {
    for (int attempt = 0;; ++attempt) {
      CSHAPES_REQUIRE(attempt <= o.max_redraws, "articulated: ", class_name, " pose ", p,
                      " still self-intersects after ", o.max_redraws, " redraws; lower the amplitude");
      // One random stream per (pose, attempt): pose p does not depend on how many redraws earlier poses
      // needed.
      PoseAngles angles = random_pose(c.skeleton, derive_seed(o.seed, 1000003ULL * p + attempt), o.amplitude);
      Mesh posed{pose_mesh(c.skeleton, c.rest.V, W, angles), c.rest.F};
      const bool intersects = self_intersects(posed);
      if (o.progress) o.progress("articulated", p + (intersects ? 0 : 1), o.poses);
      if (intersects) {
        ++c.redraws;
        continue;
      }
      c.isometry.push_back(edge_length_change(c.rest, posed.V));
      c.poses.push_back(std::move(posed));
      c.angles.push_back(std::move(angles));
      break;
    }
  }
  return c;
}

GluedHand generate_glued_hand(std::uint64_t seed, int glues) {
  const Skeleton s = hand();
  const Mesh rest = articulated_rest_mesh(s);
  const Eigen::MatrixXd W = skinning_weights(s, rest.V);
  // Fingers drawn together (adduction about z towards the middle finger's line) and slightly curled, so that
  // neighbouring fingers almost touch along their length but do not intersect.
  PoseAngles angles = neutral_pose(s);
  for (size_t j = 0; j < s.joints.size(); ++j) {
    const Joint& joint = s.joints[j];
    if (joint.axes.size() == 2 && joint.axes[1].isApprox(kZ) && joint.name.find("_1") != std::string::npos) {
      // Finger base: the spread of the rest pose is 0.25·x/38 rad; close most of it.
      double x = s.joints[joint.parent].position.x();
      angles[j][1] = 0.8 * std::atan2(0.25 * x, 17.0);
      angles[j][0] = -0.15;
    }
  }
  GluedHand h;
  h.separated = Mesh{pose_mesh(s, rest.V, W, angles), rest.F};
  CSHAPES_REQUIRE(!self_intersects(h.separated), "hand: the fingers-together pose self-intersects");
  TopologicalNoiseOptions no;
  no.glue_count = glues;
  no.seed = seed;
  no.min_separation_fraction = 0.05;
  TopologicalNoiseResult r = glue_topological_noise(h.separated, no);
  h.glued = r.mesh;
  for (const GluedPair& p : r.pairs) h.glued_pairs.emplace_back(p.a, p.b);
  return h;
}

std::vector<ArticulatedShape> make_articulated_dataset(const ArticulatedDatasetOptions& o) {
  const std::vector<std::string> names = articulated_classes();
  static_assert(generate_limits::kClasses.maximum == 4, "the limit of classes is the number of classes");
  CSHAPES_REQUIRE(names.size() == 4, "dataset: ", names.size(), " articulated classes, the limit says 4");
  check_limit(generate_limits::kClasses, o.classes, "dataset");
  check_limit(generate_limits::kPoses, o.poses, "dataset");
  check_limit(generate_limits::kNoisy, o.noisy, "dataset");
  check_limit(generate_limits::kGlue, o.glue_count, "dataset");
  CSHAPES_REQUIRE(o.poses >= 0 && o.noisy >= 0 && o.poses + o.noisy >= 1, "dataset: needs at least one pose");
  std::vector<ArticulatedShape> shapes;
  const double total = static_cast<double>(o.classes) * (o.poses + o.noisy);
  // The stop without the classes' own reports, which would restart the count.
  const ProgressFn poll = polls_of(o.progress);
  auto report = [&] {
    if (o.progress) o.progress("dataset", static_cast<double>(shapes.size()), total);
  };
  for (int c = 0; c < o.classes; ++c) {
    ArticulatedOptions ao;
    ao.poses = o.poses;
    ao.seed = derive_seed(o.seed, static_cast<std::uint64_t>(c));
    ao.rest = o.rest;
    ao.progress = poll;
    ArticulatedClass cls = generate_articulated(names[c], ao);
    for (int p = 0; p < o.poses; ++p) {
      ArticulatedShape s;
      s.class_name = names[c];
      s.pose = p;
      s.name = names[c] + std::to_string(p);
      s.mesh = cls.poses[p];
      s.isometry = cls.isometry[p];
      shapes.push_back(std::move(s));
      report();
    }
    if (o.noisy == 0) continue;
    const Eigen::MatrixXd W = skinning_weights(cls.skeleton, cls.rest.V);
    for (int k = 0; k < o.noisy; ++k) {
      ArticulatedShape s;
      s.class_name = names[c];
      s.pose = o.poses + k;
      s.name = names[c] + std::to_string(s.pose);
      s.noisy = true;
      bool done = false;
      const int max_draws = 60;
      for (int attempt = 0; attempt < max_draws && !done; ++attempt) {
        PoseAngles angles = random_pose(
            cls.skeleton, derive_seed(ao.seed, 7777777ULL + 1000003ULL * k + attempt), ao.amplitude);
        Mesh posed{pose_mesh(cls.skeleton, cls.rest.V, W, angles), cls.rest.F};
        const bool intersects = self_intersects(posed);
        if (poll) poll("", 0, 0);
        if (intersects) continue;
        // Prefer poses whose parts almost touch at the default gap; widen the gap only after many draws.
        TopologicalNoiseOptions no;
        no.glue_count = o.glue_count;
        no.seed = derive_seed(ao.seed, 555ULL + k);
        no.gap_edge_lengths *= attempt < 10 ? 1.0 : attempt < 20 ? 1.5 : 2.0;
        // Shapes whose parts rarely come close (the spider's legs): after 30 draws, let gluing relax too.
        no.relax_steps = attempt < 30 ? 0 : 3;
        no.geodesic.progress = poll;
        try {
          TopologicalNoiseResult r = glue_topological_noise(posed, no);
          s.mesh = r.mesh;
          for (const GluedPair& g : r.pairs) s.glued_pairs.emplace_back(g.a, g.b);
          s.isometry = edge_length_change(cls.rest, posed.V);
          done = true;
        } catch (const Error&) {
          // too few almost-touching spots in this pose: draw another
        }
      }
      CSHAPES_REQUIRE(done, "dataset: no pose of class ", names[c], " could be glued ", o.glue_count,
                      " times in ", max_draws, " draws");
      shapes.push_back(std::move(s));
      report();
    }
  }
  return shapes;
}

}  // namespace cshapes
