#include "cshapes/eval/correspondence_error.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <limits>
#include <map>
#include <memory>
#include <sstream>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/geodesics/fast_marching.h"
#include "cshapes/geodesics/geodesics.h"
#include "cshapes/mesh/mesh_repair.h"

namespace cshapes {

std::vector<int> read_vts(const std::string& path, Index num_vertices) {
  std::istringstream in(read_text_file(path));
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
  result.median_error = error_median(result.errors);
  return result;
}

CorrespondencePairs read_correspondence_pairs(const std::string& path, Index a_vertices, Index b_vertices) {
  std::istringstream in(read_text_file(path));
  CorrespondencePairs pairs;
  std::map<long, int> line_of;  // vertex of A -> the line that listed it
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    std::istringstream fields(line);
    std::vector<std::string> tokens;
    for (std::string t; fields >> t;) tokens.push_back(t);
    if (tokens.empty()) continue;  // blank line
    CSHAPES_REQUIRE(tokens.size() == 2, path, ":", number, ": expected two 1-based vertex indices, got ",
                    tokens.size(), " field", tokens.size() == 1 ? "" : "s", " ('", line, "')");
    long value[2];
    for (int c = 0; c < 2; ++c) {
      char* end = nullptr;
      errno = 0;
      value[c] = std::strtol(tokens[static_cast<size_t>(c)].c_str(), &end, 10);
      CSHAPES_REQUIRE(end && *end == '\0' && errno == 0, path, ":", number, ": '",
                      tokens[static_cast<size_t>(c)], "' is not a vertex index");
      CSHAPES_REQUIRE(value[c] >= 1, path, ":", number, ": vertex index ", value[c],
                      " (expected 1-based, >= 1)");
      const Index limit = c == 0 ? a_vertices : b_vertices;
      CSHAPES_REQUIRE(limit <= 0 || value[c] <= limit, path, ":", number, ": vertex index ", value[c],
                      " exceeds the ", c == 0 ? "query" : "reference", " mesh's ", limit, " vertices");
    }
    auto [it, inserted] = line_of.emplace(value[0], number);
    CSHAPES_REQUIRE(inserted, path, ":", number, ": vertex ", value[0], " is listed again (first on line ",
                    it->second, ")");
    pairs.from.push_back(static_cast<int>(value[0] - 1));
    pairs.to.push_back(static_cast<int>(value[1] - 1));
  }
  CSHAPES_REQUIRE(!pairs.from.empty(), path, ": no vertex pair");
  return pairs;
}

namespace {

// The cumulative curve, mean and median of result.errors (+inf entries count in the curve's denominator and
// the median, not in the mean).
void summarise_errors(CorrespondenceErrorResult& result, const CorrespondenceErrorOptions& options) {
  const Index used = result.errors.size();
  result.thresholds = Eigen::VectorXd::LinSpaced(options.curve_points, 0.0, options.max_threshold);
  std::vector<double> sorted(result.errors.data(), result.errors.data() + used);
  std::sort(sorted.begin(), sorted.end());
  result.fraction = Eigen::VectorXd::Zero(options.curve_points);
  for (int t = 0; used > 0 && t < options.curve_points; ++t) {
    auto within = std::upper_bound(sorted.begin(), sorted.end(), result.thresholds[t]) - sorted.begin();
    result.fraction[t] = static_cast<double>(within) / static_cast<double>(used);
  }
  result.mean_error = finite_mean(result.errors);
  result.median_error = error_median(result.errors);
}

}  // namespace

namespace {

// The samples scored: evenly spaced over the list, those whose true vertex is on the repaired mesh kept (the
// others counted in *skipped); every index checked.
std::vector<int> kept_samples(Index nb, const std::vector<int>& truth_b, const std::vector<int>& symmetric_b,
                              const RepairedMesh& repaired, const CorrespondenceErrorOptions& options,
                              const std::string& b_name, int* skipped) {
  const int total = static_cast<int>(truth_b.size());
  const int wanted = options.max_samples > 0 ? std::min(options.max_samples, total) : total;
  std::vector<int> kept;
  for (int k = 0; k < wanted; ++k) {
    const int s = static_cast<int>(static_cast<long>(k) * total / wanted);
    const size_t u = static_cast<size_t>(s);
    CSHAPES_REQUIRE(truth_b[u] >= 0 && truth_b[u] < nb, "correspondence error: sample ", s, " is vertex ",
                    truth_b[u], " of ", b_name, ", which has ", nb, " vertices");
    CSHAPES_REQUIRE(symmetric_b.empty() || (symmetric_b[u] >= -1 && symmetric_b[u] < nb),
                    "correspondence error: the mirrored truth of sample ", s, " is vertex ", symmetric_b[u],
                    " of ", b_name, ", which has ", nb, " vertices");
    if (repaired_copies(repaired.vertex_map, truth_b[u]).empty()) {
      ++*skipped;
      continue;
    }
    kept.push_back(s);
  }
  CSHAPES_REQUIRE(!kept.empty(),
                  "correspondence error: every sample's true vertex was dropped by the repair of ", b_name,
                  " (", repaired.text, ")");
  return kept;
}

void check_maps(const std::vector<Eigen::VectorXi>& maps, const std::vector<int>& kept,
                const std::vector<int>& truth_a, Index nb, const std::string& b_name) {
  for (size_t i = 0; i < maps.size(); ++i) {
    for (int s : kept) {
      const int va = truth_a[static_cast<size_t>(s)];
      CSHAPES_REQUIRE(va >= 0 && va < maps[i].size(), "correspondence error: sample ", s, " is vertex ", va,
                      " of A, but map ", i, " covers ", maps[i].size(), " vertices");
      const int m = maps[i][va];
      CSHAPES_REQUIRE(m >= -1 && m < nb, "correspondence error: map ", i, " sends vertex ", va, " of A to ",
                      m, ", not a vertex of ", b_name);
    }
  }
}

// distance[i](k, 0 / 1): the geodesic distance on B from map i's image of kept sample k to its true / mirrored
// vertex (+inf: none). One geodesic field per distinct true or mirrored vertex (a mirrored one the repair
// dropped is not used), OpenMP over them.
std::vector<Eigen::MatrixX2d> image_distances(const std::vector<Eigen::VectorXi>& maps,
                                              const std::vector<int>& kept, const std::vector<int>& truth_a,
                                              const std::vector<int>& truth_b,
                                              const std::vector<int>& symmetric_b, const RepairedMesh& repaired,
                                              Index nb, const CorrespondenceErrorOptions& options) {
  const Index used = static_cast<Index>(kept.size());
  // For each source vertex, the (sample, is-mirrored) entries it serves.
  std::map<int, std::vector<std::pair<Index, bool>>> by_source;
  for (Index k = 0; k < used; ++k) {
    const size_t s = static_cast<size_t>(kept[static_cast<size_t>(k)]);
    by_source[truth_b[s]].push_back({k, false});
    if (!symmetric_b.empty() && symmetric_b[s] >= 0 &&
        !repaired_copies(repaired.vertex_map, symmetric_b[s]).empty())
      by_source[symmetric_b[s]].push_back({k, true});
  }
  std::vector<std::pair<int, std::vector<std::pair<Index, bool>>>> groups(by_source.begin(), by_source.end());
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<Eigen::MatrixX2d> distance(maps.size(), Eigen::MatrixX2d::Constant(used, 2, inf));
  std::unique_ptr<FastMarching> marching;
  if (options.geodesics.method == GeodesicMethod::FastMarching)
    marching = std::make_unique<FastMarching>(repaired.mesh);  // stencils once, sources many
  std::exception_ptr error;
#pragma omp parallel for schedule(dynamic, 4)
  for (long g = 0; g < static_cast<long>(groups.size()); ++g) {
    try {
      const auto& [source, entries] = groups[static_cast<size_t>(g)];
      const std::vector<int> copies = repaired_copies(repaired.vertex_map, source);
      Eigen::VectorXd on_repaired = marching ? marching->distances(copies)
                                             : geodesic_distances(repaired.mesh, copies, options.geodesics);
      Eigen::VectorXd d = distances_to_input_vertices(on_repaired, repaired.vertex_map, nb);
      for (const auto& [k, mirrored] : entries) {
        const int va = truth_a[static_cast<size_t>(kept[static_cast<size_t>(k)])];
        for (size_t i = 0; i < maps.size(); ++i) {
          const int m = maps[i][va];
          // A map onto a vertex the repair dropped (another component): no surface path, infinitely wrong.
          if (m >= 0 && std::isfinite(d[m])) distance[i](k, mirrored ? 1 : 0) = d[m];
        }
      }
    } catch (...) {
#pragma omp critical(cshapes_symmetric_correspondence_error)
      if (!error) error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
  return distance;
}

}  // namespace

SymmetricCorrespondenceErrorResult symmetric_correspondence_errors(
    const Mesh& b, const std::vector<Eigen::VectorXi>& maps, const std::vector<int>& truth_a,
    const std::vector<int>& truth_b, const std::vector<int>& symmetric_b,
    const CorrespondenceErrorOptions& options, const std::string& b_name) {
  const Index nb = b.num_vertices();
  CSHAPES_REQUIRE(truth_a.size() == truth_b.size() && !truth_a.empty(),
                  "correspondence error: ", truth_a.size(), " and ", truth_b.size(),
                  " ground-truth samples (expected equal, non-zero counts)");
  CSHAPES_REQUIRE(symmetric_b.empty() || symmetric_b.size() == truth_b.size(),
                  "correspondence error: ", symmetric_b.size(), " symmetric entries for ", truth_b.size(),
                  " samples");
  CSHAPES_REQUIRE(options.curve_points >= 2 && options.max_threshold > 0,
                  "correspondence error: need curve_points >= 2 and max_threshold > 0");
  CSHAPES_REQUIRE(!maps.empty(), "correspondence error: no map to score");

  RepairOptions ro;
  ro.name = b_name;
  ro.purpose = "geodesics of the correspondence error (one manifold component, no zero-area faces)";
  const RepairedMesh repaired = repair_for(b, MeshRequirements::manifold_surface(), ro);

  SymmetricCorrespondenceErrorResult result;
  result.repair_text = repaired.text;
  const std::vector<int> kept =
      kept_samples(nb, truth_b, symmetric_b, repaired, options, b_name, &result.skipped_samples);
  const Index used = static_cast<Index>(kept.size());
  check_maps(maps, kept, truth_a, nb, b_name);
  const std::vector<Eigen::MatrixX2d> distance =
      image_distances(maps, kept, truth_a, truth_b, symmetric_b, repaired, nb, options);

  const double normaliser =
      options.normalise ? std::sqrt(surface_area(repaired.mesh.V, repaired.mesh.F)) : 1.0;
  CSHAPES_REQUIRE(normaliser > 0, "correspondence error: ", b_name, " has zero area");
  for (size_t i = 0; i < maps.size(); ++i) {
    CorrespondenceErrorResult r;
    r.samples = kept;
    r.normaliser = normaliser;
    r.errors.resize(used);
    Eigen::VectorXd direct_errors(used), mirrored_errors(used);
    int unmapped = 0, mirrored = 0;
    for (Index k = 0; k < used; ++k) {
      const int va = truth_a[static_cast<size_t>(kept[static_cast<size_t>(k)])];
      if (maps[i][va] < 0) ++unmapped;
      const double direct = distance[i](k, 0), flipped = distance[i](k, 1);
      if (flipped < direct) ++mirrored;
      r.errors[k] = std::min(direct, flipped) / normaliser;
      direct_errors[k] = direct / normaliser;
      const size_t s = static_cast<size_t>(kept[static_cast<size_t>(k)]);
      const bool has_mirror = !symmetric_b.empty() && symmetric_b[s] >= 0 && maps[i][va] >= 0 &&
                              !repaired_copies(repaired.vertex_map, symmetric_b[s]).empty();
      mirrored_errors[k] = (has_mirror ? flipped : direct) / normaliser;
    }
    summarise_errors(r, options);
    result.direct_errors.push_back(direct_errors);
    result.mirrored_errors.push_back(mirrored_errors);
    result.maps.push_back(std::move(r));
    result.unmapped.push_back(unmapped);
    result.symmetric_chosen.push_back(mirrored);
  }
  return result;
}

double finite_mean(const Eigen::VectorXd& errors) {
  double sum = 0;
  Index finite = 0;
  for (Index i = 0; i < errors.size(); ++i)
    if (std::isfinite(errors[i])) sum += errors[i], ++finite;
  return finite > 0 ? sum / static_cast<double>(finite) : std::numeric_limits<double>::quiet_NaN();
}

double error_median(Eigen::VectorXd errors) {
  if (errors.size() == 0) return std::numeric_limits<double>::quiet_NaN();
  std::sort(errors.data(), errors.data() + errors.size());
  const Index h = errors.size() / 2;
  return errors.size() % 2 ? errors[h] : 0.5 * (errors[h - 1] + errors[h]);
}

double fraction_within(const Eigen::VectorXd& errors, double threshold) {
  if (errors.size() == 0) return 0;
  return static_cast<double>((errors.array() <= threshold).count()) / static_cast<double>(errors.size());
}

}  // namespace cshapes
