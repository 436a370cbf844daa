#include "eval/correspondence_error.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <map>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/geodesics.h"

namespace cshapes {

std::vector<int> read_vts(const std::string& path, Index num_vertices) {
  std::istringstream in(read_file(path));
  std::vector<int> indices;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    std::istringstream fields(line);
    std::string first;
    if (!(fields >> first)) continue;  // blank line
    char* end = nullptr;
    long value = std::strtol(first.c_str(), &end, 10);
    CSHAPES_REQUIRE(end && *end == '\0', path, ":", number, ": '", first, "' is not a vertex index");
    CSHAPES_REQUIRE(value >= 1, path, ":", number, ": vertex index ", value, " (expected 1-based, >= 1)");
    CSHAPES_REQUIRE(num_vertices <= 0 || value <= num_vertices, path, ":", number, ": vertex index ", value,
                    " exceeds the mesh's ", num_vertices, " vertices");
    indices.push_back(static_cast<int>(value - 1));
  }
  CSHAPES_REQUIRE(!indices.empty(), path, ": no vertex index");
  return indices;
}

CorrespondenceErrorResult correspondence_error(const Mesh& b, const Eigen::VectorXi& map_a_to_b,
                                               const std::vector<int>& truth_a,
                                               const std::vector<int>& truth_b,
                                               const CorrespondenceErrorOptions& options,
                                               const DistanceMatrix* geodesics_b) {
  const Index nb = b.num_vertices();
  CSHAPES_REQUIRE(truth_a.size() == truth_b.size() && !truth_a.empty(),
                  "correspondence error: ", truth_a.size(), " and ", truth_b.size(),
                  " ground-truth samples (expected equal, non-zero counts)");
  CSHAPES_REQUIRE(options.curve_points >= 2 && options.max_threshold > 0,
                  "correspondence error: need curve_points >= 2 and max_threshold > 0");
  CSHAPES_REQUIRE(!geodesics_b || (geodesics_b->rows() == nb && geodesics_b->cols() == nb),
                  "correspondence error: the geodesic matrix is ", geodesics_b ? geodesics_b->rows() : 0, "x",
                  geodesics_b ? geodesics_b->cols() : 0, ", B has ", nb, " vertices");

  CorrespondenceErrorResult result;
  const int total = static_cast<int>(truth_a.size());
  const int used = options.max_samples > 0 ? std::min(options.max_samples, total) : total;
  for (int k = 0; k < used; ++k)
    result.samples.push_back(static_cast<int>(static_cast<long>(k) * total / used));

  // Per sample: the mapped vertex and the true vertex of B.
  std::vector<int> mapped(static_cast<size_t>(used)), truth(static_cast<size_t>(used));
  for (int k = 0; k < used; ++k) {
    int s = result.samples[static_cast<size_t>(k)];
    int va = truth_a[static_cast<size_t>(s)], vb = truth_b[static_cast<size_t>(s)];
    CSHAPES_REQUIRE(va >= 0 && va < map_a_to_b.size(), "correspondence error: sample ", s, " is vertex ", va,
                    " of A, but the map covers ", map_a_to_b.size(), " vertices");
    CSHAPES_REQUIRE(vb >= 0 && vb < nb, "correspondence error: sample ", s, " is vertex ", vb,
                    " of B, which has ", nb, " vertices");
    int m = map_a_to_b[va];
    CSHAPES_REQUIRE(m >= 0 && m < nb, "correspondence error: the map sends vertex ", va, " of A to ", m,
                    ", not a vertex of B");
    mapped[static_cast<size_t>(k)] = m;
    truth[static_cast<size_t>(k)] = vb;
  }

  result.normaliser = options.normalise ? std::sqrt(surface_area(b.V, b.F)) : 1.0;
  CSHAPES_REQUIRE(result.normaliser > 0, "correspondence error: B has zero area");
  result.errors.resize(used);
  if (geodesics_b) {
    for (int k = 0; k < used; ++k)
      result.errors[k] = (*geodesics_b)(truth[static_cast<size_t>(k)], mapped[static_cast<size_t>(k)]);
  } else {
    // One Dijkstra per distinct true vertex, serving every sample that shares it.
    std::map<int, std::vector<int>> by_truth;
    for (int k = 0; k < used; ++k) by_truth[truth[static_cast<size_t>(k)]].push_back(k);
    std::vector<std::pair<int, std::vector<int>>> groups(by_truth.begin(), by_truth.end());
    std::exception_ptr error;
#pragma omp parallel for schedule(dynamic, 8)
    for (long g = 0; g < static_cast<long>(groups.size()); ++g) {
      try {
        Eigen::VectorXd d = geodesic_distances(b, {groups[static_cast<size_t>(g)].first}, options.geodesics);
        for (int k : groups[static_cast<size_t>(g)].second)
          result.errors[k] = d[mapped[static_cast<size_t>(k)]];
      } catch (...) {
#pragma omp critical(cshapes_correspondence_error)
        if (!error) error = std::current_exception();
      }
    }
    if (error) std::rethrow_exception(error);
  }
  result.errors /= result.normaliser;

  result.thresholds = Eigen::VectorXd::LinSpaced(options.curve_points, 0.0, options.max_threshold);
  std::vector<double> sorted(result.errors.data(), result.errors.data() + used);
  std::sort(sorted.begin(), sorted.end());
  result.fraction.resize(options.curve_points);
  for (int t = 0; t < options.curve_points; ++t) {
    auto within = std::upper_bound(sorted.begin(), sorted.end(), result.thresholds[t]) - sorted.begin();
    result.fraction[t] = static_cast<double>(within) / used;
  }
  result.mean_error = result.errors.mean();
  result.median_error =
      used % 2 ? sorted[static_cast<size_t>(used / 2)]
               : 0.5 * (sorted[static_cast<size_t>(used / 2 - 1)] + sorted[static_cast<size_t>(used / 2)]);
  return result;
}

}  // namespace cshapes
