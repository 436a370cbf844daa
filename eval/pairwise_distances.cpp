#include "eval/pairwise_distances.h"

#include <omp.h>

#include <atomic>
#include <cstdio>
#include <exception>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/error.h"
#include "core/timing.h"
#include "eval/cache.h"
#include "matching/shape_distance.h"

namespace cshapes {

namespace {

struct PairValue {
  double hausdorff = 0, chamfer = 0, rmse = 0;
  int reflection = 0;
};

// A pair's cache value (JSON, stored as CBOR like every cache entry): the distances and the alignment.
nlohmann::json encode(const PairValue& v, const IcpResult& r) {
  const Eigen::Matrix3d& R = r.transform.rotation;
  const Eigen::Vector3d& t = r.transform.translation;
  return {{"hausdorff", v.hausdorff},
          {"chamfer", v.chamfer},
          {"rmse", v.rmse},
          {"reflection", v.reflection},
          {"iterations", r.total_iterations},
          {"R", {R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2)}},
          {"t", {t[0], t[1], t[2]}}};
}

bool decode(const std::string& bytes, PairValue& v) {
  const nlohmann::json j = nlohmann::json::from_cbor(bytes, true, false);
  if (!j.is_discarded()) {
    for (const char* field : {"hausdorff", "chamfer", "rmse", "reflection"})
      if (!j.is_object() || !j.contains(field) || !j[field].is_number()) return false;
    v.hausdorff = j["hausdorff"].get<double>();
    v.chamfer = j["chamfer"].get<double>();
    v.rmse = j["rmse"].get<double>();
    v.reflection = j["reflection"].get<int>();
    return true;
  }
  // Entries written before the caches shared one format: one text line with exact doubles (%.17g).
  std::istringstream in(bytes);
  std::string a, b, c, d;
  return static_cast<bool>(in >> a >> v.hausdorff >> b >> v.chamfer >> c >> v.rmse >> d >> v.reflection) &&
         a == "hausdorff" && b == "chamfer" && c == "rmse" && d == "reflection";
}

}  // namespace

std::string points_content_key(const Points& X) {
  std::string bytes = "points " + std::to_string(X.rows()) + "\n";
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> rows = X;
  bytes.append(reinterpret_cast<const char*>(rows.data()), static_cast<size_t>(rows.size()) * sizeof(double));
  return sha256_hex(bytes);
}

PairwiseDistanceResult pairwise_distances(const std::vector<Points>& shapes,
                                          const std::vector<std::string>& keys,
                                          const PairwiseDistanceOptions& options) {
  const auto start = WallClock::now();
  const int n = static_cast<int>(shapes.size());
  CSHAPES_REQUIRE(keys.empty() || keys.size() == shapes.size(), "pairwise distances: ", keys.size(),
                  " keys for ", shapes.size(), " shapes");
  std::vector<std::string> key(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i)
    key[static_cast<size_t>(i)] =
        keys.empty() ? points_content_key(shapes[static_cast<size_t>(i)]) : keys[static_cast<size_t>(i)];

  PairwiseDistanceResult result;
  result.hausdorff = result.chamfer = result.rmse = Eigen::MatrixXd::Zero(n, n);
  result.reflection = Eigen::MatrixXi::Zero(n, n);
  result.pairs = static_cast<long>(n) * (n - 1) / 2;
  IcpOptions icp_options = options.icp;
  icp_options.parallel = false;
  const std::string option_key = to_key_string(icp_options);
  DiskCache cache(options.cache_dir);

  // Pass 1 (cheap, serial): cached pairs. The shape with the smaller key is the source.
  struct Pair {
    int source, target;
    std::string key;
  };
  std::vector<Pair> todo;
  auto store = [&](int i, int j, const PairValue& v) {
    result.hausdorff(i, j) = result.hausdorff(j, i) = v.hausdorff;
    result.chamfer(i, j) = result.chamfer(j, i) = v.chamfer;
    result.rmse(i, j) = result.rmse(j, i) = v.rmse;
    result.reflection(i, j) = result.reflection(j, i) = v.reflection;
  };
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      int s = key[static_cast<size_t>(i)] <= key[static_cast<size_t>(j)] ? i : j, t = s == i ? j : i;
      std::string pair_key = cache_key(
          {"pairwise-distance-1", key[static_cast<size_t>(s)], key[static_cast<size_t>(t)], option_key});
      PairValue v;
      std::optional<std::string> cached = cache.get(pair_key);
      if (cached && decode(*cached, v)) {
        store(i, j, v);
        ++result.cached;
      } else {
        todo.push_back({s, t, pair_key});
      }
    }

  // Pass 2: prepare the shapes the remaining pairs need, then align them, OpenMP over pairs.
  std::vector<std::unique_ptr<IcpShape>> prepared(static_cast<size_t>(n));
  std::vector<char> needed(static_cast<size_t>(n), 0);
  for (const Pair& p : todo)
    needed[static_cast<size_t>(p.source)] = needed[static_cast<size_t>(p.target)] = 1;
  const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();
  std::exception_ptr error;
  std::atomic<bool> stop{false};
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (int i = 0; i < n; ++i) {
    if (!needed[static_cast<size_t>(i)] || stop) continue;
    try {
      // Vertices a repair dropped are NaN rows (pipeline/canonical_forms.h): aligned and measured without
      // them.
      prepared[static_cast<size_t>(i)] =
          std::make_unique<IcpShape>(finite_rows(shapes[static_cast<size_t>(i)]), icp_options);
    } catch (...) {
#pragma omp critical(cshapes_pairwise_error)
      if (!error) error = std::current_exception();
      stop = true;
    }
  }
  if (error) std::rethrow_exception(error);

  std::atomic<long> computed{0};
  const long total_todo = static_cast<long>(todo.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (long k = 0; k < total_todo; ++k) {
    if (stop) continue;
    const Pair& p = todo[static_cast<size_t>(k)];
    try {
      IcpResult alignment;
      ShapeDistance d =
          aligned_shape_distance(*prepared[static_cast<size_t>(p.source)],
                                 *prepared[static_cast<size_t>(p.target)], icp_options, &alignment);
      PairValue v{d.hausdorff, d.chamfer, d.rmse, alignment.transform.is_reflection() ? 1 : 0};
      cache.put_json(p.key, encode(v, alignment));
      store(p.source, p.target, v);  // distinct entries per pair: no race
      long done = ++computed;
      if (options.progress) {
#pragma omp critical(cshapes_pairwise_progress)
        options.progress("distances", static_cast<double>(result.cached + done),
                         static_cast<double>(result.pairs));
      }
      if (options.fail_after_computed >= 0 && done >= options.fail_after_computed)
        fail("pairwise distances: stopped after ", done, " computed pairs (test hook fail_after_computed)");
    } catch (...) {
#pragma omp critical(cshapes_pairwise_error)
      if (!error) error = std::current_exception();
      stop = true;
    }
  }
  result.computed = computed;
  if (error) std::rethrow_exception(error);
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace cshapes
