#include "cshapes/canon/form_quality.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <unordered_set>

#include "cshapes/support/error.h"
#include "cshapes/mesh/mesh.h"

namespace cshapes {

namespace {

double coordinate_median(const Points& X, int column) {
  std::vector<double> v;
  v.reserve(X.rows());
  for (Index i = 0; i < X.rows(); ++i)
    if (std::isfinite(X(i, column))) v.push_back(X(i, column));
  if (v.empty()) return 0;
  auto mid = v.begin() + v.size() / 2;
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

std::string format(const char* pattern, double a, double b, double c) {
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, pattern, a, b, c);
  return buffer;
}

// The stretch statistics of q from the kept edges' stretches (reordered) and their sum.
void summarise_stretch(std::vector<double>& stretch, double sum, FormQuality& q) {
  q.edges_measured = static_cast<Index>(stretch.size());
  if (stretch.empty()) return;
  q.mean_stretch = sum / static_cast<double>(stretch.size());
  // A NaN stretch (non-finite coordinates) makes the max NaN; nth_element ranks NaN arbitrarily.
  q.max_stretch = q.min_stretch = stretch.front();
  bool any_nan = false;
  for (double s : stretch) {
    any_nan = any_nan || std::isnan(s);
    q.max_stretch = std::max(q.max_stretch, s);
    q.min_stretch = std::min(q.min_stretch, s);
  }
  if (any_nan) q.max_stretch = std::nan("");
  const size_t rank = static_cast<size_t>(std::ceil(0.99 * static_cast<double>(stretch.size()))) - 1;
  std::nth_element(stretch.begin(), stretch.begin() + static_cast<std::ptrdiff_t>(rank), stretch.end());
  q.p99_stretch = stretch[rank];
}

// Detached parts: within each component of the input graph, every component of the kept (untorn) edges but
// the largest (ties: the lowest label) is marked.
void mark_detached(Index n, const Edges& E, const std::vector<bool>& torn, std::vector<char>& detached) {
  Index kept_count = 0;
  for (Index e = 0; e < E.rows(); ++e) kept_count += torn[e] ? 0 : 1;
  Edges kept(kept_count, 2);
  for (Index e = 0, k = 0; e < E.rows(); ++e)
    if (!torn[e]) kept.row(k++) = E.row(e);
  const Components whole = connected_components(n, E), parts = connected_components(n, kept);
  if (parts.count <= whole.count) return;
  std::vector<int> main_part(whole.count, -1);  // per input component: its largest kept component
  for (Index i = 0; i < n; ++i) {
    int& best = main_part[whole.label[i]];
    const int p = parts.label[i];
    if (best < 0 || parts.sizes[p] > parts.sizes[best] || (parts.sizes[p] == parts.sizes[best] && p < best))
      best = p;
  }
  for (Index i = 0; i < n; ++i) detached[i] = parts.label[i] != main_part[whole.label[i]];
}

// The one-line description: "ok: ..." or "NOT OK: <the runaway vertices>; ...", then the stretch figures.
std::string describe(const FormQuality& q, bool finite) {
  const std::string stretch =
      format("edge stretch (form length / input length) max %.3g, p99 %.3g, mean %.3g", q.max_stretch,
             q.p99_stretch, q.mean_stretch);
  if (q.ok) return "ok: " + stretch;
  std::string what = std::to_string(q.runaway_vertices) + " runaway vertices (" + std::to_string(q.far_vertices) +
                     " far, " + std::to_string(q.stretched_vertices) + " on overstretched edges, " +
                     std::to_string(q.detached_vertices) + " detached, " + std::to_string(q.coincident_vertices) +
                     " coincident with a neighbour";
  if (!finite) what += ", non-finite coordinates";
  what += format("; farthest %.3g bbox diagonals from the median", q.max_distance, 0, 0);
  if (!q.runaway_examples.empty()) what += "; first vertex " + std::to_string(q.runaway_examples.front());
  return "NOT OK: " + what + "); " + stretch;
}

}  // namespace

void fail_form_quality(FormQuality& quality, const std::string& reason) {
  quality.ok = false;
  std::string rest = quality.description;
  for (const char* prefix : {"ok: ", "NOT OK: "})
    if (rest.rfind(prefix, 0) == 0) rest = rest.substr(std::string(prefix).size());
  quality.description = "NOT OK: " + reason + "; " + rest;
}

std::vector<bool> torn_edge_flags(const Edges& E, const Edges& torn) {
  std::unordered_set<std::uint64_t> keys;
  auto key = [](int i, int j) {
    return (static_cast<std::uint64_t>(std::min(i, j)) << 32) | static_cast<std::uint32_t>(std::max(i, j));
  };
  for (Index e = 0; e < torn.rows(); ++e) keys.insert(key(torn(e, 0), torn(e, 1)));
  std::vector<bool> flags(E.rows(), false);
  for (Index e = 0; e < E.rows(); ++e) flags[e] = keys.count(key(E(e, 0), E(e, 1))) > 0;
  return flags;
}

FormQuality form_quality(const Points& input_V, const Edges& E, const Points& X,
                         const std::vector<bool>* torn_edges, const FormQualityOptions& options) {
  const Index n = input_V.rows();
  CSHAPES_REQUIRE(X.rows() == n, "form quality: the form has ", X.rows(), " vertices, the input ", n);
  CSHAPES_REQUIRE(!torn_edges || static_cast<Index>(torn_edges->size()) == E.rows(),
                  "form quality: ", torn_edges ? torn_edges->size() : 0, " torn flags for ", E.rows(),
                  " edges");
  CSHAPES_REQUIRE(options.far_diagonals > 0 && options.overstretch > 0 && options.listed >= 0,
                  "form quality: far_diagonals and overstretch must be > 0 and listed >= 0");
  for (Index e = 0; e < E.rows(); ++e)
    CSHAPES_REQUIRE(E(e, 0) >= 0 && E(e, 0) < n && E(e, 1) >= 0 && E(e, 1) < n, "form quality: edge ", e,
                    " (", E(e, 0), ", ", E(e, 1), ") is out of range for ", n, " vertices");
  FormQuality q;
  if (n == 0) {
    q.description = "ok: empty form";
    return q;
  }
  auto torn = [&](Index e) { return torn_edges && (*torn_edges)[e]; };
  std::vector<char> far(n, 0), stretched(n, 0), detached(n, 0), coincident(n, 0);
  const double coincident_length = options.coincident_fraction * finite_bbox_diagonal(X);

  // Stretches over the kept edges.
  const Eigen::VectorXd input_lengths = edge_lengths(input_V, E);
  const double mean_length = E.rows() ? input_lengths.mean() : 0;
  std::vector<double> stretch;
  stretch.reserve(E.rows());
  double sum = 0;
  for (Index e = 0; e < E.rows(); ++e) {
    if (torn(e)) continue;
    const int i = E(e, 0), j = E(e, 1);
    const double length = (X.row(i) - X.row(j)).norm();
    const double limit = options.overstretch * std::max(input_lengths(e), mean_length);
    if (!(length <= limit)) {  // NaN counts as over the limit
      ++q.overstretched_edges;
      stretched[i] = stretched[j] = 1;
    }
    if (input_lengths(e) <= 0) continue;
    if (length <= coincident_length) coincident[i] = coincident[j] = 1;
    const double s = length / input_lengths(e);
    stretch.push_back(s);
    sum += s;
  }
  summarise_stretch(stretch, sum, q);

  // Distance from the form's coordinate-wise median, in input bbox diagonals.
  const double diagonal = std::max(bbox_diagonal(input_V), 1e-300);
  const Eigen::RowVector3d median(coordinate_median(X, 0), coordinate_median(X, 1), coordinate_median(X, 2));
  for (Index i = 0; i < n; ++i) {
    const double d = (X.row(i) - median).norm() / diagonal;
    if (!(d <= options.far_diagonals)) far[i] = 1;
    if (!(d <= q.max_distance)) q.max_distance = d;
  }

  if (torn_edges) mark_detached(n, E, *torn_edges, detached);

  bool finite = X.allFinite();
  for (Index i = 0; i < n; ++i) {
    q.far_vertices += far[i];
    q.stretched_vertices += stretched[i];
    q.detached_vertices += detached[i];
    q.coincident_vertices += coincident[i];
    if (far[i] || stretched[i] || detached[i] || coincident[i]) {
      if (static_cast<int>(q.runaway_examples.size()) < options.listed) q.runaway_examples.push_back(i);
      ++q.runaway_vertices;
    }
  }
  q.ok = q.runaway_vertices == 0 && finite;
  q.description = describe(q, finite);
  return q;
}

}  // namespace cshapes
