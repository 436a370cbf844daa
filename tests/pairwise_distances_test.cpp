#include "cshapes/eval/pairwise_distances.h"

#include <gtest/gtest.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/data/cache.h"
#include "cshapes/matching/shape_distance.h"
#include "tests/test_support.h"

namespace cshapes {
namespace pairwise_distances_test {

namespace fs = std::filesystem;

// Six small shapes in two families (ellipsoids and lumpier ones), each placed at random.
std::vector<Points> small_shapes() {
  std::vector<Points> shapes;
  for (int s = 0; s < 6; ++s) {
    std::mt19937_64 rng(100 + s);
    std::normal_distribution<double> normal(0.0, 1.0);
    Points X(300, 3);
    for (Index i = 0; i < X.rows(); ++i) {
      Eigen::Vector3d u(normal(rng), normal(rng), normal(rng));
      u.normalize();
      double lump = s < 3 ? 0.05 * s : 0.3 + 0.05 * s;
      double r = 1.0 + lump * std::sin(3 * u.x()) * std::cos(2 * u.y());
      X.row(i) = (Eigen::Vector3d(3.0, 1.5, 1.0).asDiagonal() * (r * u)).transpose();
    }
    shapes.push_back(random_rigid_transform(200 + s, 2.0, s % 2).apply(X));
  }
  return shapes;
}

PairwiseDistanceOptions fast_options(const std::string& cache_dir, int threads) {
  PairwiseDistanceOptions o;
  o.icp.pyramid = {50, 150};
  o.cache_dir = cache_dir;
  o.threads = threads;
  return o;
}

long count_entries(const std::string& dir) {
  long n = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file() && e.path().extension() == ".bin") ++n;
  return n;
}

// Pairs stored in the cache's packs (the layout eval/pairwise_distances.h documents).
long count_cached_pairs(const std::string& dir) {
  const DiskCache packs(dir + "/packs");
  long n = 0;
  for (const std::string& key : packs.keys())
    n += static_cast<long>(packs.get_json(key)->at("source").size());
  return n;
}

TEST(PairwiseDistances, SymmetricZeroDiagonalAndEqualToSingleAlignments) {
  std::vector<Points> shapes = small_shapes();
  PairwiseDistanceOptions o = fast_options("", 2);
  PairwiseDistanceResult r = pairwise_distances(shapes, {}, o);
  EXPECT_EQ(r.pairs, 15);
  EXPECT_EQ(r.computed, 15);
  EXPECT_EQ(r.cached, 0);
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(r.hausdorff(i, i), 0.0);
    for (int j = 0; j < 6; ++j) {
      EXPECT_EQ(r.hausdorff(i, j), r.hausdorff(j, i));
      EXPECT_EQ(r.chamfer(i, j), r.chamfer(j, i));
      if (i != j) {
        EXPECT_GT(r.hausdorff(i, j), 0.0);
      }
      EXPECT_LE(r.chamfer(i, j), r.rmse(i, j) + 1e-12);  // mean ≤ root mean square
      EXPECT_LE(r.rmse(i, j), r.hausdorff(i, j) + 1e-12);
    }
  }
  // Each entry is the distance of the pair aligned on its own (source: the shape with the smaller key).
  std::string k0 = points_content_key(shapes[0]), k4 = points_content_key(shapes[4]);
  const Points& source = k0 <= k4 ? shapes[0] : shapes[4];
  const Points& target = k0 <= k4 ? shapes[4] : shapes[0];
  IcpOptions icp = o.icp;
  ShapeDistance single = aligned_shape_distance(source, target, icp);
  EXPECT_DOUBLE_EQ(r.hausdorff(0, 4), single.hausdorff);
  EXPECT_DOUBLE_EQ(r.chamfer(0, 4), single.chamfer);
  // Within a family (0-2 or 3-5) shapes are closer than across.
  EXPECT_LT(r.chamfer(0, 1), r.chamfer(0, 5));
}

TEST(PairwiseDistances, IndependentOfTheOrderOfShapes) {
  std::vector<Points> shapes = small_shapes();
  std::vector<Points> reversed(shapes.rbegin(), shapes.rend());
  PairwiseDistanceResult a = pairwise_distances(shapes, {}, fast_options("", 1));
  PairwiseDistanceResult b = pairwise_distances(reversed, {}, fast_options("", 1));
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) EXPECT_EQ(a.hausdorff(i, j), b.hausdorff(5 - i, 5 - j));
}

// The acceptance test: a run killed midway and restarted recomputes nothing that was cached.
TEST(PairwiseDistances, KilledRunResumesWithoutRecomputing) {
  std::vector<Points> shapes = small_shapes();
  std::string dir = test::scratch_dir("pairwise");
  const long total = 15, k = 5;
  PairwiseDistanceOptions killed = fast_options(dir, 1);
  killed.fail_after_computed = k;
  EXPECT_THROW(pairwise_distances(shapes, {}, killed), Error);
  EXPECT_EQ(count_cached_pairs(dir), k);
  EXPECT_EQ(count_entries(dir), 1);  // in one pack

  PairwiseDistanceResult resumed = pairwise_distances(shapes, {}, fast_options(dir, 1));
  EXPECT_EQ(resumed.cached, k);            // hits: what the killed run stored
  EXPECT_EQ(resumed.computed, total - k);  // misses: only the rest
  PairwiseDistanceResult again = pairwise_distances(shapes, {}, fast_options(dir, 1));
  EXPECT_EQ(again.cached, total);
  EXPECT_EQ(again.computed, 0);
  // Cached values are exact (CBOR doubles) and equal a run without a cache.
  PairwiseDistanceResult fresh = pairwise_distances(shapes, {}, fast_options("", 1));
  EXPECT_EQ(again.hausdorff, fresh.hausdorff);
  EXPECT_EQ(again.chamfer, fresh.chamfer);
  EXPECT_EQ(again.rmse, fresh.rmse);
  EXPECT_EQ(resumed.hausdorff, fresh.hausdorff);
  fs::remove_all(dir);
}

TEST(PairwiseDistances, EntriesOfTheOlderLayoutsAreStillRead) {
  // Before packs, each pair had an entry of its own under cache_key({"pairwise-distance-1", source key,
  // target key, ICP options}): CBOR, and before that a text line. Both are still read.
  std::vector<Points> shapes = small_shapes();
  shapes.resize(3);
  const std::string dir = test::scratch_dir("pairwise-legacy");
  const PairwiseDistanceOptions o = fast_options(dir, 1);
  const PairwiseDistanceResult fresh = pairwise_distances(shapes, {}, fast_options("", 1));
  std::vector<std::string> key;
  for (const Points& X : shapes) key.push_back(points_content_key(X));
  IcpOptions icp = o.icp;
  icp.parallel = false;
  auto legacy_key = [&](int i, int j) {
    const int s = key[i] <= key[j] ? i : j, t = s == i ? j : i;
    return cache_key({"pairwise-distance-1", key[s], key[t], to_key_string(icp)});
  };
  const DiskCache cache(dir);
  cache.put_json(legacy_key(0, 1), {{"hausdorff", fresh.hausdorff(0, 1) * 2},
                                    {"chamfer", fresh.chamfer(0, 1)},
                                    {"rmse", fresh.rmse(0, 1)},
                                    {"reflection", fresh.reflection(0, 1)}});
  char line[256];
  std::snprintf(line, sizeof line, "hausdorff %.17g chamfer %.17g rmse %.17g reflection %d iterations 3\n",
                fresh.hausdorff(1, 2) * 3, fresh.chamfer(1, 2), fresh.rmse(1, 2), fresh.reflection(1, 2));
  cache.put(legacy_key(1, 2), line);
  PairwiseDistanceResult again = pairwise_distances(shapes, {}, o);
  EXPECT_EQ(again.cached, 2);
  EXPECT_EQ(again.computed, 1);
  EXPECT_EQ(again.hausdorff(0, 1), fresh.hausdorff(0, 1) * 2);  // the values read, not recomputed
  EXPECT_EQ(again.hausdorff(2, 1), fresh.hausdorff(1, 2) * 3);
  EXPECT_EQ(again.chamfer(1, 2), fresh.chamfer(1, 2));
  EXPECT_EQ(again.hausdorff(0, 2), fresh.hausdorff(0, 2));
  EXPECT_EQ(count_cached_pairs(dir), 1);  // only the new pair went into a pack
  fs::remove_all(dir);
}

TEST(PairwiseDistances, PacksHoldManyPairs) {
  std::vector<Points> shapes = small_shapes();
  const std::string dir = test::scratch_dir("pairwise-packs");
  PairwiseDistanceOptions o = fast_options(dir, 2);
  o.pack_pairs = 5;
  PairwiseDistanceResult first = pairwise_distances(shapes, {}, o);
  EXPECT_EQ(count_cached_pairs(dir), 15);
  EXPECT_EQ(count_entries(dir), 3);
  // Read back exactly, whatever the pack size of the reader.
  PairwiseDistanceResult again = pairwise_distances(shapes, {}, fast_options(dir, 1));
  EXPECT_EQ(again.cached, 15);
  EXPECT_EQ(again.hausdorff, first.hausdorff);
  EXPECT_EQ(again.reflection, first.reflection);
  // A damaged pack is ignored (its pairs recomputed), like any damaged entry.
  const DiskCache packs(dir + "/packs");
  packs.put(packs.keys().front(), "not CBOR");
  PairwiseDistanceResult repaired = pairwise_distances(shapes, {}, fast_options(dir, 1));
  EXPECT_EQ(repaired.computed, 5);
  EXPECT_EQ(repaired.hausdorff, first.hausdorff);
  EXPECT_THROW(pairwise_distances(shapes, {},
                                  [&] {
                                    PairwiseDistanceOptions bad = fast_options("", 1);
                                    bad.pack_pairs = 0;
                                    return bad;
                                  }()),
               Error);
  fs::remove_all(dir);
}

TEST(PairwiseDistances, FlippedBytesInAPackAreRecomputedNotServed) {
  // Issue 22: 8 bytes flipped inside a float64 of a pair pack changed the distance matrix silently.
  std::vector<Points> shapes = small_shapes();
  shapes.resize(4);
  const std::string dir = test::scratch_dir("pairwise-flipped");
  const PairwiseDistanceResult first = pairwise_distances(shapes, {}, fast_options(dir, 1));
  const DiskCache packs(dir + "/packs");
  ASSERT_EQ(packs.keys().size(), 1u);
  const std::string path = packs.entry_path(packs.keys().front());
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  // The first float64 of the "hausdorff" column (CBOR 0xfb + 8 bytes).
  const size_t at = bytes.find('\xfb', bytes.find("hausdorff"));
  ASSERT_NE(at, std::string::npos);
  for (size_t k = at + 1; k < at + 9; ++k) bytes[k] = static_cast<char>(bytes[k] ^ 0x21);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;

  std::vector<std::string> warnings;
  set_cache_warning_sink([&](const std::string& line) { warnings.push_back(line); });
  const PairwiseDistanceResult again = pairwise_distances(shapes, {}, fast_options(dir, 1));
  set_cache_warning_sink({});
  EXPECT_EQ(again.cached, 0);
  EXPECT_EQ(again.computed, 6);
  EXPECT_EQ(again.hausdorff, first.hausdorff);
  ASSERT_FALSE(warnings.empty());
  EXPECT_NE(warnings[0].find(path), std::string::npos) << warnings[0];
  // The recomputed pairs are cached again, under a sound pack.
  EXPECT_EQ(pairwise_distances(shapes, {}, fast_options(dir, 1)).cached, 6);
  fs::remove_all(dir);
}

TEST(PairwiseDistances, FailedPackWriteStopsTheRunAndEarlierPacksStay) {
  // Issue 22: a failed pack write is an error (the disk's reason named), not a quiet loss; the packs written
  // before it keep their pairs for the next run.
  std::vector<Points> shapes = small_shapes();
  const std::string dir = test::scratch_dir("pairwise-full");
  PairwiseDistanceOptions o = fast_options(dir, 1);
  o.pack_pairs = 2;
  fail_file_writes_for_testing(3);  // packs 1 and 2 are written, the disk is full from the third
  try {
    pairwise_distances(shapes, {}, o);
    ADD_FAILURE() << "no error";
  } catch (const WriteError& e) {
    EXPECT_NE(std::string(e.what()).find(dir + "/packs/"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(std::strerror(ENOSPC)), std::string::npos) << e.what();
  }
  fail_file_writes_for_testing(0);
  EXPECT_EQ(count_cached_pairs(dir), 4);
  const PairwiseDistanceResult resumed = pairwise_distances(shapes, {}, fast_options(dir, 1));
  EXPECT_EQ(resumed.cached, 4);
  EXPECT_EQ(resumed.computed, 11);
  EXPECT_EQ(resumed.hausdorff, pairwise_distances(shapes, {}, fast_options("", 1)).hausdorff);
  fs::remove_all(dir);
}

TEST(PairwiseDistances, OnlyThePairsAsked) {
  std::vector<Points> shapes = small_shapes();
  const PairwiseDistanceResult all = pairwise_distances(shapes, {}, fast_options("", 2));
  PairwiseDistanceOptions o = fast_options("", 2);
  o.only_pairs = {{0, 3}, {3, 0}, {5, 1}};  // a pair listed in both orders counts once
  const PairwiseDistanceResult some = pairwise_distances(shapes, {}, o);
  EXPECT_EQ(some.pairs, 2);
  EXPECT_EQ(some.computed, 2);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      const bool asked =
          (std::min(i, j) == 0 && std::max(i, j) == 3) || (std::min(i, j) == 1 && std::max(i, j) == 5);
      if (i == j)
        EXPECT_EQ(some.hausdorff(i, j), 0.0);
      else if (asked)
        EXPECT_EQ(some.hausdorff(i, j), all.hausdorff(i, j));
      else
        EXPECT_TRUE(std::isnan(some.hausdorff(i, j))) << i << "," << j;
    }
  o.only_pairs = {{2, 2}};
  EXPECT_THROW(pairwise_distances(shapes, {}, o), Error);
}

TEST(PairwiseDistances, KilledParallelRunResumesWithoutRecomputing) {
  // With two threads, pairs in flight when the hook fires may still finish and be stored: count what is
  // on disk, and check that the rerun computes exactly the rest.
  std::vector<Points> shapes = small_shapes();
  std::string dir = test::scratch_dir("pairwise-parallel");
  PairwiseDistanceOptions killed = fast_options(dir, 2);
  killed.fail_after_computed = 4;
  EXPECT_THROW(pairwise_distances(shapes, {}, killed), Error);
  long stored = count_cached_pairs(dir);
  EXPECT_GE(stored, 4);
  EXPECT_LT(stored, 15);
  PairwiseDistanceResult resumed = pairwise_distances(shapes, {}, fast_options(dir, 2));
  EXPECT_EQ(resumed.cached, stored);
  EXPECT_EQ(resumed.computed, 15 - stored);
  fs::remove_all(dir);
}

TEST(PairwiseDistances, KeysFollowContentAndOptions) {
  std::vector<Points> shapes = small_shapes();
  std::string dir = test::scratch_dir("pairwise-keys");
  std::vector<std::string> keys = {"a", "b", "c", "d", "e", "f"};
  pairwise_distances(shapes, keys, fast_options(dir, 2));
  // Same keys, same options: all cached. Other ICP options: nothing is.
  EXPECT_EQ(pairwise_distances(shapes, keys, fast_options(dir, 2)).cached, 15);
  PairwiseDistanceOptions other = fast_options(dir, 2);
  other.icp.trim_fraction = 0.05;
  EXPECT_EQ(pairwise_distances(shapes, keys, other).cached, 0);
  // One shape's key changed (its input file changed): only its 5 pairs are recomputed.
  keys[2] = "c2";
  PairwiseDistanceResult r = pairwise_distances(shapes, keys, fast_options(dir, 2));
  EXPECT_EQ(r.computed, 5);
  EXPECT_EQ(r.cached, 10);
  EXPECT_THROW(pairwise_distances(shapes, {"x"}, fast_options(dir, 1)), Error);
  fs::remove_all(dir);
}

TEST(PairwiseDistances, PointsContentKey) {
  Points X = small_shapes()[0];
  Points Y = X;
  EXPECT_EQ(points_content_key(X), points_content_key(Y));
  Y(3, 1) += 1e-12;
  EXPECT_NE(points_content_key(X), points_content_key(Y));
}

// Issue 57: the promise "any finite scale". A set scaled by 1e150 or 1e-150 gives the matrix scaled by the
// same factor, to rounding (ICP refused every shape of it by size, and distmat had "0 usable shapes").
TEST(PairwiseDistances, MatrixScalesWithTheSetAtAnyFiniteScale) {
  const std::vector<Points> shapes = small_shapes();
  const PairwiseDistanceResult unit = pairwise_distances(shapes, {}, fast_options("", 1));
  for (double s : {1e150, 1e-150}) {
    SCOPED_TRACE(s);
    std::vector<Points> scaled;
    for (const Points& X : shapes) scaled.push_back(X * s);
    const PairwiseDistanceResult r = pairwise_distances(scaled, {}, fast_options("", 1));
    for (const auto& [got, want] : {std::pair{&r.hausdorff, &unit.hausdorff}, std::pair{&r.chamfer, &unit.chamfer},
                                    std::pair{&r.rmse, &unit.rmse}})
      EXPECT_LE((*got / s - *want).cwiseAbs().maxCoeff(), 1e-9 * want->maxCoeff());
    EXPECT_EQ(r.reflection, unit.reflection);
  }
}

// A shape ICP cannot take at any size is refused by its index; one beside shapes 1e150 times larger too.
TEST(PairwiseDistances, RefusesAShapeThatSpansNoPlaneByItsIndex) {
  std::vector<Points> shapes = small_shapes();
  shapes[2] = Eigen::RowVector3d(1, 2, 3).replicate(50, 1);
  try {
    pairwise_distances(shapes, {}, fast_options("", 1));
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("shape 2: ICP needs points that span a plane"), std::string::npos)
        << e.what();
  }
  shapes = small_shapes();
  shapes[4] *= 1e150;
  try {
    pairwise_distances(shapes, {}, fast_options("", 1));
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("shape 0 is under"), std::string::npos) << e.what();
  }
}

}  // namespace pairwise_distances_test
}  // namespace cshapes
