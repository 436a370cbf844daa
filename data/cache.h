// A content-addressed on-disk cache for results that are expensive to recompute (canonical forms,
// alignments, distances), so that a killed run restarts where it stopped and never computes a cached item
// twice.
//
// Keys are SHA-256 hex digests of everything the result depends on: the input files' CONTENT (not their
// names or dates: content_hash / file_content_hash) and a canonical option string (e.g. to_key_string of
// the options). Values are opaque bytes.
//
// Values: every cshapes cache stores CBOR-encoded JSON through get_json/put_json (compact, exact for doubles,
// readable by any CBOR tool); get/put move the raw bytes.
//
// Layout: DIR/ab/abcdef….bin, one file per entry (the first two hex digits fan out the directory), each
// "CSHCACHE3 <size> <checksum>\n" followed by the value, the checksum a SHA-256 over the entry's key and
// the value's SHA-256: an entry copied, swapped or renamed under another key's name is a miss there.
// Entries are written to a temporary file and renamed, so an entry exists completely or not at all: a
// process killed mid-write leaves at most a stray "*.tmp.*" file, which is ignored. An entry whose header
// does not match its size is treated as missing and rewritten. Every read verifies the checksum: an entry
// whose bytes changed after they were written is never served; it is removed, counted (damaged()), reported
// through the warning sink naming the entry's file, and the caller recomputes it. Entries of format 2
// ("CSHCACHE2 <size> <SHA-256 of the value>\n": the value verified, not its key) and of format 1 ("CSHCACHE1
// <size>\n", before checksums) are never served: they are misses, recomputed and rewritten in the current
// format, said once per DiskCache through the sink.
//
// A write that fails (full disk, read-only folder, a cache folder that is a file) throws cshapes::WriteError
// (support/error.h) with the path and the system's reason: callers that skip a failing item must rethrow it.
// Safe for concurrent readers and writers (threads or processes): the last rename wins, with equal content.
#pragma once

#include <atomic>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cshapes/mesh/mesh.h"
#include "cshapes/support/sha256.h"

namespace cshapes {

// Cache values of the common types, as JSON (rows of coordinates flattened row-major).
nlohmann::json points_to_json(const Points& X);
Points points_from_json(const nlohmann::json& j);  // throws on a malformed value
nlohmann::json faces_to_json(const Faces& F);
Faces faces_from_json(const nlohmann::json& j);  // throws on a malformed value
nlohmann::json mesh_to_json(const Mesh& mesh);   // {"V": [...], "F": [...]}
Mesh mesh_from_json(const nlohmann::json& j);    // throws on a malformed value

// sha256_hex and file_content_hash: support/sha256.h.
// A key from several parts, each length-prefixed so that ("ab", "c") and ("a", "bc") differ.
std::string cache_key(const std::vector<std::string>& parts);

// Where the caches' warnings go (a damaged entry, entries of an older format), for every DiskCache of the
// process; none by default. The CLI and the Python module print them. Thread-safe.
void set_cache_warning_sink(std::function<void(const std::string&)> sink);
// Sends one line to that sink (for the caches built on DiskCache, e.g. the pair packs).
void cache_warning(const std::string& line);

class DiskCache {
 public:
  // directory: where entries live (created on first write). Empty: a disabled cache, every get() a miss
  // and put() a no-op, so callers need no second code path.
  explicit DiskCache(std::string directory = "");

  bool enabled() const { return !directory_.empty(); }
  const std::string& directory() const { return directory_; }
  // The file an entry lives in.
  std::string entry_path(const std::string& key) const;

  // The value stored under key, counting a hit; or nothing, counting a miss.
  std::optional<std::string> get(const std::string& key) const;
  // Stores atomically (temp file + rename), with the value's checksum. Throws cshapes::WriteError on I/O
  // failure.
  void put(const std::string& key, const std::string& value) const;
  // get(), or compute() then put(): compute runs only on a miss.
  std::string get_or_compute(const std::string& key, const std::function<std::string()>& compute) const;

  // The value under key decoded from CBOR; nothing when missing or not CBOR (an entry of an older format:
  // the caller recomputes and overwrites it).
  std::optional<nlohmann::json> get_json(const std::string& key) const;
  // Stores value as CBOR, atomically.
  void put_json(const std::string& key, const nlohmann::json& value) const;
  // get_json(), or compute() then put_json().
  nlohmann::json get_or_compute_json(const std::string& key,
                                     const std::function<nlohmann::json()>& compute) const;

  // The keys of the entries present, sorted (a writer's temporary files are not entries). Empty for a
  // disabled cache or a missing directory. Cost: one listing of the directory and its fan-out folders.
  std::vector<std::string> keys() const;

  long hits() const { return hits_; }
  long misses() const { return misses_; }
  // Entries whose checksum did not match their content (each removed and reported).
  long damaged() const { return damaged_; }

 private:
  std::string directory_;
  mutable std::atomic<long> hits_{0};
  mutable std::atomic<long> misses_{0};
  mutable std::atomic<long> damaged_{0};
  mutable std::atomic<bool> said_unverified_{false};
};

}  // namespace cshapes
