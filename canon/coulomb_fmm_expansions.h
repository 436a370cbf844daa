// Internal to the fast multipole method (canon/coulomb_fmm.cpp): the Cartesian Taylor expansions of 1/r, their
// operators per order (P2M, M2M, L2L, L2P; M2L per instruction set), the octree cell they act on, and the
// parameters (order, opening angle, leaf size) that reach a requested accuracy. Written in
// canon/coulomb_fmm_expansions.cpp.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "cshapes/canon/coulomb_fmm.h"

namespace cshapes::fmm_detail {

// Four doubles in one AVX register (GCC/Clang vector extension): M2L runs four source cells at once.
typedef double V4 __attribute__((vector_size(32)));
typedef double UnalignedV4 __attribute__((vector_size(32), aligned(8)));  // for loads from std::vector rows

// Multi-indices k = (k_x, k_y, k_z) with |k| = k_x + k_y + k_z ≤ p, ordered by degree, and the index tables
// every expansion operator walks. A coefficient array of order p has count = (p+1)(p+2)(p+3)/6 entries.
struct MultiIndexTables {
  int order = 0;
  int count = 0;
  std::vector<std::array<int, 3>> exponent;
  std::vector<int> degree;
  std::vector<double> factorial;              // k! = k_x! k_y! k_z!
  std::vector<double> sign;                   // (−1)^|k|
  std::vector<int> parent, axis;              // k = parent + e_axis (axis: last nonzero component)
  std::vector<std::array<int, 3>> minus_one;  // index of k − e_i, or −1
  std::vector<std::array<int, 3>> minus_two;  // index of k − 2e_i, or −1
  std::vector<std::array<int, 3>> pair_sum;   // (m, k, m+k) with |m| + |k| ≤ p: M2L
  std::vector<std::array<int, 3>> shift;      // (k, a, k−a) with a ≤ k: M2M and L2L
  std::array<std::vector<std::array<int, 2>>, 3> gradient;  // (n, n + e_i) with |n| ≤ p − 1: L2P
  std::vector<int> lookup_table;                            // (p+1)³ → index, −1 when |k| > p
  // pair_sum grouped by m: entries [m2l_offset[m], m2l_offset[m+1]) of m2l_k / m2l_mk
  std::vector<int> m2l_offset, m2l_k, m2l_mk;
  // The recurrence's terms for each k: the existing k − e_i (with their axis i) and k − 2e_i
  struct RecurrenceTerms {
    int n1 = 0, n2 = 0;
    int axis1[3] = {0, 0, 0}, index1[3] = {0, 0, 0}, index2[3] = {0, 0, 0};
    double c1 = 0, c2 = 0;  // (2|k|−1)/|k| and (|k|−1)/|k|
  };
  std::vector<RecurrenceTerms> recurrence;

  explicit MultiIndexTables(int p);

  // out[k] = d^k / k!
  void monomials(const double d[3], double* out) const {
    out[0] = 1;
    for (int k = 1; k < count; ++k) out[k] = out[parent[k]] * d[axis[k]] / exponent[k][axis[k]];
  }

  // out[k] = ∂^k (1/‖R‖) for four separation vectors R at once, one per SIMD lane, from the recurrence for
  // the Taylor coefficients T_k = ∂^k(1/‖R‖)/k! of Duan & Krasny (2001):
  //   |k| ‖R‖² T_k + (2|k|−1) Σ_i R_i T_{k−e_i} + (|k|−1) Σ_i T_{k−2e_i} = 0.
  void derivatives4(const V4 R[3], V4* out) const {
    const V4 inv_r2 = 1.0 / (R[0] * R[0] + R[1] * R[1] + R[2] * R[2]);
    for (int l = 0; l < 4; ++l) out[0][l] = std::sqrt(inv_r2[l]);
    for (int k = 1; k < count; ++k) {
      const RecurrenceTerms& r = recurrence[k];
      V4 s1 = R[r.axis1[0]] * out[r.index1[0]];
      for (int t = 1; t < r.n1; ++t) s1 += R[r.axis1[t]] * out[r.index1[t]];
      V4 s2 = {0, 0, 0, 0};
      for (int t = 0; t < r.n2; ++t) s2 += out[r.index2[t]];
      out[k] = -(r.c1 * s1 + r.c2 * s2) * inv_r2;
    }
    for (int k = 1; k < count; ++k) out[k] *= factorial[k];
  }
};

struct Cell {
  int32_t begin = 0, end = 0;  // points [begin, end) in Morton order
  int32_t child_begin = -1;    // children are cells [child_begin, child_begin + child_count)
  int32_t child_count = 0;
  int32_t parent = -1;
  int32_t depth = 0;             // in the collapsed tree
  double center[3] = {0, 0, 0};  // centre of mass (unit charges): the expansion centre
  double radius = 0;             // max distance of the cell's points from center
  bool leaf() const { return child_count == 0; }
  int32_t size() const { return end - begin; }
};

// The unrolled P2M (points of a leaf → its multipole), M2M / L2L (a shift between a cell and its parent) and L2P
// (a leaf's local expansion → its points' potentials and forces) of order 3 … 6 (3 … 5 for the shifts);
// nullptr: the table-driven loops of MultiIndexTables (other orders).
using StaticP2MFunction = void (*)(const double*, const double*, const double*, int32_t, int32_t,
                                   const double*, double*);
using StaticL2PFunction = void (*)(const double*, const double*, const double*, int32_t, int32_t,
                                   const double*, const double*, double*, double*, double*, double*);
using StaticShiftFunction = void (*)(const double*, const double*, double*);
StaticP2MFunction static_p2m(int order);
StaticShiftFunction static_m2m(int order);
StaticShiftFunction static_l2l(int order);
StaticL2PFunction static_l2p(int order);

// The M2L of one target cell, compiled for each instruction set of support/simd.h
// (canon/coulomb_m2l_simd.inl): the same operations on the same vector type, in 256-bit registers there,
// unfused (-ffp-contract=off), so every target gives the same bytes.
using M2LCellFunction = void (*)(const double* center, const int32_t* list, size_t count, const Cell* cells,
                                 const double* multipoles, int stride, double* local);

// The unrolled M2L of a cell for this order (1 … 6) and the kernels' instruction set; nullptr: the
// table-driven loop (higher orders).
M2LCellFunction m2l_cell_kernel(int order);

// The tables of each order, built on first use and shared (read-only) by every later evaluation.
const MultiIndexTables& tables_of_order(int order);

// The translations of one cell, each by the unrolled kernel of its order where there is one, else by the
// tables' loops; points in normalized coordinates x, y, z (Morton order), mono: scratch of t.count doubles.
// P2M: M_k += Σ_j (x_j − z)^k / k! over the cell's points.
void p2m_cell(const MultiIndexTables& t, const Cell& cell, const double* x, const double* y, const double* z,
              double* M, double* mono);
// M2M: M_k += Σ_{a≤k} M^child_a s^{k−a}/(k−a)!, s = z_child − z.
void m2m_shift(const MultiIndexTables& t, const double s[3], const double* child, double* M, double* mono);
// L2L: L_a += Σ_{m≥a} L^parent_m s^{m−a}/(m−a)!, s = z − z_parent.
void l2l_shift(const MultiIndexTables& t, const double s[3], const double* parent, double* L, double* mono);
// L2P: φ_i += Σ_m L_m e^m/m!, f_i −= Σ_n L_{n+e_c} e^n/n!, e = x_i − z, over the cell's points.
void l2p_cell(const MultiIndexTables& t, const Cell& cell, const double* x, const double* y, const double* z,
              const double* L, double* potential, double* fx, double* fy, double* fz, double* mono);
// M2L into L of the target centre from the cells `list` (orders above 6, where there is no unrolled kernel):
// four sources per pass, one per lane, the lanes summed at the end in a fixed order. multipoles: `stride`
// doubles per cell, (−1)^|k| M_k; zero_moments: `stride` zeros (an empty lane). The vectors are scratch.
void m2l_table_driven(const MultiIndexTables& t, const double center[3], const std::vector<int32_t>& list,
                      const Cell* cells, const double* multipoles, int stride, const double* zero_moments,
                      std::vector<V4>& derivative, std::vector<V4>& moments, std::vector<V4>& accumulated,
                      double* L);

// The interaction lists of the calling thread's evaluations, kept between them for their capacity (cleared,
// not freed). Released when an evaluation needed more than kKeptListCells cells (about 1.5 million points at
// leaves of 48), so a single large evaluation does not hold its lists' memory afterwards.
struct ListStore {
  std::vector<std::vector<int32_t>> m2l, p2p;
};
inline constexpr size_t kKeptListCells = 100000;
ListStore& list_store();  // the calling thread's

// The buffers of one evaluation (canon/coulomb_fmm.cpp), kept by the calling thread from one evaluation to the
// next (the Coulomb iteration evaluates thousands of times at one size): allocating them afresh returned their
// pages to the system and faulted them in again each time, a noticeable share of an evaluation at the
// iteration's sizes (docs/coulomb-defaults.md, "The fast sum's parameters").
// Released after an evaluation of more than kKeptWorkspacePoints points, so a single large one does not hold
// its memory.
struct Workspace {
  std::vector<std::pair<uint64_t, int32_t>> keyed, keyed_scratch;
  std::vector<double> unit;
  std::vector<int32_t> order;
  std::vector<uint64_t> keys;
  std::vector<double> xd, yd, zd;
  std::vector<float> xs, ys, zs, xf, yf, zf, xl, yl, zl;
  std::vector<Cell> cells;
  std::vector<int32_t> depth_start;
  std::vector<double> multipoles, locals;
  std::vector<std::vector<int32_t>> deferred;
  std::vector<double> potential, fx, fy, fz;
};
inline constexpr Index kKeptWorkspacePoints = 200000;
Workspace& workspace();  // the calling thread's

// The cheapest parameters whose error on the test sets stayed below options.accuracy with a margin (the
// table: canon/coulomb_fmm_expansions.cpp; its measurements: docs/coulomb-defaults.md, "The fast sum's
// parameters"), with the options' explicit order, angle and leaf size.
struct FmmParameters {
  double accuracy;
  int order;
  double opening_angle;
  int leaf_size;
  bool framed_near_field = false;  // near field in leaf frames (see kFramedNearFieldMinAccuracy)
  bool refined_estimate = true;    // its 1/r refined by a Newton step (see kUnrefinedMinAccuracy)
};
FmmParameters choose_parameters(const CoulombFmmOptions& options);

}  // namespace cshapes::fmm_detail
