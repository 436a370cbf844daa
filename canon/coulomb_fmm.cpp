#include "canon/coulomb_fmm.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "canon/coulomb_p2p.h"
#include "core/error.h"
#include "core/morton.h"
#include "core/simd.h"
#include "core/timing.h"

namespace cshapes {
namespace {

using coulomb_detail::FloatPoints;
using coulomb_detail::FramedRange;
using coulomb_detail::kBlock;
using coulomb_detail::SourceRange;

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

  explicit MultiIndexTables(int p) : order(p) {
    const int side = p + 1;
    lookup_table.assign(side * side * side, -1);
    for (int d = 0; d <= p; ++d)
      for (int a = d; a >= 0; --a)
        for (int b = d - a; b >= 0; --b) {
          const int c = d - a - b;
          lookup_table[(a * side + b) * side + c] = static_cast<int>(exponent.size());
          exponent.push_back({a, b, c});
          degree.push_back(d);
        }
    count = static_cast<int>(exponent.size());
    auto index = [&](std::array<int, 3> k) {
      if (k[0] < 0 || k[1] < 0 || k[2] < 0 || k[0] + k[1] + k[2] > p) return -1;
      return lookup_table[(k[0] * side + k[1]) * side + k[2]];
    };
    auto fact = [](int m) {
      double f = 1;
      for (int i = 2; i <= m; ++i) f *= i;
      return f;
    };
    factorial.resize(count), sign.resize(count), parent.assign(count, -1), axis.assign(count, -1);
    minus_one.resize(count), minus_two.resize(count);
    for (int k = 0; k < count; ++k) {
      const auto e = exponent[k];
      factorial[k] = fact(e[0]) * fact(e[1]) * fact(e[2]);
      sign[k] = degree[k] % 2 ? -1.0 : 1.0;
      for (int i = 0; i < 3; ++i) {
        auto m1 = e, m2 = e;
        m1[i] -= 1, m2[i] -= 2;
        minus_one[k][i] = index(m1);
        minus_two[k][i] = index(m2);
        if (e[i] > 0) axis[k] = i, parent[k] = index(m1);
      }
    }
    for (int m = 0; m < count; ++m)
      for (int k = 0; k < count; ++k) {
        const auto em = exponent[m], ek = exponent[k];
        const int mk = index({em[0] + ek[0], em[1] + ek[1], em[2] + ek[2]});
        if (mk >= 0) pair_sum.push_back({m, k, mk});
        if (ek[0] <= em[0] && ek[1] <= em[1] && ek[2] <= em[2])
          shift.push_back({m, k, index({em[0] - ek[0], em[1] - ek[1], em[2] - ek[2]})});
      }
    m2l_offset.push_back(0);
    for (int m = 0; m < count; ++m) {
      for (const auto& t : pair_sum)
        if (t[0] == m) m2l_k.push_back(t[1]), m2l_mk.push_back(t[2]);
      m2l_offset.push_back(static_cast<int>(m2l_k.size()));
    }
    recurrence.resize(count);
    for (int k = 1; k < count; ++k) {
      RecurrenceTerms& r = recurrence[k];
      for (int i = 0; i < 3; ++i) {
        if (minus_one[k][i] >= 0) r.axis1[r.n1] = i, r.index1[r.n1++] = minus_one[k][i];
        if (minus_two[k][i] >= 0) r.index2[r.n2++] = minus_two[k][i];
      }
      r.c1 = (2.0 * degree[k] - 1) / degree[k];
      r.c2 = (degree[k] - 1.0) / degree[k];
    }
    for (int n = 0; n < count; ++n) {
      if (degree[n] >= p) continue;
      for (int i = 0; i < 3; ++i) {
        auto e = exponent[n];
        e[i] += 1;
        gradient[i].push_back({n, index(e)});
      }
    }
  }

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

// The compile-time tables of the M2L of order P (canon/coulomb_m2l_simd.inl), so that its fully unrolled
// loops address registers and fixed offsets instead of loading indices (about 2× faster than the table-driven
// loop of MultiIndexTables). Same multi-index order as MultiIndexTables.
template <int P>
struct StaticM2L {
  static constexpr int kCount = (P + 1) * (P + 2) * (P + 3) / 6;
  static constexpr int kPairs = (P + 1) * (P + 2) * (P + 3) * (P + 4) * (P + 5) * (P + 6) / 720;
  struct Tables {
    int exponent[kCount][3] = {};
    int n1[kCount] = {}, axis1[kCount][3] = {}, index1[kCount][3] = {}, n2[kCount] = {},
        index2[kCount][3] = {};
    double c1[kCount] = {}, c2[kCount] = {}, factorial[kCount] = {};
    int pair_m[kPairs] = {}, pair_k[kPairs] = {}, pair_mk[kPairs] = {};
  };
  static constexpr int index_of(const Tables& t, int a, int b, int c) {
    if (a < 0 || b < 0 || c < 0 || a + b + c > P) return -1;
    for (int k = 0; k < kCount; ++k)
      if (t.exponent[k][0] == a && t.exponent[k][1] == b && t.exponent[k][2] == c) return k;
    return -1;
  }
  static constexpr Tables make() {
    Tables t;
    int next = 0;
    for (int d = 0; d <= P; ++d)
      for (int a = d; a >= 0; --a)
        for (int b = d - a; b >= 0; --b) {
          t.exponent[next][0] = a, t.exponent[next][1] = b, t.exponent[next][2] = d - a - b;
          ++next;
        }
    for (int k = 0; k < kCount; ++k) {
      const int d = t.exponent[k][0] + t.exponent[k][1] + t.exponent[k][2];
      double f = 1;
      for (int i = 0; i < 3; ++i)
        for (int q = 2; q <= t.exponent[k][i]; ++q) f *= q;
      t.factorial[k] = f;
      if (d == 0) continue;
      for (int i = 0; i < 3; ++i) {
        int e1[3] = {t.exponent[k][0], t.exponent[k][1], t.exponent[k][2]};
        int e2[3] = {e1[0], e1[1], e1[2]};
        e1[i] -= 1, e2[i] -= 2;
        const int i1 = index_of(t, e1[0], e1[1], e1[2]), i2 = index_of(t, e2[0], e2[1], e2[2]);
        if (i1 >= 0) t.axis1[k][t.n1[k]] = i, t.index1[k][t.n1[k]++] = i1;
        if (i2 >= 0) t.index2[k][t.n2[k]++] = i2;
      }
      t.c1[k] = (2.0 * d - 1) / d;
      t.c2[k] = (d - 1.0) / d;
    }
    int pair = 0;
    for (int m = 0; m < kCount; ++m)
      for (int k = 0; k < kCount; ++k) {
        const int mk = index_of(t, t.exponent[m][0] + t.exponent[k][0], t.exponent[m][1] + t.exponent[k][1],
                                t.exponent[m][2] + t.exponent[k][2]);
        if (mk < 0) continue;
        t.pair_m[pair] = m, t.pair_k[pair] = k, t.pair_mk[pair] = mk;
        ++pair;
      }
    return t;
  }
  static constexpr Tables kTables = make();
};

// P2M and L2P of one leaf with compile-time tables (unrolled, like StaticM2L; ≈ 3× faster than the table
// loops of MultiIndexTables). Same multi-index order and the same formulas as the table-driven passes.
template <int P>
struct StaticPointExpansion {
  static constexpr int kCount = StaticM2L<P>::kCount;
  static constexpr int kGradient = P * (P + 1) * (P + 2) / 6;  // multi-indices of degree ≤ P − 1
  struct Tables {
    int parent[kCount] = {}, axis[kCount] = {};
    double inverse_exponent[kCount] = {};                               // 1 / k_axis
    int gradient_from[kGradient] = {}, gradient_to[3][kGradient] = {};  // (n, n + e_i)
  };
  static constexpr Tables make() {
    constexpr const auto& m = StaticM2L<P>::kTables;
    Tables t;
    for (int k = 1; k < kCount; ++k)
      for (int i = 0; i < 3; ++i)
        if (m.exponent[k][i] > 0) {
          t.axis[k] = i;
          t.parent[k] = StaticM2L<P>::index_of(m, m.exponent[k][0] - (i == 0), m.exponent[k][1] - (i == 1),
                                               m.exponent[k][2] - (i == 2));
          t.inverse_exponent[k] = 1.0 / m.exponent[k][i];
        }
    int g = 0;
    for (int n = 0; n < kCount; ++n) {
      if (m.exponent[n][0] + m.exponent[n][1] + m.exponent[n][2] >= P) continue;
      t.gradient_from[g] = n;
      for (int i = 0; i < 3; ++i)
        t.gradient_to[i][g] = StaticM2L<P>::index_of(
            m, m.exponent[n][0] + (i == 0), m.exponent[n][1] + (i == 1), m.exponent[n][2] + (i == 2));
      ++g;
    }
    return t;
  }
  static constexpr Tables kTables = make();

  // The pairs (k, a, k − a) with a ≤ k componentwise, as MultiIndexTables::shift: M2M and L2L.
  static constexpr int count_shifts() {
    constexpr const auto& m = StaticM2L<P>::kTables;
    int c = 0;
    for (int k = 0; k < kCount; ++k)
      for (int a = 0; a < kCount; ++a)
        c += m.exponent[a][0] <= m.exponent[k][0] && m.exponent[a][1] <= m.exponent[k][1] &&
             m.exponent[a][2] <= m.exponent[k][2];
    return c;
  }
  static constexpr int kShifts = count_shifts();
  struct ShiftTables {
    int k[kShifts] = {}, a[kShifts] = {}, k_minus_a[kShifts] = {};
  };
  static constexpr ShiftTables make_shifts() {
    constexpr const auto& m = StaticM2L<P>::kTables;
    ShiftTables t;
    int c = 0;
    for (int k = 0; k < kCount; ++k)
      for (int a = 0; a < kCount; ++a)
        if (m.exponent[a][0] <= m.exponent[k][0] && m.exponent[a][1] <= m.exponent[k][1] &&
            m.exponent[a][2] <= m.exponent[k][2]) {
          t.k[c] = k, t.a[c] = a;
          t.k_minus_a[c] = StaticM2L<P>::index_of(m, m.exponent[k][0] - m.exponent[a][0],
                                                  m.exponent[k][1] - m.exponent[a][1],
                                                  m.exponent[k][2] - m.exponent[a][2]);
          ++c;
        }
    return t;
  }
  static constexpr ShiftTables kShiftTables = make_shifts();

  // M2M: M_k += Σ_{a≤k} M^child_a s^{k−a}/(k−a)!
  static void m2m(const double s[3], const double* child, double* M) {
    constexpr const ShiftTables& t = kShiftTables;
    double mono[kCount];
    monomials(s, mono);
#pragma GCC unroll 1024
    for (int j = 0; j < kShifts; ++j) M[t.k[j]] += child[t.a[j]] * mono[t.k_minus_a[j]];
  }
  // L2L: L_a += Σ_{m≥a} L^parent_m t^{m−a}/(m−a)!
  static void l2l(const double shift[3], const double* parent, double* L) {
    constexpr const ShiftTables& t = kShiftTables;
    double mono[kCount];
    monomials(shift, mono);
#pragma GCC unroll 1024
    for (int j = 0; j < kShifts; ++j) L[t.a[j]] += parent[t.k[j]] * mono[t.k_minus_a[j]];
  }

  // out[k] = d^k / k!
  static void monomials(const double d[3], double* out) {
    constexpr const Tables& t = kTables;
    out[0] = 1;
#pragma GCC unroll 128
    for (int k = 1; k < kCount; ++k) out[k] = out[t.parent[k]] * d[t.axis[k]] * t.inverse_exponent[k];
  }

  // M_k += Σ_i (x_i − z)^k / k! over points [begin, end)
  static void p2m(const double* x, const double* y, const double* z, int32_t begin, int32_t end,
                  const double center[3], double* M) {
    double sum[kCount] = {}, mono[kCount];
    for (int32_t i = begin; i < end; ++i) {
      const double d[3] = {x[i] - center[0], y[i] - center[1], z[i] - center[2]};
      monomials(d, mono);
#pragma GCC unroll 128
      for (int k = 0; k < kCount; ++k) sum[k] += mono[k];
    }
    for (int k = 0; k < kCount; ++k) M[k] += sum[k];
  }

  // φ_i += Σ_m L_m e^m/m!, force_i −= Σ_n L_{n+e_c} e^n/n!, e = x_i − z, over points [begin, end)
  static void l2p(const double* x, const double* y, const double* z, int32_t begin, int32_t end,
                  const double center[3], const double* L, double* potential, double* fx, double* fy,
                  double* fz) {
    constexpr const Tables& t = kTables;
    double mono[kCount];
    for (int32_t i = begin; i < end; ++i) {
      const double e[3] = {x[i] - center[0], y[i] - center[1], z[i] - center[2]};
      monomials(e, mono);
      double phi = 0, g[3] = {0, 0, 0};
#pragma GCC unroll 128
      for (int m = 0; m < kCount; ++m) phi += L[m] * mono[m];
#pragma GCC unroll 128
      for (int j = 0; j < kGradient; ++j) {
        g[0] += L[t.gradient_to[0][j]] * mono[t.gradient_from[j]];
        g[1] += L[t.gradient_to[1][j]] * mono[t.gradient_from[j]];
        g[2] += L[t.gradient_to[2][j]] * mono[t.gradient_from[j]];
      }
      potential[i] += phi;
      fx[i] -= g[0], fy[i] -= g[1], fz[i] -= g[2];
    }
  }
};

using StaticP2MFunction = void (*)(const double*, const double*, const double*, int32_t, int32_t,
                                   const double*, double*);
using StaticL2PFunction = void (*)(const double*, const double*, const double*, int32_t, int32_t,
                                   const double*, const double*, double*, double*, double*, double*);
StaticP2MFunction static_p2m(int order) {
  switch (order) {
    case 3:
      return &StaticPointExpansion<3>::p2m;
    case 4:
      return &StaticPointExpansion<4>::p2m;
    case 5:
      return &StaticPointExpansion<5>::p2m;
    case 6:
      return &StaticPointExpansion<6>::p2m;
    default:
      return nullptr;  // other orders use the table-driven loop
  }
}
using StaticShiftFunction = void (*)(const double*, const double*, double*);
StaticShiftFunction static_m2m(int order) {
  switch (order) {
    case 3:
      return &StaticPointExpansion<3>::m2m;
    case 4:
      return &StaticPointExpansion<4>::m2m;
    case 5:
      return &StaticPointExpansion<5>::m2m;
    default:
      return nullptr;  // other orders use the table-driven loop
  }
}
StaticShiftFunction static_l2l(int order) {
  switch (order) {
    case 3:
      return &StaticPointExpansion<3>::l2l;
    case 4:
      return &StaticPointExpansion<4>::l2l;
    case 5:
      return &StaticPointExpansion<5>::l2l;
    default:
      return nullptr;
  }
}
StaticL2PFunction static_l2p(int order) {
  switch (order) {
    case 3:
      return &StaticPointExpansion<3>::l2p;
    case 4:
      return &StaticPointExpansion<4>::l2p;
    case 5:
      return &StaticPointExpansion<5>::l2p;
    case 6:
      return &StaticPointExpansion<6>::l2p;
    default:
      return nullptr;
  }
}

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

// The M2L of one target cell, compiled for each instruction set of core/simd.h
// (canon/coulomb_m2l_simd.inl): the same operations on the same vector type, in 256-bit registers and with
// fused multiply-adds there.
using M2LCellFunction = void (*)(const double* center, const int32_t* list, size_t count, const Cell* cells,
                                 const double* multipoles, int stride, double* local);
#pragma GCC push_options
#pragma GCC target("avx2,fma")
namespace avx2 {
#include "canon/coulomb_m2l_simd.inl"
}  // namespace avx2
#pragma GCC pop_options
#pragma GCC push_options
#pragma GCC target("avx2,fma,avx512f,avx512vl,avx512dq,avx512bw")
namespace avx512 {
#include "canon/coulomb_m2l_simd.inl"
}  // namespace avx512
#pragma GCC pop_options
namespace baseline {
#include "canon/coulomb_m2l_simd.inl"
}  // namespace baseline

// The unrolled M2L of a cell for this order (1 … 6) and the kernels' instruction set; nullptr: the
// table-driven loop (higher orders).
M2LCellFunction m2l_cell_kernel(int order) {
  switch (simd_target()) {
    case SimdTarget::Avx512:
      return avx512::m2l_cell_function(order);
    case SimdTarget::Avx2:
      return avx2::m2l_cell_function(order);
    case SimdTarget::Baseline:
      break;
  }
  return baseline::m2l_cell_function(order);
}

constexpr int kMortonLevels = 21;  // Morton code bits per axis (core/morton.h)

// The tables of each order, built on first use and shared (read-only) by every later evaluation.
const MultiIndexTables& tables_of_order(int order) {
  static std::array<std::once_flag, 17> once;
  static std::array<std::unique_ptr<const MultiIndexTables>, 17> tables;
  std::call_once(once[order], [&] { tables[order] = std::make_unique<const MultiIndexTables>(order); });
  return *tables[order];
}

// The accuracy → (order, θ, leaf size) table, measured with `cshapes bench coulomb --threads 1` (relative L2
// gradient error against exact direct summation).
// 1. Synthetic sets, n = 50,000 (--full-direct-max 0 --sample 500), worst of uniform cube, sphere, clustered
//    and points on tosca5k/cat0's surface, over p ∈ 3…10, θ ∈ {0.4 … 0.7}, leaf ∈ {48, 96}:
//      (3, 0.7) 3.0e-3   (3, 0.6) 1.8e-3   (4, 0.6) 5.9e-4   (5, 0.6) 1.7e-4   (4, 0.5) 2.5e-4   (5,
//      0.5) 6.4e-5 (6, 0.5) 2.3e-5   (6, 0.4) 4.8e-6   (7, 0.4) 1.4e-6   (8, 0.4) 4.8e-7   (10, 0.4) 4.3e-7
//    Smaller sets can be worse: for p = 4 over n ∈ {1000, …, 30000} the worst was 9.4e-4 at θ = 0.6
//    (uniform, n = 3505), 6.1e-4 at θ = 0.55, 3.9e-4 at θ = 0.5.
// 2. The vertices of real meshes are harder (regular spacing, a gradient that largely cancels): worst over
//    all 24 tosca5k meshes (--mesh FILE):
//      (4, 0.6) 1.9e-3   (4, 0.5) 9.3e-4   (4, 0.45) 4.0e-4   (4, 0.4) 3.1e-4   (5, 0.6) 9.0e-4   (5,
//      0.5) 4.5e-4 (5, 0.45) 1.2e-4  (6, 0.5) 2.3e-4   (6, 0.45) 6.1e-5   (6, 0.4) 4.1e-5
//    and over the four worst of them (michael0, victoria10, cat2, cat3):
//      (3, 0.6) 4.3e-3   (3, 0.4) 9.0e-4   (7, 0.4) 1.2e-5   (8, 0.35) 3.0e-6  (10, 0.35) 4.9e-7
// 3. With the framed near field (2 threads, --sample 500): at the default (4, 0.45, 48) tosca5k
//    worst 3.9e-4 (michael0); regular torus grids (vertices) 6.8e-4 at 225,000 and 6.9e-4 at 1,000,000
//    points, where θ = 0.5 gives 1.1e-3 and 1.2e-3 (so a larger θ for large n is not safe); random points at
//    1,000,000 (uniform, sphere, clustered, cat0 surface) 3.7e-5 … 1.4e-4.
// Each row below is the cheapest setting whose worst error over both kept a margin of ≥ 1.6× (2.5× at the
// default 1e-3 on the sets of 1 and 2, 1.45× on the torus grids of 3). The float near field limits the
// attainable error to ≈ 5e-7 … 1.1e-6 (order 10, θ = 0.05 still gives 5e-7 at n = 50,000; (10, 0.35)
// gave 1.1e-6 on 3,000 uniform points): requests below 3e-6 get the last row; use Summation::Direct for more.
// Energy errors were ≤ accuracy/10 except at 1e-2 (1.5e-4 on victoria10).
struct FmmParameters {
  double accuracy;
  int order;
  double opening_angle;
  int leaf_size;
  bool framed_near_field = false;  // near field in leaf frames (see kFramedNearFieldMinAccuracy)
};
constexpr FmmParameters kParameterTable[] = {
    {1e-2, 3, 0.6, 48},  {3e-3, 4, 0.6, 48}, {1e-3, 4, 0.45, 48}, {3e-4, 5, 0.45, 96},
    {1e-4, 6, 0.45, 96}, {3e-5, 7, 0.4, 96}, {1e-5, 8, 0.35, 96}, {3e-6, 10, 0.35, 96},
};

// The near field in local frames (coulomb_p2p.h, p2p_framed_block) is ≈ 1.3× faster than the exact-difference
// kernel (p2p_block) but rounds each difference to ~1e-7 of the frame's size (a leaf's parent) rather than of
// the difference: that adds up to 2e-5 … 4e-5 relative gradient error where the near forces cancel (3,000
// points on a sphere), harmless at 1e-3 but not at 1e-5. Requests below this, and orders above 5 (which
// only pay off below it), use the exact-difference kernel.
constexpr double kFramedNearFieldMinAccuracy = 3e-4;

FmmParameters choose_parameters(const CoulombFmmOptions& options) {
  CSHAPES_REQUIRE(options.accuracy > 0, "Coulomb FMM: accuracy must be positive, got ", options.accuracy);
  FmmParameters chosen = kParameterTable[std::size(kParameterTable) - 1];
  for (const FmmParameters& row : kParameterTable)
    if (row.accuracy <= options.accuracy) {
      chosen = row;
      break;
    }
  if (options.order > 0) chosen.order = options.order;
  chosen.framed_near_field = options.accuracy >= kFramedNearFieldMinAccuracy && chosen.order <= 5;
  if (options.opening_angle > 0) chosen.opening_angle = options.opening_angle;
  if (options.leaf_size > 0) chosen.leaf_size = options.leaf_size;
  CSHAPES_REQUIRE(chosen.order >= 1 && chosen.order <= 16, "Coulomb FMM: order must be in [1, 16], got ",
                  chosen.order);
  CSHAPES_REQUIRE(chosen.opening_angle > 0 && chosen.opening_angle < 1,
                  "Coulomb FMM: opening angle must be in (0, 1), got ", chosen.opening_angle);
  return chosen;
}

// The interaction lists of the calling thread's evaluations, kept between them for their capacity. Released
// when an evaluation needed more than kKeptListCells cells (about 1.5 million points at leaves of 48), so a
// single large evaluation does not hold its lists' memory afterwards.
struct ListStore {
  std::vector<std::vector<int32_t>> m2l, p2p;
};
constexpr size_t kKeptListCells = 100000;
ListStore& list_store() {
  thread_local ListStore store;
  return store;
}

class Fmm {
 public:
  // time_kernels: also time the M2L and P2P work of every cell (stats.seconds_m2l, seconds_p2p), two clock
  // reads per cell, for benchmarks; the phases are always timed.
  Fmm(const Points& X, const FmmParameters& parameters, double min_distance, CoulombFmmStats& stats,
      bool time_kernels)
      : X_(X),
        n_(X.rows()),
        tables_(tables_of_order(parameters.order)),
        stride_((tables_.count + 3) / 4 * 4),
        zero_moments_(stride_, 0.0),
        theta_(parameters.opening_angle),
        leaf_size_(parameters.leaf_size),
        framed_near_field_(parameters.framed_near_field),
        stats_(stats),
        time_kernels_(time_kernels) {
    norm_ = coulomb_detail::normalize_points(X, min_distance);
  }

  ~Fmm() {
    if (cells_.size() > kKeptListCells) list_store() = ListStore{};
  }

  CoulombEvaluation run(bool want_potentials) {
    auto t = WallClock::now();
    build_tree();
    stats_.seconds_tree = seconds_since(t);
    t = WallClock::now();
    upward_pass();
    stats_.seconds_upward = seconds_since(t);
    t = WallClock::now();
    // The lists live in a per-thread store that keeps their capacity from one evaluation to the next (the
    // Coulomb iteration evaluates thousands of times at one size): cleared, not freed. A first evaluation
    // allocates each list once instead of through a growth sequence (typical lists: ~60 M2L sources per cell,
    // ~30 near-field leaves per leaf at the default accuracy).
    if (m2l_lists_.size() < cells_.size()) {
      m2l_lists_.resize(cells_.size());
      p2p_lists_.resize(cells_.size());
    }
    for (size_t c = 0; c < cells_.size(); ++c) {
      m2l_lists_[c].clear();
      p2p_lists_[c].clear();
      if (m2l_lists_[c].capacity() == 0) m2l_lists_[c].reserve(64);
      if (cells_[c].leaf() && p2p_lists_[c].capacity() == 0) p2p_lists_[c].reserve(32);
    }
    traverse_parallel();
    stats_.seconds_traversal = seconds_since(t);
    t = WallClock::now();
    interactions();
    stats_.seconds_interactions = seconds_since(t);
    t = WallClock::now();
    downward_pass();
    stats_.seconds_downward = seconds_since(t);
    return gather(want_potentials);
  }

 private:
  void build_tree() {
    // Morton keys on a 2^21 grid over the normalized cube [-1, 1]³; sorting by (key, index) is deterministic.
    std::vector<std::pair<uint64_t, int32_t>> keyed(n_);
    const double cells_per_unit = 0.5 * double(1 << kMortonLevels);
    // The normalized coordinates in input order (reordered below, not computed twice).
    std::vector<double> unit(3 * static_cast<size_t>(n_));
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < n_; ++i) {
      uint64_t key = 0;
      for (int c = 0; c < 3; ++c) {
        const double u = (X_(i, c) - norm_.center[c]) / norm_.scale;
        unit[3 * i + c] = u;
        // floor, then clamp to the grid: for a finite value the same as clamping first and truncating
        // (which is floor on [0, max]), without SSE2's slow floor and unsigned conversion.
        const double g = std::clamp((u + 1) * cells_per_unit, 0.0, double((1 << kMortonLevels) - 1));
        key |= morton_spread_bits(static_cast<uint64_t>(static_cast<int64_t>(g))) << (2 - c);
      }
      keyed[i] = {key, static_cast<int32_t>(i)};
    }
    radix_sort_by_key(keyed, 3 * kMortonLevels);  // the same order as std::sort on the pairs
    order_.resize(n_);
    keys_.resize(n_);
    xd_.resize(n_), yd_.resize(n_), zd_.resize(n_);
    if (framed_near_field_) {
      xs_.resize(n_), ys_.resize(n_), zs_.resize(n_);
    } else {
      xf_.resize(n_), yf_.resize(n_), zf_.resize(n_), xl_.resize(n_), yl_.resize(n_), zl_.resize(n_);
    }
#pragma omp parallel for schedule(static)
    for (Index s = 0; s < n_; ++s) {
      const Index i = keyed[s].second;
      order_[s] = static_cast<int32_t>(i);
      keys_[s] = keyed[s].first;
      xd_[s] = unit[3 * i], yd_[s] = unit[3 * i + 1], zd_[s] = unit[3 * i + 2];
      if (!framed_near_field_) {
        coulomb_detail::split_float(xd_[s], xf_[s], xl_[s]);
        coulomb_detail::split_float(yd_[s], yf_[s], yl_[s]);
        coulomb_detail::split_float(zd_[s], zf_[s], zl_[s]);
      }
    }

    // Breadth-first: parents precede children, siblings are contiguous, depth never decreases.
    cells_.clear();
    std::vector<int> morton_level;  // octree level at which each cell's points start to differ
    Cell root;
    root.begin = 0, root.end = static_cast<int32_t>(n_);
    cells_.push_back(root);
    morton_level.push_back(0);
    for (size_t c = 0; c < cells_.size(); ++c) {
      const int32_t begin = cells_[c].begin, end = cells_[c].end;
      if (end - begin <= leaf_size_) continue;
      for (int level = morton_level[c]; level < kMortonLevels; ++level) {
        const int shift = 3 * (kMortonLevels - 1 - level);
        std::array<int32_t, 9> bound;
        bound[0] = begin;
        for (int o = 0; o < 8; ++o)
          bound[o + 1] = static_cast<int32_t>(
              std::partition_point(keys_.begin() + bound[o], keys_.begin() + end,
                                   [&](uint64_t k) { return static_cast<int>((k >> shift) & 7) <= o; }) -
              keys_.begin());
        int nonempty = 0;
        for (int o = 0; o < 8; ++o) nonempty += bound[o + 1] > bound[o];
        if (nonempty < 2) continue;  // a chain of single-child cells: skip the level
        cells_[c].child_begin = static_cast<int32_t>(cells_.size());
        for (int o = 0; o < 8; ++o) {
          if (bound[o + 1] == bound[o]) continue;
          Cell child;
          child.begin = bound[o], child.end = bound[o + 1];
          child.parent = static_cast<int32_t>(c);
          child.depth = cells_[c].depth + 1;
          cells_.push_back(child);
          morton_level.push_back(level + 1);
        }
        cells_[c].child_count = static_cast<int32_t>(cells_.size()) - cells_[c].child_begin;
        break;
      }
    }
    depth_start_.assign(1, 0);
    for (size_t c = 1; c < cells_.size(); ++c)
      if (cells_[c].depth != cells_[c - 1].depth) depth_start_.push_back(static_cast<int32_t>(c));
    depth_start_.push_back(static_cast<int32_t>(cells_.size()));

    // Centres of mass bottom-up, then the exact radius of each cell's points (O(n · depth)).
    for (size_t c = cells_.size(); c-- > 0;) {
      Cell& cell = cells_[c];
      double s[3] = {0, 0, 0};
      if (cell.leaf()) {
        for (int32_t i = cell.begin; i < cell.end; ++i) s[0] += xd_[i], s[1] += yd_[i], s[2] += zd_[i];
      } else {
        for (int32_t ch = cell.child_begin; ch < cell.child_begin + cell.child_count; ++ch)
          for (int k = 0; k < 3; ++k) s[k] += cells_[ch].center[k] * cells_[ch].size();
      }
      for (int k = 0; k < 3; ++k) cell.center[k] = s[k] / cell.size();
    }
#pragma omp parallel for schedule(dynamic, 16)
    for (size_t c = 0; c < cells_.size(); ++c) {
      Cell& cell = cells_[c];
      double r2 = 0;
      for (int32_t i = cell.begin; i < cell.end; ++i) {
        const double dx = xd_[i] - cell.center[0], dy = yd_[i] - cell.center[1], dz = zd_[i] - cell.center[2];
        r2 = std::max(r2, dx * dx + dy * dy + dz * dz);
      }
      cell.radius = std::sqrt(r2);
      if (framed_near_field_ && cell.leaf()) {  // the near field's float coordinates (coulomb_p2p.h)
        const Cell& frame = cells_[frame_cell(static_cast<int32_t>(c))];
        for (int32_t i = cell.begin; i < cell.end; ++i) {
          xs_[i] = coulomb_detail::frame_coordinate(xd_[i], frame.center[0]);
          ys_[i] = coulomb_detail::frame_coordinate(yd_[i], frame.center[1]);
          zs_[i] = coulomb_detail::frame_coordinate(zd_[i], frame.center[2]);
        }
      }
    }
    stats_.cells = static_cast<Index>(cells_.size());
    stats_.tree_depth = static_cast<Index>(depth_start_.size()) - 1;
    stats_.leaves = std::count_if(cells_.begin(), cells_.end(), [](const Cell& c) { return c.leaf(); });
  }

  // The frame of a leaf's near-field coordinates: its parent (the root for a single-leaf tree), so that
  // consecutive sibling leaves in a near-field list form one source range of one frame. Differences keep
  // ~1e-7 of the parent's size.
  int32_t frame_cell(int32_t leaf) const {
    return cells_[leaf].parent >= 0 ? cells_[leaf].parent : leaf;
  }

  double* multipole(size_t c) {
    return multipoles_.data() + c * stride_;
  }
  double* local(size_t c) {
    return locals_.data() + c * stride_;
  }

  // Few parallel regions on purpose: on a shared, oversubscribed machine every OpenMP barrier can cost a
  // scheduler time slice, so the cheap per-cell translations (M2M, L2L) run serially and only the per-point
  // work (P2M, L2P) and the interactions run in parallel.
  void upward_pass() {
    const int count = tables_.count;
    multipoles_.assign(cells_.size() * stride_, 0.0);
    locals_.assign(cells_.size() * stride_, 0.0);
    leaves_.clear();
    for (size_t c = 0; c < cells_.size(); ++c)
      if (cells_[c].leaf()) leaves_.push_back(static_cast<int32_t>(c));
    // P2M: M_k = Σ_j (x_j − z)^k / k!
    const StaticP2MFunction fixed_p2m = static_p2m(tables_.order);
#pragma omp parallel
    {
      std::vector<double> mono(count);
#pragma omp for schedule(dynamic, 16)
      for (size_t l = 0; l < leaves_.size(); ++l) {
        const Cell& cell = cells_[leaves_[l]];
        double* M = multipole(leaves_[l]);
        if (fixed_p2m) {
          fixed_p2m(xd_.data(), yd_.data(), zd_.data(), cell.begin, cell.end, cell.center, M);
          continue;
        }
        for (int32_t i = cell.begin; i < cell.end; ++i) {
          const double d3[3] = {xd_[i] - cell.center[0], yd_[i] - cell.center[1], zd_[i] - cell.center[2]};
          tables_.monomials(d3, mono.data());
          for (int k = 0; k < count; ++k) M[k] += mono[k];
        }
      }
    }
    // M2M, children before parents: M_k = Σ_children Σ_{a≤k} M^child_a s^{k−a}/(k−a)!, s = z_child − z
    std::vector<double> mono(count);
    const StaticShiftFunction fixed_m2m = static_m2m(tables_.order);
    for (size_t c = cells_.size(); c-- > 0;) {
      const Cell& cell = cells_[c];
      double* M = multipole(c);
      for (int32_t ch = cell.child_begin; ch < cell.child_begin + cell.child_count; ++ch) {
        const double s3[3] = {cells_[ch].center[0] - cell.center[0], cells_[ch].center[1] - cell.center[1],
                              cells_[ch].center[2] - cell.center[2]};
        const double* Mc = multipole(ch);
        if (fixed_m2m) {
          fixed_m2m(s3, Mc, M);
          continue;
        }
        tables_.monomials(s3, mono.data());
        for (const auto& t : tables_.shift) M[t[0]] += Mc[t[1]] * mono[t[2]];
      }
    }
    // Store (−1)^|k| M_k: the sign of the source offset in the Taylor expansion, applied once. (After the
    // M2M pass, which needs the unsigned moments of every child.)
    for (size_t c = 0; c < cells_.size(); ++c) {
      double* M = multipole(c);
      for (int k = 0; k < count; ++k) M[k] *= tables_.sign[k];
    }
  }

  // The traversal in parallel: a serial pass stops at target cells of at most `cut` points and defers their
  // pairs; then each deferred target's pairs are traversed by one thread, in the serial pass's order.
  // Deferred targets are disjoint subtrees, and traverse(a, ·) writes only to lists of a's subtree, so the
  // lists are the same as a serial traversal's, whatever the thread count.
  void traverse_parallel() {
    deferred_cut_ = std::max<int32_t>(static_cast<int32_t>(n_ / 32), leaf_size_);
    deferred_.assign(cells_.size(), {});
    deferring_ = true;
    traverse(0, 0);
    deferring_ = false;
    std::vector<int32_t> targets;
    for (size_t a = 0; a < cells_.size(); ++a)
      if (!deferred_[a].empty()) targets.push_back(static_cast<int32_t>(a));
#pragma omp parallel for schedule(dynamic, 1)
    for (size_t t = 0; t < targets.size(); ++t)
      for (int32_t b : deferred_[targets[t]]) traverse(targets[t], b);
    deferred_.clear();
  }

  // Dual-tree traversal (target a, source b): every ordered pair of points is covered exactly once, either by
  // an M2L of b's multipole into a's local expansion, or by a direct leaf-leaf sum.
  void traverse(int32_t a, int32_t b) {
    const Cell& A = cells_[a];
    const Cell& B = cells_[b];
    if (deferring_ && A.size() <= deferred_cut_) {
      deferred_[a].push_back(b);
      return;
    }
    if (a == b) {
      if (A.leaf()) {
        p2p_lists_[a].push_back(a);
        return;
      }
      for (int32_t ca = A.child_begin; ca < A.child_begin + A.child_count; ++ca)
        for (int32_t cb = A.child_begin; cb < A.child_begin + A.child_count; ++cb) traverse(ca, cb);
      return;
    }
    const double dx = A.center[0] - B.center[0], dy = A.center[1] - B.center[1],
                 dz = A.center[2] - B.center[2];
    if (well_separated(A.radius + B.radius, dx * dx + dy * dy + dz * dz)) {
      m2l_lists_[a].push_back(b);
      return;
    }
    if (A.leaf() && B.leaf()) {
      p2p_lists_[a].push_back(b);
      return;
    }
    if (!A.leaf() && (B.leaf() || A.radius >= B.radius)) {
      for (int32_t ca = A.child_begin; ca < A.child_begin + A.child_count; ++ca) traverse(ca, b);
    } else {
      for (int32_t cb = B.child_begin; cb < B.child_begin + B.child_count; ++cb) traverse(a, cb);
    }
  }

  // Whether r_A + r_B < θ·√d2, exactly as that expression evaluates (the traversal's lists, and so every bit
  // of the sum, are those of the square-root test): squares decide when they are farther apart than their
  // rounding (a few ulps) could move them, the square root only in between or near underflow.
  bool well_separated(double radii, double d2) const {
    const double lhs = radii * radii, rhs = theta2_ * d2;
    if (rhs > 1e-280) {
      if (lhs < rhs * (1 - 1e-12)) return true;
      if (lhs > rhs * (1 + 1e-12)) return false;
    }
    return radii < theta_ * std::sqrt(d2);
  }

  void interactions() {
    const int count = tables_.count;
    potential_.assign(n_, 0.0), fx_.assign(n_, 0.0), fy_.assign(n_, 0.0), fz_.assign(n_, 0.0);
    Index m2l_total = 0, p2p_total = 0;
    double m2l_seconds = 0, p2p_seconds = 0;
    const M2LCellFunction fixed_m2l = m2l_cell_kernel(tables_.order);
#pragma omp parallel reduction(+ : m2l_total, p2p_total, m2l_seconds, p2p_seconds)
    {
      std::vector<V4> derivative(count), moments(stride_), accumulated(count);
      std::vector<FramedRange> ranges;
      std::vector<SourceRange> exact_ranges;
#pragma omp for schedule(dynamic, 1)
      for (size_t a = 0; a < cells_.size(); ++a) {
        const Cell& A = cells_[a];
        // M2L: L_m += Σ_k (−1)^|k| M_k ∂^{m+k}(1/r)(z_a − z_b), four sources b per pass, one per lane;
        // the lanes are summed at the end in a fixed order (canon/coulomb_m2l_simd.inl for orders ≤ 6).
        const std::vector<int32_t>& list = m2l_lists_[a];
        const auto m2l_start = time_kernels_ ? WallClock::now() : WallClock::time_point{};
        if (!list.empty() && fixed_m2l) {
          fixed_m2l(A.center, list.data(), list.size(), cells_.data(), multipoles_.data(), stride_, local(a));
        } else if (!list.empty()) {  // orders above 6: the table-driven loop
          std::fill(accumulated.begin(), accumulated.end(), V4{0, 0, 0, 0});
          for (size_t g = 0; g < list.size(); g += 4) {
            V4 R[3];
            const double* M[4];
            for (int l = 0; l < 4; ++l) {
              if (g + l < list.size()) {
                const Cell& B = cells_[list[g + l]];
                for (int c = 0; c < 3; ++c) R[c][l] = A.center[c] - B.center[c];
                M[l] = multipole(list[g + l]);
              } else {  // an empty lane: a harmless separation and no charge
                R[0][l] = 1, R[1][l] = 0, R[2][l] = 0;
                M[l] = zero_moments_.data();
              }
            }
            // moments[k][l] = M[l][k]: 4×4 transposes of aligned rows (stride_ is a multiple of 4).
            for (int k = 0; k < stride_; k += 4) {
              const V4 r0 = *reinterpret_cast<const UnalignedV4*>(M[0] + k),
                       r1 = *reinterpret_cast<const UnalignedV4*>(M[1] + k),
                       r2 = *reinterpret_cast<const UnalignedV4*>(M[2] + k),
                       r3 = *reinterpret_cast<const UnalignedV4*>(M[3] + k);
              const V4 a01 = __builtin_shufflevector(r0, r1, 0, 4, 2, 6),
                       b01 = __builtin_shufflevector(r0, r1, 1, 5, 3, 7),
                       a23 = __builtin_shufflevector(r2, r3, 0, 4, 2, 6),
                       b23 = __builtin_shufflevector(r2, r3, 1, 5, 3, 7);
              moments[k] = __builtin_shufflevector(a01, a23, 0, 1, 4, 5);
              moments[k + 1] = __builtin_shufflevector(b01, b23, 0, 1, 4, 5);
              moments[k + 2] = __builtin_shufflevector(a01, a23, 2, 3, 6, 7);
              moments[k + 3] = __builtin_shufflevector(b01, b23, 2, 3, 6, 7);
            }
            tables_.derivatives4(R, derivative.data());
            for (int m = 0; m < count; ++m) {
              V4 sum = accumulated[m];
              for (int j = tables_.m2l_offset[m]; j < tables_.m2l_offset[m + 1]; ++j)
                sum += moments[tables_.m2l_k[j]] * derivative[tables_.m2l_mk[j]];
              accumulated[m] = sum;
            }
          }
          double* L = local(a);
          for (int m = 0; m < count; ++m)
            L[m] += (accumulated[m][0] + accumulated[m][1]) + (accumulated[m][2] + accumulated[m][3]);
        }
        m2l_total += static_cast<Index>(m2l_lists_[a].size());
        if (time_kernels_) m2l_seconds += seconds_since(m2l_start);
        if (!A.leaf() || p2p_lists_[a].empty()) continue;
        const auto p2p_start = time_kernels_ ? WallClock::now() : WallClock::time_point{};
        ranges.clear(), exact_ranges.clear();
        Index sources = 0;
        int self_range = -1;
        int32_t last_frame = -1;
        for (int32_t b : p2p_lists_[a]) {
          const Cell& B = cells_[b];
          const int32_t frame = frame_cell(b);
          if (frame == last_frame && ranges.back().end == B.begin) {  // a following sibling: one longer range
            ranges.back().end = B.end;
          } else {
            const Cell& F = cells_[frame];
            ranges.push_back({{F.center[0], F.center[1], F.center[2]},
                              B.begin,
                              B.end,
                              coulomb_detail::frame_close_h(F.radius)});
            last_frame = frame;
          }
          if (b == static_cast<int32_t>(a)) self_range = static_cast<int>(ranges.size()) - 1;
          exact_ranges.push_back({B.begin, B.end});
          sources += B.size();
        }
        p2p_total += sources * A.size();
        if (!framed_near_field_) {
          const FloatPoints points{xf_.data(), yf_.data(), zf_.data(), xl_.data(), yl_.data(), zl_.data()};
          for (int32_t i0 = A.begin; i0 < A.end; i0 += kBlock)
            coulomb_detail::p2p_block(points, i0, std::min<int32_t>(kBlock, A.end - i0), exact_ranges.data(),
                                      static_cast<int>(exact_ranges.size()), norm_.floor2, potential_.data(),
                                      fx_.data(), fy_.data(), fz_.data());
        } else {
          for (int32_t i0 = A.begin; i0 < A.end; i0 += kBlock)
            coulomb_detail::p2p_framed_block(
                xd_.data(), yd_.data(), zd_.data(), i0, std::min<int32_t>(kBlock, A.end - i0), ranges.data(),
                static_cast<int>(ranges.size()), self_range, xs_.data(), ys_.data(), zs_.data(), norm_.floor2,
                potential_.data(), fx_.data(), fy_.data(), fz_.data());
        }
        if (time_kernels_) p2p_seconds += seconds_since(p2p_start);
      }
    }
    stats_.seconds_m2l = m2l_seconds;
    stats_.seconds_p2p = p2p_seconds;
    stats_.m2l_interactions = m2l_total;
    stats_.p2p_interactions = p2p_total;
  }

  void downward_pass() {
    const int count = tables_.count;
    // L2L, parents before children: L_a += Σ_{m≥a} L^parent_m t^{m−a}/(m−a)!, t = z − z_parent
    std::vector<double> mono(count);
    const StaticShiftFunction fixed_l2l = static_l2l(tables_.order);
    for (size_t c = 1; c < cells_.size(); ++c) {
      const Cell& cell = cells_[c];
      const Cell& parent = cells_[cell.parent];
      const double t3[3] = {cell.center[0] - parent.center[0], cell.center[1] - parent.center[1],
                            cell.center[2] - parent.center[2]};
      const double* Lp = local(cell.parent);
      double* L = local(c);
      if (fixed_l2l) {
        fixed_l2l(t3, Lp, L);
        continue;
      }
      tables_.monomials(t3, mono.data());
      for (const auto& t : tables_.shift) L[t[1]] += Lp[t[0]] * mono[t[2]];
    }
    // L2P: φ(x) += Σ_m L_m e^m/m!, ∇φ(x) += Σ_n L_{n+e_i} e^n/n!, e = x − z; force f = −∇φ
    const StaticL2PFunction fixed_l2p = static_l2p(tables_.order);
#pragma omp parallel
    {
      std::vector<double> mono_point(count);
#pragma omp for schedule(dynamic, 16)
      for (size_t l = 0; l < leaves_.size(); ++l) {
        const Cell& cell = cells_[leaves_[l]];
        const double* L = local(leaves_[l]);
        if (fixed_l2p) {
          fixed_l2p(xd_.data(), yd_.data(), zd_.data(), cell.begin, cell.end, cell.center, L,
                    potential_.data(), fx_.data(), fy_.data(), fz_.data());
          continue;
        }
        for (int32_t i = cell.begin; i < cell.end; ++i) {
          const double e[3] = {xd_[i] - cell.center[0], yd_[i] - cell.center[1], zd_[i] - cell.center[2]};
          tables_.monomials(e, mono_point.data());
          double phi = 0;
          for (int m = 0; m < count; ++m) phi += L[m] * mono_point[m];
          double g[3] = {0, 0, 0};
          for (int k = 0; k < 3; ++k)
            for (const auto& t : tables_.gradient[k]) g[k] += L[t[1]] * mono_point[t[0]];
          potential_[i] += phi;
          fx_[i] -= g[0], fy_[i] -= g[1], fz_[i] -= g[2];
        }
      }
    }
  }

  CoulombEvaluation gather(bool want_potentials) {
    CoulombEvaluation result;
    result.summation_used = CoulombOptions::Summation::Fast;
    result.gradient.resize(n_, 3);
    if (want_potentials) result.potential.resize(n_);
    const double gradient_scale = -2 / (norm_.scale * norm_.scale);
    double energy = 0;
    for (Index s = 0; s < n_; ++s) energy += potential_[s];  // in Morton order, as always
#pragma omp parallel for schedule(static)
    for (Index s = 0; s < n_; ++s) {
      const Index i = order_[s];
      result.gradient(i, 0) = gradient_scale * fx_[s];
      result.gradient(i, 1) = gradient_scale * fy_[s];
      result.gradient(i, 2) = gradient_scale * fz_[s];
      if (want_potentials) result.potential[i] = potential_[s] / norm_.scale;
    }
    result.energy = energy / norm_.scale;
    return result;
  }

  const Points& X_;
  const Index n_;
  const MultiIndexTables& tables_;
  const int stride_;  // doubles per cell's expansion: count rounded up to a multiple of 4
  const std::vector<double> zero_moments_;  // the moments of an empty M2L lane
  const double theta_;
  const double theta2_ = theta_ * theta_;
  const int leaf_size_;
  const bool framed_near_field_;
  CoulombFmmStats& stats_;
  const bool time_kernels_;
  coulomb_detail::NormalizedPoints norm_;
  std::vector<int32_t> order_;  // sorted position s holds input point order_[s]
  std::vector<uint64_t> keys_;
  std::vector<double> xd_, yd_, zd_;
  std::vector<float> xs_, ys_, zs_;  // framed near field: float coordinates in each point's leaf frame
  std::vector<float> xf_, yf_, zf_, xl_, yl_, zl_;  // otherwise: float high and low parts (coulomb_p2p.h)
  std::vector<Cell> cells_;
  std::vector<int32_t> leaves_;
  std::vector<int32_t> depth_start_;  // cells of depth d: [depth_start_[d], depth_start_[d+1])
  std::vector<double> multipoles_, locals_;
  // Indexed by cell; only the first cells_.size() are this evaluation's (see run()).
  std::vector<std::vector<int32_t>>& m2l_lists_ = list_store().m2l;
  std::vector<std::vector<int32_t>>& p2p_lists_ = list_store().p2p;
  std::vector<std::vector<int32_t>> deferred_;  // traverse_parallel's deferred pairs, by target
  int32_t deferred_cut_ = 0;
  bool deferring_ = false;
  std::vector<double> potential_, fx_, fy_, fz_;
};

}  // namespace

CoulombEvaluation coulomb_fmm(const Points& X, const CoulombFmmOptions& options, CoulombFmmStats* stats) {
  const FmmParameters parameters = choose_parameters(options);
  CoulombFmmStats local_stats;
  CoulombFmmStats& s = stats ? *stats : local_stats;
  s = CoulombFmmStats{};
  s.order = parameters.order;
  s.opening_angle = parameters.opening_angle;
  s.leaf_size = parameters.leaf_size;
  CSHAPES_REQUIRE(X.allFinite(), "Coulomb FMM: the ", X.rows(), " points contain a non-finite coordinate");
  CSHAPES_REQUIRE(X.rows() < (Index(1) << 31) - kBlock, "Coulomb FMM: too many points (", X.rows(), ")");
  if (X.rows() == 0) {
    CoulombEvaluation empty;
    empty.summation_used = CoulombOptions::Summation::Fast;
    empty.gradient.resize(0, 3);
    if (options.want_potentials) empty.potential.resize(0);
    return empty;
  }
  Fmm fmm(X, parameters, options.min_distance, s, stats != nullptr);
  return fmm.run(options.want_potentials);
}

}  // namespace cshapes
