#include "cshapes/data/cache.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "tests/test_support.h"

namespace cshapes {
namespace cache_test {

namespace fs = std::filesystem;

TEST(Sha256, KnownAnswers) {
  // FIPS 180-4 examples (one block, two blocks) and the empty message; 56 bytes straddle the padding
  // boundary (the length no longer fits in the same block), 64 bytes fill one block exactly.
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(sha256_hex(std::string(64, 'a')),
            "ffe054fe7ae0cb6dc65c3af9b61d5209f439851db43d0ba5997337df154668eb");
  EXPECT_EQ(sha256_hex(std::string(1000000, 'a')),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(CacheKey, PartsAreDelimited) {
  EXPECT_NE(cache_key({"ab", "c"}), cache_key({"a", "bc"}));
  EXPECT_EQ(cache_key({"x", "y"}), cache_key({"x", "y"}));
  EXPECT_EQ(cache_key({"x"}).size(), 64u);
}

TEST(DiskCache, StoresCountsAndSurvivesRestart) {
  std::string dir = test::scratch_dir("cache");
  std::string key = cache_key({"item", "1"});
  {
    DiskCache cache(dir);
    EXPECT_FALSE(cache.get(key).has_value());
    int computed = 0;
    std::string binary("a\0b\nc", 5);  // values are opaque bytes
    EXPECT_EQ(cache.get_or_compute(key,
                                   [&] {
                                     ++computed;
                                     return binary;
                                   }),
              binary);
    EXPECT_EQ(cache.get_or_compute(key,
                                   [&] {
                                     ++computed;
                                     return std::string("other");
                                   }),
              binary);
    EXPECT_EQ(computed, 1);
    EXPECT_EQ(cache.hits(), 1);
    EXPECT_EQ(cache.misses(), 2);
  }
  DiskCache again(dir);  // a new process, say
  ASSERT_TRUE(again.get(key).has_value());
  EXPECT_EQ(again.get(key)->size(), 5u);
  EXPECT_EQ(again.hits(), 2);
  EXPECT_EQ(again.misses(), 0);
  EXPECT_TRUE(fs::exists(again.entry_path(key)));
  EXPECT_EQ(fs::path(again.entry_path(key)).parent_path().filename().string(), key.substr(0, 2));
  fs::remove_all(dir);
}

TEST(DiskCache, DamagedOrPartialEntriesAreMisses) {
  std::string dir = test::scratch_dir("cache-damaged");
  DiskCache cache(dir);
  std::string key = cache_key({"damaged"});
  cache.put(key, "0123456789");
  // Truncate the entry as a crash of a non-atomic writer would: the size in the header no longer matches.
  std::string path = cache.entry_path(key);
  fs::resize_file(path, fs::file_size(path) - 3);
  EXPECT_FALSE(cache.get(key).has_value());
  test::write_text(path, "garbage");
  EXPECT_FALSE(cache.get(key).has_value());
  // A stray temporary file from a killed writer is not an entry.
  std::string other = cache_key({"other"});
  test::write_text(cache.entry_path(other) + ".tmp.123.0", "CSHCACHE1 1\nx");
  EXPECT_FALSE(cache.get(other).has_value());
  cache.put(key, "fixed");
  EXPECT_EQ(cache.get(key).value(), "fixed");
  fs::remove_all(dir);
}

TEST(DiskCache, JsonValuesRoundTripExactlyAndOtherBytesAreMisses) {
  std::string dir = test::scratch_dir("cache-json");
  DiskCache cache(dir);
  const std::string m = cache_key({"m"}), text = cache_key({"text"}), absent = cache_key({"absent"});
  Mesh mesh;
  mesh.V = Points::Random(7, 3);
  mesh.V(2, 1) = 1.0 / 3.0;
  mesh.F.resize(2, 3);
  mesh.F << 0, 1, 2, 4, 5, 6;
  cache.put_json(m, mesh_to_json(mesh));
  std::optional<nlohmann::json> hit = cache.get_json(m);
  ASSERT_TRUE(hit.has_value());
  const Mesh back = mesh_from_json(*hit);
  EXPECT_EQ(back.V, mesh.V);  // bit for bit
  EXPECT_EQ(back.F, mesh.F);
  EXPECT_EQ(points_from_json(points_to_json(mesh.V)), mesh.V);
  EXPECT_EQ(faces_from_json(faces_to_json(mesh.F)), mesh.F);
  EXPECT_THROW(points_from_json(nlohmann::json(std::vector<double>{1, 2})), Error);
  // A value that is not CBOR (an older entry's text) is a miss for get_json, which the caller recomputes.
  cache.put(text, "hausdorff 1 chamfer 2\n");
  EXPECT_FALSE(cache.get_json(text).has_value());
  EXPECT_FALSE(cache.get_json(absent).has_value());
  int calls = 0;
  auto compute = [&calls] {
    ++calls;
    return nlohmann::json{{"x", 1.5}};
  };
  EXPECT_EQ(cache.get_or_compute_json(text, compute)["x"], 1.5);
  EXPECT_EQ(cache.get_or_compute_json(text, compute)["x"], 1.5);
  EXPECT_EQ(calls, 1);
  std::filesystem::remove_all(dir);
}

// The bytes of a cache entry's file.
std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Replaces a file's bytes.
void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

// Changes the 8 bytes of the first CBOR float64 (major type 7, 0xfb) after `after` in the file, keeping its
// size: what a flipped disk block or a hostile edit does to a cached number.
void flip_first_double(const std::string& path, size_t after = 0) {
  std::string bytes = file_bytes(path);
  const size_t at = bytes.find('\xfb', after);
  ASSERT_NE(at, std::string::npos) << path;
  ASSERT_LE(at + 9, bytes.size());
  for (size_t k = at + 1; k < at + 9; ++k) bytes[k] = static_cast<char>(bytes[k] ^ 0x5a);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

// Collects what the caches report (set_cache_warning_sink) while in scope.
struct CapturedWarnings {
  std::vector<std::string> lines;
  CapturedWarnings() {
    set_cache_warning_sink([this](const std::string& line) { lines.push_back(line); });
  }
  ~CapturedWarnings() { set_cache_warning_sink({}); }
};

TEST(DiskCache, FlippedBytesInsideANumberAreNeverServed) {
  // Issue 22: 8 bytes flipped inside a float64 of a cached form were served as valid.
  const std::string dir = test::scratch_dir("cache-flipped");
  const DiskCache cache(dir);
  const std::string key = cache_key({"form"});
  const std::vector<double> X = {1.0 / 3.0, 2.5, -7.25, 1e-3};
  cache.put_json(key, nlohmann::json{{"X", X}});
  const std::string path = cache.entry_path(key);
  flip_first_double(path, file_bytes(path).find('\n'));
  EXPECT_EQ(fs::file_size(path), file_bytes(path).size());  // size and header intact: only a number changed
  CapturedWarnings warnings;
  EXPECT_FALSE(cache.get_json(key).has_value());
  EXPECT_EQ(cache.damaged(), 1);
  ASSERT_EQ(warnings.lines.size(), 1u);
  EXPECT_NE(warnings.lines[0].find(path), std::string::npos) << warnings.lines[0];
  EXPECT_NE(warnings.lines[0].find("checksum"), std::string::npos) << warnings.lines[0];
  EXPECT_FALSE(fs::exists(path));  // removed, so that the recomputed value takes its place
  // Recomputed through get_or_compute_json: the true value again.
  const nlohmann::json again = cache.get_or_compute_json(key, [&] { return nlohmann::json{{"X", X}}; });
  EXPECT_EQ(again["X"].get<std::vector<double>>(), X);
  EXPECT_EQ(cache.get_json(key).value()["X"].get<std::vector<double>>(), X);
  fs::remove_all(dir);
}

// Issue 57: an entry of the unchecked format 1 whose bytes were changed was still served. Older formats are
// never trusted: a miss (recomputed, rewritten in the current format), said once per cache.
TEST(DiskCache, EntriesOfFormatOneAreRecomputedNotTrusted) {
  const std::string dir = test::scratch_dir("cache-format1");
  const DiskCache cache(dir);
  const std::string a = cache_key({"a"}), b = cache_key({"b"});
  test::write_text(cache.entry_path(a), "CSHCACHE1 5\nhellO");  // changed bytes: nothing can tell
  test::write_text(cache.entry_path(b), "CSHCACHE1 3\nabc");
  CapturedWarnings warnings;
  EXPECT_FALSE(cache.get(a).has_value());
  EXPECT_FALSE(cache.get(b).has_value());
  EXPECT_EQ(cache.misses(), 2);
  ASSERT_EQ(warnings.lines.size(), 1u);
  EXPECT_NE(warnings.lines[0].find(dir), std::string::npos);
  EXPECT_NE(warnings.lines[0].find("recomputed"), std::string::npos) << warnings.lines[0];
  // The recomputed value replaces the entry in the current format, with its checksum, and is then served.
  EXPECT_EQ(cache.get_or_compute(a, [] { return std::string("hello"); }), "hello");
  const std::string bound = sha256_hex("cshapes-cache-entry;" + a + ";" + sha256_hex("hello"));
  EXPECT_EQ(file_bytes(cache.entry_path(a)).rfind("CSHCACHE3 5 " + bound + "\nhello", 0), 0u);
  EXPECT_EQ(cache.get(a).value(), "hello");
  fs::remove_all(dir);
}

// Issue 36: two canonical-form entries swapped on disk gave a permuted distance matrix with exit 0 (the
// checksum covered the value, not the key it was stored under). Swapped, copied or renamed entries are
// misses, reported and removed; each key then gets its own value again.
TEST(DiskCache, AnEntryUnderAnotherKeysNameIsAMiss) {
  const std::string dir = test::scratch_dir("cache-swapped");
  const DiskCache cache(dir);
  const std::string a = cache_key({"form", "a"}), b = cache_key({"form", "b"}), c = cache_key({"form", "c"});
  cache.put_json(a, nlohmann::json{{"X", {1.0, 2.0}}});
  cache.put_json(b, nlohmann::json{{"X", {3.0, 4.0}}});
  const std::string bytes_a = file_bytes(cache.entry_path(a)), bytes_b = file_bytes(cache.entry_path(b));
  write_bytes(cache.entry_path(a), bytes_b);  // swapped
  write_bytes(cache.entry_path(b), bytes_a);
  fs::create_directories(fs::path(cache.entry_path(c)).parent_path());
  fs::copy_file(cache.entry_path(a), cache.entry_path(c));  // copied under a third key
  CapturedWarnings warnings;
  EXPECT_FALSE(cache.get_json(a).has_value());
  EXPECT_FALSE(cache.get_json(b).has_value());
  EXPECT_FALSE(cache.get_json(c).has_value());
  EXPECT_EQ(cache.damaged(), 3);
  ASSERT_EQ(warnings.lines.size(), 3u);
  EXPECT_NE(warnings.lines[0].find(cache.entry_path(a)), std::string::npos) << warnings.lines[0];
  const nlohmann::json again = cache.get_or_compute_json(a, [] { return nlohmann::json{{"X", {1.0, 2.0}}}; });
  EXPECT_EQ(cache.get_json(a).value()["X"][1], 2.0);
  fs::remove_all(dir);
}

// Entries of format 2 (the value's checksum, not bound to its key) are misses too, said once per cache.
TEST(DiskCache, EntriesOfFormatTwoAreRecomputedNotTrusted) {
  const std::string dir = test::scratch_dir("cache-format2");
  const DiskCache cache(dir);
  const std::string a = cache_key({"a"});
  test::write_text(cache.entry_path(a), "CSHCACHE2 5 " + sha256_hex("hello") + "\nhello");
  CapturedWarnings warnings;
  EXPECT_FALSE(cache.get(a).has_value());
  EXPECT_FALSE(cache.get(a).has_value());
  ASSERT_EQ(warnings.lines.size(), 1u);
  EXPECT_NE(warnings.lines[0].find("older cache format"), std::string::npos) << warnings.lines[0];
  fs::remove_all(dir);
}

TEST(DiskCache, FailedWriteIsAWriteErrorNamingTheEntryAndTheReason) {
  // Issue 22: a cache that cannot be written must stop the run, not look like a failing shape.
  const std::string dir = test::scratch_dir("cache-full");
  const DiskCache cache(dir);
  const std::string key = cache_key({"full"});
  cache.put(cache_key({"before"}), "kept");
  fail_file_writes_for_testing(1);  // the disk is full from the next file on
  try {
    cache.put(key, std::string(100000, 'x'));
    ADD_FAILURE() << "no error";
  } catch (const WriteError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(cache.entry_path(key)), std::string::npos) << message;
    EXPECT_NE(message.find(std::strerror(ENOSPC)), std::string::npos) << message;
  }
  EXPECT_THROW(cache.put(cache_key({"next"}), "x"), WriteError);  // a full disk stays full
  fail_file_writes_for_testing(0);
  EXPECT_FALSE(fs::exists(cache.entry_path(key)));
  for (const auto& e : fs::recursive_directory_iterator(dir))  // no temporary file left behind
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();
  EXPECT_EQ(cache.get(cache_key({"before"})).value(), "kept");
  cache.put(key, "after");  // disarmed
  EXPECT_EQ(cache.get(key).value(), "after");

  // A cache folder that is a file: a WriteError naming the path, with the system's reason.
  const std::string file = dir + "/a-file";
  test::write_text(file, "x");
  const DiskCache not_a_folder(file);
  try {
    not_a_folder.put(key, "x");
    ADD_FAILURE() << "no error";
  } catch (const WriteError& e) {
    EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

TEST(DiskCache, DisabledCacheComputesEveryTime) {
  DiskCache cache;
  EXPECT_FALSE(cache.enabled());
  int computed = 0;
  cache.get_or_compute(cache_key({"k"}), [&] {
    ++computed;
    return std::string("v");
  });
  cache.get_or_compute(cache_key({"k"}), [&] {
    ++computed;
    return std::string("v");
  });
  EXPECT_EQ(computed, 2);
  EXPECT_EQ(cache.misses(), 2);
}

TEST(DiskCache, FileContentHashFollowsContentNotName) {
  std::string dir = test::scratch_dir("cache-hash");
  test::write_text(dir + "/a.off", "same");
  test::write_text(dir + "/b.off", "same");
  test::write_text(dir + "/c.off", "different");
  EXPECT_EQ(file_content_hash(dir + "/a.off"), file_content_hash(dir + "/b.off"));
  EXPECT_NE(file_content_hash(dir + "/a.off"), file_content_hash(dir + "/c.off"));
  EXPECT_THROW(file_content_hash(dir + "/missing.off"), Error);
  EXPECT_THROW(DiskCache(dir).entry_path("../escape"), Error);
  fs::remove_all(dir);
}

TEST(DiskCache, KeysListsTheEntries) {
  const std::string dir = test::scratch_dir("cache-keys");
  const DiskCache cache(dir);
  EXPECT_TRUE(cache.keys().empty());
  const std::string a = cache_key({"a"}), b = cache_key({"b"});
  cache.put(b, "2");
  cache.put(a, "1");
  // A writer's temporary file and a foreign file are not entries.
  std::ofstream(cache.entry_path(a) + ".tmp.host.1.0") << "half";
  std::ofstream(dir + "/README") << "x";
  std::vector<std::string> expected = {a, b};
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(cache.keys(), expected);
  EXPECT_TRUE(DiskCache("").keys().empty());
  fs::remove_all(dir);
}

}  // namespace cache_test
}  // namespace cshapes
