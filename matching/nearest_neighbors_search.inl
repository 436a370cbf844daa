// The KD-tree's search (matching/nearest_neighbors.cpp), written once over a vector of kLanes doubles and
// included inside one namespace per instruction set, under that set's `#pragma GCC target` (support/simd.h):
// the includer defines kLanes, kLeaf and Node and includes the headers first. Every target computes the same
// squared distances ((x − q)² summed in the order x, y, z, two roundings per term: the file is compiled
// without fused multiply-adds) and picks the same point, so every target gives the same bytes.

typedef double Vec __attribute__((vector_size(8 * kLanes), aligned(8), may_alias));
constexpr int kVectors = kLeaf / kLanes;
static_assert(kVectors % 4 == 0, "a leaf is scanned 4 vectors at a time");

// The leaf's squared distances a vector at a time, then one horizontal minimum: no branch per point.
inline void scan_leaf(const TreeArrays& t, int first_slot, const double* q, double& best_d2, int& best_slot) {
  const size_t s = static_cast<size_t>(first_slot);
  Vec qx, qy, qz, start;
  for (int l = 0; l < kLanes; ++l) {
    qx[l] = q[0];
    qy[l] = q[1];
    qz[l] = q[2];
    start[l] = best_d2;
  }
  Vec d2[kVectors];
  // Four running minima: independent dependency chains. A padding slot's NaN distance never replaces one
  // (NaN < v is false), so they start from best_d2 rather than from a first distance that may be NaN.
  Vec running[4] = {start, start, start, start};
  for (int b = 0; b < kVectors; b += 4) {
    for (int u = 0; u < 4; ++u) {
      const Vec px = *reinterpret_cast<const Vec*>(t.x + s + kLanes * (b + u));
      const Vec py = *reinterpret_cast<const Vec*>(t.y + s + kLanes * (b + u));
      const Vec pz = *reinterpret_cast<const Vec*>(t.z + s + kLanes * (b + u));
      const Vec dx = px - qx, dy = py - qy, dz = pz - qz;
      d2[b + u] = dx * dx + dy * dy + dz * dz;
      running[u] = d2[b + u] < running[u] ? d2[b + u] : running[u];
    }
  }
  Vec least0 = running[0], least1 = running[1], least2 = running[2], least3 = running[3];
  least0 = least1 < least0 ? least1 : least0;
  least2 = least3 < least2 ? least3 : least2;
  const Vec least = least2 < least0 ? least2 : least0;
  double m = least[0];
  for (int l = 1; l < kLanes; ++l) m = std::min(m, least[l]);
  if (!(m < best_d2)) return;
  for (int k = 0; k < kLeaf; ++k)
    if (d2[k / kLanes][k % kLanes] == m) {
      best_d2 = m;
      best_slot = first_slot + k;
      return;
    }
}

inline void search(const TreeArrays& t, int node, const double* q, double box_d2, double* axis_d2,
                   double& best_d2, int& best_slot) {
  const Node& n = t.nodes[static_cast<size_t>(node)];
  if (n.axis < 0) {
    scan_leaf(t, n.second, q, best_d2, best_slot);
    return;
  }
  const int axis = n.axis;
  const double v = q[axis];
  int nearer, farther;
  double cut;  // squared distance along `axis` from q to the farther child's side
  if ((v - n.low) + (v - n.high) < 0) {
    nearer = node + 1;
    farther = n.second;
    cut = (v - n.high) * (v - n.high);
  } else {
    nearer = n.second;
    farther = node + 1;
    cut = (v - n.low) * (v - n.low);
  }
  search(t, nearer, q, box_d2, axis_d2, best_d2, best_slot);
  const double saved = axis_d2[axis];
  const double farther_d2 = box_d2 + cut - saved;
  if (farther_d2 < best_d2) {
    axis_d2[axis] = cut;
    search(t, farther, q, farther_d2, axis_d2, best_d2, best_slot);
    axis_d2[axis] = saved;
  }
}

// Exact nearest slot to q among points nearer than sqrt(best_d2); best_slot unchanged if none.
inline void find(const TreeArrays& t, const double* q, double& best_d2, int& best_slot) {
  // Squared distance from q to the bounding box, per axis: the search's lower bound.
  double axis_d2[3];
  double box_d2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double below = t.box_low[k] - q[k], above = q[k] - t.box_high[k];
    const double d = below > 0 ? below : above > 0 ? above : 0.0;
    axis_d2[k] = d * d;
    box_d2 += axis_d2[k];
  }
  search(t, 0, q, box_d2, axis_d2, best_d2, best_slot);
}

// Not inline: the entry the dispatcher calls, compiled under the includer's target.
void find_entry(const TreeArrays& t, const double* q, double& best_d2, int& best_slot) {
  find(t, q, best_d2, best_slot);
}
