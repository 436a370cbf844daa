#include "cshapes/canon/coulomb_fmm_expansions.h"

#include <algorithm>
#include <memory>
#include <mutex>

#include "cshapes/support/error.h"
#include "cshapes/support/simd.h"

namespace cshapes::fmm_detail {

MultiIndexTables::MultiIndexTables(int p) : order(p) {
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

namespace {

// The compile-time tables of the M2L of order P (canon/coulomb_m2l_simd.inl), so that its fully unrolled
// loops address registers and fixed offsets instead of loading indices (faster than the table-driven loop of
// MultiIndexTables: docs/coulomb-defaults.md, "The fast sum's parameters"). Same multi-index order as
// MultiIndexTables.
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

// P2M and L2P of one leaf with compile-time tables (unrolled, like StaticM2L, and faster for it than the
// table loops of MultiIndexTables). Same multi-index order and the same formulas as the table-driven passes.
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

}  // namespace

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

// Internal linkage, as every kernel compiled for an instruction set (docs/design.md, "Kernels per
// instruction set").
namespace {
#pragma GCC push_options
#pragma GCC target("avx2,fma")
namespace avx2 {
#include "cshapes/canon/coulomb_m2l_simd.inl"
}  // namespace avx2
#pragma GCC pop_options
#pragma GCC push_options
#pragma GCC target("avx2,fma,avx512f,avx512vl,avx512dq,avx512bw")
namespace avx512 {
#include "cshapes/canon/coulomb_m2l_simd.inl"
}  // namespace avx512
#pragma GCC pop_options
namespace baseline {
#include "cshapes/canon/coulomb_m2l_simd.inl"
}  // namespace baseline
}  // namespace

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

// The tables of each order, built on first use and shared (read-only) by every later evaluation.
const MultiIndexTables& tables_of_order(int order) {
  static std::array<std::once_flag, 17> once;
  static std::array<std::unique_ptr<const MultiIndexTables>, 17> tables;
  std::call_once(once[order], [&] { tables[order] = std::make_unique<const MultiIndexTables>(order); });
  return *tables[order];
}

// The accuracy → (order, θ, leaf size) table. Each row is the cheapest setting whose worst relative L2
// error of the gradient against exact direct summation (`cshapes bench coulomb`) kept a margin below the
// row's accuracy, over synthetic sets (points in a uniform cube, on a sphere, in clusters, on a mesh's
// surface; smaller sets can be worse than large ones) and over the vertices of real meshes, which are harder
// (regular spacing, a gradient that largely cancels). Regular grids' vertices, checked at large n after the
// table was chosen, show that a larger θ for large n is not safe. The float near field limits the
// attainable error: requests below the last row get the last row; use Summation::Direct for more. The
// energy's error is smaller than the gradient's. (The measurements, their commands and the margins:
// docs/coulomb-defaults.md, "The fast sum's parameters".)
constexpr FmmParameters kParameterTable[] = {
    {1e-2, 3, 0.6, 48},  {3e-3, 4, 0.6, 48}, {1e-3, 4, 0.45, 48}, {3e-4, 5, 0.45, 96},
    {1e-4, 6, 0.45, 96}, {3e-5, 7, 0.4, 96}, {1e-5, 8, 0.35, 96}, {3e-6, 10, 0.35, 96},
};

// The near field in local frames (coulomb_p2p.h, p2p_framed_block) is faster than the exact-difference kernel
// (p2p_block) but rounds each difference to ~1e-7 of the frame's size (a leaf's parent) rather than of the
// difference: where the near forces cancel, that adds a relative gradient error harmless at 1e-3 but not at
// 1e-5 (the measurements: docs/coulomb-defaults.md, "The fast sum's parameters"). Requests below this, and
// orders above 5 (which only pay off below it), use the exact-difference kernel.
constexpr double kFramedNearFieldMinAccuracy = 3e-4;

// The framed near field takes the hardware's 12-bit estimate of 1/r as it is, without the Newton step (4 of
// its 24 operations per pair), for requests of at least this. Each pair term is then off by up to 1.5·2⁻¹²
// (3.7e-4) relative, and the errors partly cancel over a leaf's sources: at 1e-3 the gradient's error grows
// but keeps the margin the table's rule asks, and at 1e-2 (the canonization's default) it barely moves (the
// measurements: docs/coulomb-defaults.md, "The fast sum's parameters"). Below it the step stays: at 3e-4 the
// frames' own rounding (above) already takes a good part of the error budget.
constexpr double kUnrefinedMinAccuracy = 1e-3;

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
  chosen.refined_estimate = options.accuracy < kUnrefinedMinAccuracy;
  if (options.opening_angle > 0) chosen.opening_angle = options.opening_angle;
  if (options.leaf_size > 0) chosen.leaf_size = options.leaf_size;
  CSHAPES_REQUIRE(chosen.order >= 1 && chosen.order <= 16, "Coulomb FMM: order must be in [1, 16], got ",
                  chosen.order);
  CSHAPES_REQUIRE(chosen.opening_angle > 0 && chosen.opening_angle < 1,
                  "Coulomb FMM: opening angle must be in (0, 1), got ", chosen.opening_angle);
  return chosen;
}

ListStore& list_store() {
  thread_local ListStore store;
  return store;
}

Workspace& workspace() {
  thread_local Workspace w;
  return w;
}

void p2m_cell(const MultiIndexTables& t, const Cell& cell, const double* x, const double* y, const double* z,
              double* M, double* mono) {
  if (const StaticP2MFunction fixed = static_p2m(t.order)) {
    fixed(x, y, z, cell.begin, cell.end, cell.center, M);
    return;
  }
  for (int32_t i = cell.begin; i < cell.end; ++i) {
    const double d3[3] = {x[i] - cell.center[0], y[i] - cell.center[1], z[i] - cell.center[2]};
    t.monomials(d3, mono);
    for (int k = 0; k < t.count; ++k) M[k] += mono[k];
  }
}

void m2m_shift(const MultiIndexTables& t, const double s[3], const double* child, double* M, double* mono) {
  if (const StaticShiftFunction fixed = static_m2m(t.order)) {
    fixed(s, child, M);
    return;
  }
  t.monomials(s, mono);
  for (const auto& e : t.shift) M[e[0]] += child[e[1]] * mono[e[2]];
}

void l2l_shift(const MultiIndexTables& t, const double s[3], const double* parent, double* L, double* mono) {
  if (const StaticShiftFunction fixed = static_l2l(t.order)) {
    fixed(s, parent, L);
    return;
  }
  t.monomials(s, mono);
  for (const auto& e : t.shift) L[e[1]] += parent[e[0]] * mono[e[2]];
}

void l2p_cell(const MultiIndexTables& t, const Cell& cell, const double* x, const double* y, const double* z,
              const double* L, double* potential, double* fx, double* fy, double* fz, double* mono) {
  if (const StaticL2PFunction fixed = static_l2p(t.order)) {
    fixed(x, y, z, cell.begin, cell.end, cell.center, L, potential, fx, fy, fz);
    return;
  }
  for (int32_t i = cell.begin; i < cell.end; ++i) {
    const double e[3] = {x[i] - cell.center[0], y[i] - cell.center[1], z[i] - cell.center[2]};
    t.monomials(e, mono);
    double phi = 0;
    for (int m = 0; m < t.count; ++m) phi += L[m] * mono[m];
    double g[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k)
      for (const auto& n : t.gradient[k]) g[k] += L[n[1]] * mono[n[0]];
    potential[i] += phi;
    fx[i] -= g[0], fy[i] -= g[1], fz[i] -= g[2];
  }
}

void m2l_table_driven(const MultiIndexTables& t, const double center[3], const std::vector<int32_t>& list,
                      const Cell* cells, const double* multipoles, int stride, const double* zero_moments,
                      std::vector<V4>& derivative, std::vector<V4>& moments, std::vector<V4>& accumulated,
                      double* L) {
  std::fill(accumulated.begin(), accumulated.end(), V4{0, 0, 0, 0});
  for (size_t g = 0; g < list.size(); g += 4) {
    V4 R[3];
    const double* M[4];
    for (int l = 0; l < 4; ++l) {
      if (g + l < list.size()) {
        const Cell& B = cells[list[g + l]];
        for (int c = 0; c < 3; ++c) R[c][l] = center[c] - B.center[c];
        M[l] = multipoles + static_cast<size_t>(list[g + l]) * static_cast<size_t>(stride);
      } else {  // an empty lane: a harmless separation and no charge
        R[0][l] = 1, R[1][l] = 0, R[2][l] = 0;
        M[l] = zero_moments;
      }
    }
    // moments[k][l] = M[l][k]: 4×4 transposes of the rows (stride is a multiple of 4).
    for (int k = 0; k < stride; k += 4) {
      const V4 r0 = *reinterpret_cast<const UnalignedV4*>(M[0] + k),
               r1 = *reinterpret_cast<const UnalignedV4*>(M[1] + k),
               r2 = *reinterpret_cast<const UnalignedV4*>(M[2] + k),
               r3 = *reinterpret_cast<const UnalignedV4*>(M[3] + k);
      const V4 a01 = __builtin_shufflevector(r0, r1, 0, 4, 2, 6), b01 = __builtin_shufflevector(r0, r1, 1, 5, 3, 7),
               a23 = __builtin_shufflevector(r2, r3, 0, 4, 2, 6), b23 = __builtin_shufflevector(r2, r3, 1, 5, 3, 7);
      moments[k] = __builtin_shufflevector(a01, a23, 0, 1, 4, 5);
      moments[k + 1] = __builtin_shufflevector(b01, b23, 0, 1, 4, 5);
      moments[k + 2] = __builtin_shufflevector(a01, a23, 2, 3, 6, 7);
      moments[k + 3] = __builtin_shufflevector(b01, b23, 2, 3, 6, 7);
    }
    t.derivatives4(R, derivative.data());
    for (int m = 0; m < t.count; ++m) {
      V4 sum = accumulated[m];
      for (int j = t.m2l_offset[m]; j < t.m2l_offset[m + 1]; ++j)
        sum += moments[t.m2l_k[j]] * derivative[t.m2l_mk[j]];
      accumulated[m] = sum;
    }
  }
  for (int m = 0; m < t.count; ++m)
    L[m] += (accumulated[m][0] + accumulated[m][1]) + (accumulated[m][2] + accumulated[m][3]);
}

}  // namespace cshapes::fmm_detail
