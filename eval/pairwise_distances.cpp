#include "cshapes/eval/pairwise_distances.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include "cshapes/support/error.h"
#include "cshapes/support/threads.h"
#include "cshapes/support/timing.h"
#include "cshapes/data/cache.h"
#include "cshapes/mesh/unit_scale.h"
#include "cshapes/matching/shape_distance.h"

namespace cshapes {

namespace {

struct PairValue {
  double hausdorff = 0, chamfer = 0, rmse = 0;
  int reflection = 0;
};

// A pair's entry in the older one-file-per-pair layout (CBOR {hausdorff, chamfer, rmse, reflection, ...},
// or before that a text line); read, no longer written.
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

constexpr const char* kPackFormat = "cshapes-pair-pack-1";

// A finished pair on its way to a pack.
struct PackRecord {
  int source, target;
  PairValue value;
  IcpResult alignment;  // only iterations, rotation and translation are stored
};

// One pack: columns of the records, CBOR, named by the SHA-256 of its bytes.
void write_pack(const DiskCache& packs, const std::vector<PackRecord>& records,
                const std::vector<std::string>& key, const std::string& option_key) {
  if (!packs.enabled() || records.empty()) return;
  nlohmann::json source = nlohmann::json::array(), target = nlohmann::json::array();
  std::vector<double> hausdorff, chamfer, rmse, rotation, translation;
  std::vector<int> reflection, iterations;
  for (const PackRecord& r : records) {
    source.push_back(key[static_cast<size_t>(r.source)]);
    target.push_back(key[static_cast<size_t>(r.target)]);
    hausdorff.push_back(r.value.hausdorff);
    chamfer.push_back(r.value.chamfer);
    rmse.push_back(r.value.rmse);
    reflection.push_back(r.value.reflection);
    iterations.push_back(r.alignment.total_iterations);
    const Eigen::Matrix3d& R = r.alignment.transform.rotation;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) rotation.push_back(R(a, b));
    for (int a = 0; a < 3; ++a) translation.push_back(r.alignment.transform.translation[a]);
  }
  const nlohmann::json pack{{"format", kPackFormat}, {"icp", option_key},        {"source", source},
                            {"target", target},      {"hausdorff", hausdorff},   {"chamfer", chamfer},
                            {"rmse", rmse},          {"reflection", reflection}, {"iterations", iterations},
                            {"R", rotation},         {"t", translation}};
  const std::vector<std::uint8_t> bytes = nlohmann::json::to_cbor(pack);
  const std::string content(bytes.begin(), bytes.end());
  packs.put(sha256_hex(content), content);
}

// Calls found(source key, target key, value) for every pair of every readable pack made with option_key.
// A pack of another format or with inconsistent columns is ignored (as a damaged cache entry is).
template <typename Found>
void read_packs(const DiskCache& packs, const std::string& option_key, Found found) {
  for (const std::string& name : packs.keys()) {
    // A pack is named by its content's SHA-256: a second check, which also covers packs written before the
    // cache entries carried checksums.
    const std::optional<std::string> bytes = packs.get(name);
    if (!bytes) continue;
    if (sha256_hex(*bytes) != name) {
      cache_warning("cache entry " + packs.entry_path(name) +
                    ": content does not match its name (changed on disk), its pairs are recomputed");
      std::remove(packs.entry_path(name).c_str());
      continue;
    }
    const nlohmann::json decoded = nlohmann::json::from_cbor(*bytes, true, false);
    const std::optional<nlohmann::json> pack =
        decoded.is_discarded() ? std::nullopt : std::optional<nlohmann::json>(decoded);
    if (!pack || !pack->is_object() || pack->value("format", "") != kPackFormat ||
        pack->value("icp", "") != option_key)
      continue;
    try {
      const auto source = pack->at("source").get<std::vector<std::string>>();
      const auto target = pack->at("target").get<std::vector<std::string>>();
      const auto hausdorff = pack->at("hausdorff").get<std::vector<double>>();
      const auto chamfer = pack->at("chamfer").get<std::vector<double>>();
      const auto rmse = pack->at("rmse").get<std::vector<double>>();
      const auto reflection = pack->at("reflection").get<std::vector<int>>();
      const size_t n = source.size();
      if (target.size() != n || hausdorff.size() != n || chamfer.size() != n || rmse.size() != n ||
          reflection.size() != n)
        continue;
      for (size_t k = 0; k < n; ++k)
        found(source[k], target[k], PairValue{hausdorff[k], chamfer[k], rmse[k], reflection[k]});
    } catch (const nlohmann::json::exception&) {
      continue;
    }
  }
}

// Pair (i, j), i < j, of n shapes: its position in row order (0, 1), (0, 2), ..., (1, 2), ...
long condensed_index(long i, long j, long n) {
  return i * (2 * n - i - 1) / 2 + (j - i - 1);
}

}  // namespace

std::string points_content_key(const Points& X) {
  std::string bytes = "points " + std::to_string(X.rows()) + "\n";
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> rows = X;
  bytes.append(reinterpret_cast<const char*>(rows.data()), static_cast<size_t>(rows.size()) * sizeof(double));
  return sha256_hex(bytes);
}

namespace {

// One call of pairwise_distances: its inputs, the state the passes share, and the passes in order.
class PairwiseRun {
 public:
  PairwiseRun(const std::vector<Points>& shapes, const std::vector<std::string>& keys,
              const PairwiseDistanceOptions& options)
      : start_(WallClock::now()),
        shapes_(shapes),
        options_(options),
        comm_(options.communicator ? *options.communicator : single_process()),
        n_(static_cast<int>(shapes.size())),
        packs_(options.cache_dir.empty() ? "" : options.cache_dir + "/packs") {
    CSHAPES_REQUIRE(keys.empty() || keys.size() == shapes.size(), "pairwise distances: ", keys.size(),
                    " keys for ", shapes.size(), " shapes");
    CSHAPES_REQUIRE(options.pack_pairs >= 1, "pairwise distances: pack_pairs ", options.pack_pairs,
                    ", expected at least 1");
    key_.resize(static_cast<size_t>(n_));
    for (int i = 0; i < n_; ++i)
      key_[static_cast<size_t>(i)] =
          keys.empty() ? points_content_key(shapes[static_cast<size_t>(i)]) : keys[static_cast<size_t>(i)];
    // Which pairs are wanted, in row order: 0 not wanted, 1 to compute, 2 cached.
    const long all_pairs = static_cast<long>(n_) * (n_ - 1) / 2;
    status_.assign(static_cast<size_t>(all_pairs), options.only_pairs.empty() ? 1 : 0);
    for (const auto& [a, b] : options.only_pairs) {
      CSHAPES_REQUIRE(a >= 0 && b >= 0 && a < n_ && b < n_ && a != b, "pairwise distances: pair (", a, ", ",
                      b, ") of ", n_, " shapes");
      status_[static_cast<size_t>(condensed_index(std::min(a, b), std::max(a, b), n_))] = 1;
    }
    result_.hausdorff = result_.chamfer = result_.rmse = Eigen::MatrixXd::Zero(n_, n_);
    reflection_ = Eigen::MatrixXd::Zero(n_, n_);
    result_.pairs = static_cast<long>(std::count(status_.begin(), status_.end(), 1));
    icp_options_ = options.icp;
    icp_options_.parallel = false;
    option_key_ = to_key_string(icp_options_);
    scaled_icp_options_ = icp_options_;
    threads_ = options.threads > 0 ? options.threads : omp_get_max_threads();
  }

  PairwiseDistanceResult run() {
    if (comm_.is_root()) read_cache();
    comm_.broadcast_from_root(status_);
    result_.cached = static_cast<long>(std::count(status_.begin(), status_.end(), 2));
    choose_share();
    choose_scale();
    prepare_shapes();
    align_pairs();
    const bool root = gather_over_ranks();
    if (root) finish_matrices();
    result_.seconds = seconds_since(start_);
    return result_;
  }

 private:
  struct Pair {
    int source, target;
  };

  char& status(int i, int j) {
    return status_[static_cast<size_t>(condensed_index(std::min(i, j), std::max(i, j), n_))];
  }
  // The pair's source: the shape of the smaller key, so that a pair is stored once whichever way asked.
  int source_of(int i, int j) const {
    return key_[static_cast<size_t>(i)] <= key_[static_cast<size_t>(j)] ? i : j;
  }
  void store(int i, int j, const PairValue& v) {
    result_.hausdorff(i, j) = result_.hausdorff(j, i) = v.hausdorff;
    result_.chamfer(i, j) = result_.chamfer(j, i) = v.chamfer;
    result_.rmse(i, j) = result_.rmse(j, i) = v.rmse;
    reflection_(i, j) = reflection_(j, i) = v.reflection;
  }
  void keep_error() {
#pragma omp critical(cshapes_pairwise_error)
    if (!error_) error_ = std::current_exception();
    stop_ = true;
  }

  // Pass 1 (rank 0, serial): what the cache holds, from the packs, then from the older one-file-per-pair
  // entries when there are any.
  void read_cache() {
    std::unordered_map<std::string, std::vector<int>> index_of;
    for (int i = 0; i < n_; ++i) index_of[key_[static_cast<size_t>(i)]].push_back(i);
    read_packs(packs_, option_key_, [&](const std::string& a, const std::string& b, const PairValue& v) {
      auto ia = index_of.find(a), ib = index_of.find(b);
      if (ia == index_of.end() || ib == index_of.end()) return;
      for (int i : ia->second)
        for (int j : ib->second) {
          if (i == j) continue;
          char& s = status(i, j);
          if (s != 1 || source_of(i, j) != i) continue;
          store(i, j, v);
          s = 2;
        }
    });
    const DiskCache legacy(options_.cache_dir);
    std::vector<std::string> legacy_keys = legacy.keys();
    if (legacy_keys.empty()) return;
    const std::unordered_set<std::string> present(legacy_keys.begin(), legacy_keys.end());
    for (int i = 0; i < n_; ++i)
      for (int j = i + 1; j < n_; ++j) {
        char& s = status(i, j);
        if (s != 1) continue;
        const int src = source_of(i, j), tgt = src == i ? j : i;
        const std::string pair_key = cache_key({"pairwise-distance-1", key_[static_cast<size_t>(src)],
                                                key_[static_cast<size_t>(tgt)], option_key_});
        PairValue v;
        if (!present.count(pair_key)) continue;
        std::optional<std::string> cached = legacy.get(pair_key);
        if (cached && decode(*cached, v)) {
          store(i, j, v);
          s = 2;
        }
      }
  }

  // This rank's share of the missing pairs: a contiguous block of the row-order list, balanced by count.
  void choose_share() {
    const long missing = static_cast<long>(std::count(status_.begin(), status_.end(), 1));
    const ItemRange mine = contiguous_share(missing, comm_.size(), comm_.rank());
    long rank_in_missing = 0;
    for (int i = 0; i < n_ && rank_in_missing < mine.end; ++i)
      for (int j = i + 1; j < n_ && rank_in_missing < mine.end; ++j) {
        if (status(i, j) != 1) continue;
        if (rank_in_missing++ < mine.begin) continue;
        const int src = source_of(i, j);
        todo_.push_back({src, src == i ? j : i});
      }
  }

  // The factor every shape is aligned at: 1 when ICP takes every shape as it is; else the power of two that
  // brings the largest shape to unit size (exact), so that a set of any finite scale gives its matrix in its
  // own units. From all shapes, so that every rank of a distributed run uses the same.
  void choose_scale() {
    if (std::all_of(shapes_.begin(), shapes_.end(),
                    [](const Points& shape) { return icp_size_refusal(finite_rows(shape)).empty(); }))
      return;
    scale_ = std::numeric_limits<double>::infinity();
    for (const Points& shape : shapes_) {
      const Points points = finite_rows(shape);
      // A shape ICP refuses at any size (prepare_shapes names it) has no size to go by.
      if (icp_points_refusal(points).empty()) scale_ = std::min(scale_, power_of_two_unit_scale(points));
    }
    if (!std::isfinite(scale_)) scale_ = 1;
    scaled_icp_options_.max_correspondence_distance *= scale_;
  }

  // Pass 2a: the ICP shapes this rank's pairs need, OpenMP over shapes.
  void prepare_shapes() {
    prepared_.resize(static_cast<size_t>(n_));
    std::vector<char> needed(static_cast<size_t>(n_), 0);
    for (const Pair& p : todo_)
      needed[static_cast<size_t>(p.source)] = needed[static_cast<size_t>(p.target)] = 1;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads_)
    for (int i = 0; i < n_; ++i) {
      if (!needed[static_cast<size_t>(i)] || stop_) continue;
      try {
        // Vertices a repair dropped are NaN rows (pipeline/canonical_forms.h): aligned and measured without
        // them.
        Points points = finite_rows(shapes_[static_cast<size_t>(i)]);
        if (std::string refusal = icp_points_refusal(points); !refusal.empty())
          fail("pairwise distances: shape ", i, ": ", refusal);
        if (scale_ != 1) {
          points *= scale_;
          if (std::string refusal = icp_size_refusal(points); !refusal.empty())
            fail("pairwise distances: shape ", i, " is under ", kIcpSmallestSize,
                 " times the size of the largest shape; squared distances of both do not fit in a double: "
                 "scale the shapes to comparable sizes");
        }
        prepared_[static_cast<size_t>(i)] = std::make_unique<IcpShape>(points, scaled_icp_options_);
      } catch (...) {
        keep_error();
      }
    }
  }

  void write_pending(std::vector<PackRecord>& records) {
    try {
      write_pack(packs_, records, key_, option_key_);
    } catch (...) {
      keep_error();
    }
    records.clear();
  }

  // One pair, on the calling thread: aligned, stored, added to the pending pack (written when full).
  void align_pair(const Pair& p, long total_todo) {
    PackRecord record{p.source, p.target, {}, {}};
    ShapeDistance d = aligned_shape_distance(*prepared_[static_cast<size_t>(p.source)],
                                             *prepared_[static_cast<size_t>(p.target)], scaled_icp_options_,
                                             &record.alignment);
    if (scale_ != 1) scale_lengths(1 / scale_, d, &record.alignment);
    record.value = {d.hausdorff, d.chamfer, d.rmse, record.alignment.transform.is_reflection() ? 1 : 0};
    store(p.source, p.target, record.value);  // distinct entries per pair: no race
    std::vector<PackRecord> full;
    long done = 0;
#pragma omp critical(cshapes_pairwise_pack)
    {
      pending_.push_back(std::move(record));
      done = ++computed_;
      if (static_cast<long>(pending_.size()) >= options_.pack_pairs ||
          seconds_since(last_pack_) >= options_.pack_seconds) {
        full.swap(pending_);
        last_pack_ = WallClock::now();
      }
    }
    write_pending(full);
    report_progress_in_parallel(options_.progress, "distances", static_cast<double>(result_.cached + done),
                                static_cast<double>(result_.cached + total_todo));
    if (options_.fail_after_computed >= 0 && done >= options_.fail_after_computed) {
      // The hook simulates a kill after `done` stored pairs: store them now.
      std::vector<PackRecord> rest;
#pragma omp critical(cshapes_pairwise_pack)
      rest.swap(pending_);
      write_pending(rest);
      fail("pairwise distances: stopped after ", done, " computed pairs (test hook fail_after_computed)");
    }
  }

  // Pass 2b: this rank's pairs in blocks, each its own parallel region with the thread count chosen again
  // before it (support/threads.h: refresh_threads), so a long run uses the cores that are free now. A pair is
  // aligned by one thread, so its values do not depend on the count. What is left pending is written at the
  // end, also after an error: finished pairs stay cached.
  void align_pairs() {
    last_pack_ = WallClock::now();
    const long total_todo = error_ ? 0 : static_cast<long>(todo_.size());
    const long block_pairs = std::max<long>(64, 16L * threads_);
    for (long first = 0; first < total_todo && !stop_; first += block_pairs) {
      const long last = std::min(total_todo, first + block_pairs);
      const int block_threads = options_.threads > 0 ? options_.threads : refresh_threads();
#pragma omp parallel for schedule(dynamic, 1) num_threads(block_threads)
      for (long k = first; k < last; ++k) {
        if (stop_) continue;
        try {
          align_pair(todo_[static_cast<size_t>(k)], total_todo);
        } catch (...) {
          keep_error();
        }
      }
    }
    write_pending(pending_);
  }

  // Every rank learns whether any failed, so that none waits for the others in the sums; then the matrices
  // are summed to rank 0. Returns whether this rank holds the result (the others' matrices are emptied).
  bool gather_over_ranks() {
    if (comm_.any(static_cast<bool>(error_))) {
      if (error_) std::rethrow_exception(error_);
      fail("pairwise distances: another rank failed (its message says why)");
    }
    result_.computed = comm_.sum(static_cast<long>(computed_));
    if (comm_.size() > 1) {
      for (Eigen::MatrixXd* M : {&result_.hausdorff, &result_.chamfer, &result_.rmse, &reflection_})
        comm_.sum_to_root(M->data(), static_cast<size_t>(M->size()));
      if (!comm_.is_root()) {
        result_.hausdorff.resize(0, 0);
        result_.chamfer.resize(0, 0);
        result_.rmse.resize(0, 0);
        result_.reflection.resize(0, 0);
        return false;
      }
    }
    return true;
  }

  // The reflection flags as integers; pairs not asked for (only_pairs) are NaN.
  void finish_matrices() {
    result_.reflection = reflection_.cast<int>();
    if (options_.only_pairs.empty()) return;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (int i = 0; i < n_; ++i)
      for (int j = i + 1; j < n_; ++j)
        if (status(i, j) == 0)
          result_.hausdorff(i, j) = result_.hausdorff(j, i) = result_.chamfer(i, j) = result_.chamfer(j, i) =
              result_.rmse(i, j) = result_.rmse(j, i) = nan;
  }

  const WallClock::time_point start_;
  const std::vector<Points>& shapes_;
  const PairwiseDistanceOptions& options_;
  const Communicator& comm_;
  const int n_;
  const DiskCache packs_;
  std::vector<std::string> key_;
  std::string status_;
  PairwiseDistanceResult result_;
  Eigen::MatrixXd reflection_;  // summed over ranks as doubles (0 or 1)
  IcpOptions icp_options_;
  std::string option_key_;  // of icp_options_: the pairs' results are in the shapes' own units
  double scale_ = 1;        // the shapes are aligned multiplied by this (choose_scale)
  IcpOptions scaled_icp_options_;  // icp_options_ with max_correspondence_distance at that scale
  int threads_ = 1;
  std::vector<Pair> todo_;
  std::vector<std::unique_ptr<IcpShape>> prepared_;
  std::exception_ptr error_;
  std::atomic<bool> stop_{false};
  std::atomic<long> computed_{0};
  std::vector<PackRecord> pending_;  // finished, not yet in a pack
  WallClock::time_point last_pack_;
};

}  // namespace

PairwiseDistanceResult pairwise_distances(const std::vector<Points>& shapes,
                                          const std::vector<std::string>& keys,
                                          const PairwiseDistanceOptions& options) {
  return PairwiseRun(shapes, keys, options).run();
}

}  // namespace cshapes
