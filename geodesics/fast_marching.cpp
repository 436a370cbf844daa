#include "cshapes/geodesics/fast_marching.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "cshapes/support/error.h"

namespace cshapes {

namespace {

using Vec2 = Eigen::Vector2d;

double cross2(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Faces around each undirected edge, found by binary search in a sorted (edge key, face) list.
class EdgeFaces {
 public:
  explicit EdgeFaces(const Faces& F) {
    entries_.reserve(3 * F.rows());
    for (Index f = 0; f < F.rows(); ++f)
      for (int c = 0; c < 3; ++c) entries_.emplace_back(key(F(f, c), F(f, (c + 1) % 3)), static_cast<int>(f));
    std::sort(entries_.begin(), entries_.end());
  }
  // A face containing edge (a, b) other than `face`, or -1 (boundary edge).
  int other_face(int a, int b, int face) const {
    uint64_t k = key(a, b);
    auto it = std::lower_bound(entries_.begin(), entries_.end(), std::make_pair(k, -1));
    for (; it != entries_.end() && it->first == k; ++it)
      if (it->second != face) return it->second;
    return -1;
  }

 private:
  static uint64_t key(int a, int b) {
    if (a > b) std::swap(a, b);
    return (static_cast<uint64_t>(a) << 32) | static_cast<uint32_t>(b);
  }
  std::vector<std::pair<uint64_t, int>> entries_;
};

struct PendingStencil {
  int trigger;
  FastMarching::Stencil stencil;
};

// Stencil for updating `target` (at the origin) from `accepted` at p, with `other` at q.
FastMarching::Stencil make_stencil(int target, int other, const Vec2& p, const Vec2& q) {
  FastMarching::Stencil s;
  s.target = target;
  s.other = other;
  s.p_len = p.norm();
  s.q_len = q.norm();
  double det = p.x() * q.y() - p.y() * q.x();
  if (std::abs(det) <= 1e-14 * s.p_len * s.q_len) {  // degenerate triangle: edge updates only
    s.other = -1;
    s.inv00 = s.inv01 = s.inv10 = s.inv11 = 0;
    return s;
  }
  // Inverse of M = [p^T; q^T].
  s.inv00 = q.y() / det;
  s.inv01 = -p.y() / det;
  s.inv10 = -q.x() / det;
  s.inv11 = p.x() / det;
  return s;
}

// Planar-wavefront update (see the header): T_C from T_P (accepted) and T_Q, or +inf when not causal.
double triangle_update(const FastMarching::Stencil& s, double t_p, double t_q) {
  // Work relative to T_P for accuracy far from the source: T' = T_C - T_P, right-hand side (0, T_Q - T_P).
  const double dq = t_q - t_p;
  const double a0 = s.inv00 + s.inv01, a1 = s.inv10 + s.inv11;  // a = M^{-1} 1
  const double b0 = s.inv01 * dq, b1 = s.inv11 * dq;            // b = M^{-1} (0, dq)
  const double aa = a0 * a0 + a1 * a1, ab = a0 * b0 + a1 * b1, bb = b0 * b0 + b1 * b1;
  // |b - T' a|^2 = 1
  const double disc = ab * ab - aa * (bb - 1.0);
  if (disc < 0) return std::numeric_limits<double>::infinity();
  const double t = (ab + std::sqrt(disc)) / aa;
  if (t < std::max(0.0, dq)) return std::numeric_limits<double>::infinity();
  const double n0 = b0 - t * a0, n1 = b1 - t * a1;
  // -n = alpha p + beta q with alpha, beta >= 0: the characteristic enters C through the triangle.
  const double alpha = -(s.inv00 * n0 + s.inv10 * n1);
  const double beta = -(s.inv01 * n0 + s.inv11 * n1);
  // alpha and beta are per unit length: the tolerance is relative to the edges (an absolute -1e-12 let
  // non-causal updates through on a mesh scaled by 1e12: distances 4% short).
  const double tolerance = -1e-12;
  if (alpha * s.p_len < tolerance || beta * s.q_len < tolerance) return std::numeric_limits<double>::infinity();
  return t_p + t;
}

// Binary min-heap of trial vertices keyed by their current distance, with each vertex's position so that a
// decreased distance is sifted up in place (no duplicate entries, the heap holds only the narrow band).
class TrialHeap {
 public:
  TrialHeap(const double* key, Index n) : key_(key), position_(n, -1) { heap_.reserve(1024); }
  bool empty() const { return heap_.empty(); }
  // Inserts v, or restores the order after key[v] decreased.
  void push_or_decrease(int v) {
    int at = position_[v];
    if (at == -2) return;  // accepted
    if (at < 0) {
      at = static_cast<int>(heap_.size());
      heap_.push_back(v);
    }
    sift_up(at, v);
  }
  int pop() {
    const int top = heap_[0];
    position_[top] = -2;  // accepted: never inserted again (its key only decreases while it is trial)
    const int last = heap_.back();
    heap_.pop_back();
    if (!heap_.empty()) sift_down(0, last);
    return top;
  }

 private:
  void sift_up(int at, int v) {
    const double k = key_[v];
    while (at > 0) {
      const int parent = (at - 1) / 2;
      if (key_[heap_[parent]] <= k) break;
      heap_[at] = heap_[parent];
      position_[heap_[at]] = at;
      at = parent;
    }
    heap_[at] = v;
    position_[v] = at;
  }
  void sift_down(int at, int v) {
    const double k = key_[v];
    const int size = static_cast<int>(heap_.size());
    while (true) {
      int child = 2 * at + 1;
      if (child >= size) break;
      if (child + 1 < size && key_[heap_[child + 1]] < key_[heap_[child]]) ++child;
      if (key_[heap_[child]] >= k) break;
      heap_[at] = heap_[child];
      position_[heap_[at]] = at;
      at = child;
    }
    heap_[at] = v;
    position_[v] = at;
  }
  const double* key_;
  std::vector<int> heap_;
  std::vector<int> position_;  // index in heap_, -1 never inserted, -2 accepted
};

// Dijkstra-ordered marching: pops the trial vertex of least distance, accepts it, updates its stencils'
// targets. Vertices alive on entry are never changed.
void march(const std::vector<int>& offsets, const std::vector<FastMarching::Stencil>& stencils,
           Eigen::VectorXd& dist, std::vector<char>& alive, TrialHeap& heap) {
  while (!heap.empty()) {
    const int i = heap.pop();
    const double t_i = dist[i];
    alive[i] = 1;
    for (int k = offsets[i]; k < offsets[i + 1]; ++k) {
      const FastMarching::Stencil& s = stencils[k];
      // Both candidates are at least t_i: nothing to gain where the target is that close already (which
      // includes every vertex accepted by this march); vertices alive from the start are never changed.
      if (t_i >= dist[s.target] || alive[s.target]) continue;
      double candidate = t_i + s.p_len;
      if (s.other >= 0 && alive[s.other])
        candidate = std::min(candidate, triangle_update(s, t_i, dist[s.other]));
      if (candidate < dist[s.target]) {
        dist[s.target] = candidate;
        heap.push_or_decrease(s.target);
      }
    }
  }
}

}  // namespace

FastMarching::FastMarching(const Mesh& mesh, const FastMarchingOptions& options)
    : num_vertices_(mesh.num_vertices()) {
  const Points& V = mesh.V;
  const Faces& F = mesh.F;
  for (Index f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c)
      CSHAPES_REQUIRE(F(f, c) >= 0 && F(f, c) < num_vertices_, "fast marching: face ", f,
                      " has vertex index ", F(f, c), " outside 0..", num_vertices_ - 1);
  EdgeFaces edge_faces(F);
  auto length = [&](int i, int j) { return (V.row(i) - V.row(j)).norm(); };

  std::vector<PendingStencil> pending;
  pending.reserve(6 * F.rows() + 64);
  for (Index f = 0; f < F.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int C = F(f, c), P = F(f, (c + 1) % 3), Q = F(f, (c + 2) % 3);
      // The triangle in the plane: C at the origin, P on the x axis, Q above it.
      const double cp = length(C, P), cq = length(C, Q), pq = length(P, Q);
      const double qx = (cp * cp + cq * cq - pq * pq) / (2 * cp);
      const Vec2 p(cp, 0.0), q(qx, std::sqrt(std::max(0.0, cq * cq - qx * qx)));
      const bool obtuse = p.dot(q) < 0;
      int D = -1;
      Vec2 d;
      if (obtuse) {
        ++obtuse_corners_;
        if (options.unfold_obtuse) {
          // Walk across edges, unfolding each next triangle, until a vertex lands in the acute section.
          int A = P, B = Q, face = static_cast<int>(f);
          Vec2 a = p, b = q, prev_pos(0, 0);
          for (int step = 0; step < options.max_unfold_steps; ++step) {
            int g = edge_faces.other_face(A, B, face);
            if (g < 0) break;
            int R = -1;
            for (int k = 0; k < 3; ++k)
              if (F(g, k) != A && F(g, k) != B) R = F(g, k);
            if (R < 0 || R == C) break;
            const Vec2 e = b - a;
            const double ab_len = e.norm(), ar = length(A, R), br = length(B, R);
            const double x = (ar * ar - br * br + ab_len * ab_len) / (2 * ab_len);
            const double y = std::sqrt(std::max(0.0, ar * ar - x * x));
            Vec2 perp(-e.y() / ab_len, e.x() / ab_len);
            if ((prev_pos - a).dot(perp) > 0) perp = -perp;  // the unfolded vertex lies across AB from prev
            const Vec2 r = a + x * e / ab_len + y * perp;
            const bool acute_p = r.dot(p) > 0, acute_q = r.dot(q) > 0;
            if (acute_p && acute_q && cross2(p, r) > 0 && cross2(r, q) > 0) {
              D = R;
              d = r;
              break;
            }
            if (!acute_p) {  // R lies past the section on Q's side: the section crosses edge A R
              prev_pos = b;
              B = R, b = r;
            } else {  // past it on P's side: the section crosses edge R B
              prev_pos = a;
              A = R, a = r;
            }
            face = g;
          }
        }
      }
      if (D < 0) {
        pending.push_back({P, make_stencil(C, Q, p, q)});
        pending.push_back({Q, make_stencil(C, P, q, p)});
      } else {
        ++split_corners_;
        // Two acute virtual triangles C P D and C D Q replace the obtuse one.
        pending.push_back({P, make_stencil(C, D, p, d)});
        pending.push_back({D, make_stencil(C, P, d, p)});
        pending.push_back({D, make_stencil(C, Q, d, q)});
        pending.push_back({Q, make_stencil(C, D, q, d)});
      }
    }
  }
  offsets_.assign(num_vertices_ + 1, 0);
  for (const PendingStencil& s : pending) ++offsets_[s.trigger + 1];
  for (Index i = 0; i < num_vertices_; ++i) offsets_[i + 1] += offsets_[i];
  stencils_.resize(pending.size());
  std::vector<int> fill(offsets_.begin(), offsets_.end() - 1);
  for (const PendingStencil& s : pending) stencils_[fill[s.trigger]++] = s.stencil;
}

Eigen::VectorXd FastMarching::distances(const std::vector<int>& sources) const {
  Eigen::VectorXd out;
  distances(sources, out);
  return out;
}

void FastMarching::distances(const std::vector<int>& sources, Eigen::VectorXd& dist) const {
  const double inf = std::numeric_limits<double>::infinity();
  dist.setConstant(num_vertices_, inf);
  std::vector<char> alive(num_vertices_, 0);
  TrialHeap heap(dist.data(), num_vertices_);
  for (int s : sources) {
    CSHAPES_REQUIRE(s >= 0 && s < num_vertices_, "fast marching: source vertex ", s, " out of range 0..",
                    num_vertices_ - 1);
    dist[s] = 0;
    heap.push_or_decrease(s);
  }
  march(offsets_, stencils_, dist, alive, heap);
}

void FastMarching::continue_distances(Eigen::VectorXd& dist, const std::vector<char>& known) const {
  CSHAPES_REQUIRE(dist.size() == num_vertices_ && static_cast<Index>(known.size()) == num_vertices_,
                  "fast marching: continue_distances needs ", num_vertices_, " values and flags, got ",
                  dist.size(), " and ", known.size());
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<char> alive(num_vertices_, 0);
  for (Index i = 0; i < num_vertices_; ++i) {
    if (!known[i]) {
      dist[i] = inf;
      continue;
    }
    CSHAPES_REQUIRE(std::isfinite(dist[i]), "fast marching: known vertex ", i, " has distance ", dist[i]);
    alive[i] = 1;
  }
  // The front: known vertices with a stencil into the unknown region. Pushed as trial vertices (so they
  // are popped in order of their values), but marked alive: the march never changes them, and stencils use
  // them as accepted neighbours from the start.
  TrialHeap heap(dist.data(), num_vertices_);
  for (Index i = 0; i < num_vertices_; ++i) {
    if (!alive[i]) continue;
    for (int k = offsets_[i]; k < offsets_[i + 1]; ++k)
      if (!alive[stencils_[k].target]) {
        heap.push_or_decrease(static_cast<int>(i));
        break;
      }
  }
  march(offsets_, stencils_, dist, alive, heap);
}

Eigen::VectorXd fast_marching(const Mesh& mesh, const std::vector<int>& sources,
                              const FastMarchingOptions& options) {
  return FastMarching(mesh, options).distances(sources);
}

}  // namespace cshapes
