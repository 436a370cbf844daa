#include "cshapes/data/cache.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"

namespace cshapes {

namespace {

// Format 3 (current): "CSHCACHE3 <size> <checksum>\n" then the value, the checksum binding the value to
// the key it was stored under (entry_checksum): an entry copied, swapped or renamed to another key's file
// is a miss there, never another key's value. Format 2: "CSHCACHE2 <size> <sha256 of the value>\n" (value
// verified, key not), and format 1 (before checksums): "CSHCACHE1 <size>\n" then the value; both are misses
// (recomputed and rewritten), said once per cache.
constexpr const char* kMagic = "CSHCACHE3 ";
constexpr const char* kMagicOlder = "CSHCACHE";  // formats 1 and 2 share the prefix

// SHA-256 over the key and the value's SHA-256 (no copy of a large value is made).
std::string entry_checksum(const std::string& key, const std::string& value) {
  return sha256_hex("cshapes-cache-entry;" + key + ";" + sha256_hex(value));
}

std::mutex g_warning_mutex;
std::function<void(const std::string&)> g_warning_sink;

// The whole text as a decimal count; false for anything else.
bool parse_size(const std::string& text, unsigned long long& size) {
  if (text.empty() || !std::isdigit(static_cast<unsigned char>(text[0]))) return false;
  char* end = nullptr;
  errno = 0;
  size = std::strtoull(text.c_str(), &end, 10);
  return end && *end == '\0' && errno == 0;
}

}  // namespace

void cache_warning(const std::string& line) {
  std::lock_guard<std::mutex> lock(g_warning_mutex);
  if (g_warning_sink) g_warning_sink(line);
}

void set_cache_warning_sink(std::function<void(const std::string&)> sink) {
  std::lock_guard<std::mutex> lock(g_warning_mutex);
  g_warning_sink = std::move(sink);
}

std::string cache_key(const std::vector<std::string>& parts) {
  std::string joined;
  for (const std::string& p : parts) joined += std::to_string(p.size()) + ":" + p + ";";
  return sha256_hex(joined);
}

DiskCache::DiskCache(std::string directory) : directory_(std::move(directory)) {}

std::string DiskCache::entry_path(const std::string& key) const {
  CSHAPES_REQUIRE(key.size() >= 2 && key.find('/') == std::string::npos && key.find('.') == std::string::npos,
                  "cache key '", key, "' is not a hex digest (use cache_key)");
  return directory_ + "/" + key.substr(0, 2) + "/" + key + ".bin";
}

std::optional<std::string> DiskCache::get(const std::string& key) const {
  if (enabled()) {
    const std::string path = entry_path(key);
    std::ifstream in(path, std::ios::binary);
    if (in) {
      std::ostringstream buffer;
      buffer << in.rdbuf();
      std::string content = buffer.str();
      // Anything but a whole entry of a known format (a foreign, truncated or damaged file) is a miss.
      const size_t newline = content.find('\n');
      const std::string header = content.substr(0, newline == std::string::npos ? 0 : newline);
      const std::string magic = kMagic;
      unsigned long long size = 0;
      if (header.compare(0, magic.size(), magic) == 0) {
        const std::string fields = header.substr(magic.size());
        const size_t space = fields.find(' ');
        const std::string checksum = space == std::string::npos ? "" : fields.substr(space + 1);
        if (space != std::string::npos && parse_size(fields.substr(0, space), size) &&
            content.size() - newline - 1 == size && checksum.size() == 64) {
          std::string value = content.substr(newline + 1);
          if (entry_checksum(key, value) == checksum) {
            ++hits_;
            return value;
          }
          // Bytes changed after they were written, or the entry is another key's: never served. The entry
          // goes, so that the recomputed value replaces it (and a content-named entry, which is not
          // rewritten under its name, stops warning).
          ++damaged_;
          cache_warning("cache entry " + path +
                        ": content does not match its checksum (changed on disk, or another key's entry), "
                        "recomputing it");
          std::remove(path.c_str());
        }
      } else if (header.compare(0, std::string(kMagicOlder).size(), kMagicOlder) == 0) {
        // Formats 1 and 2 do not bind the value to its key (format 1 checks nothing): never trusted; the
        // recomputed value replaces the entry in the current format.
        if (!said_unverified_.exchange(true))
          cache_warning("cache " + directory_ +
                        ": entries of an older cache format (no checksum over their key) are recomputed");
      }
    }
  }
  ++misses_;
  return std::nullopt;
}

void DiskCache::put(const std::string& key, const std::string& value) const {
  if (!enabled()) return;
  const std::string checksum = entry_checksum(key, value);
  write_file_atomically(
      entry_path(key),
      [&](std::ostream& out) {
        out << kMagic << value.size() << ' ' << checksum << '\n';
        out.write(value.data(), static_cast<std::streamsize>(value.size()));
      },
      true);
}

std::vector<std::string> DiskCache::keys() const {
  std::vector<std::string> result;
  std::error_code ec;
  if (!enabled() || !std::filesystem::is_directory(directory_, ec)) return result;
  for (const auto& fan : std::filesystem::directory_iterator(directory_, ec)) {
    const std::string prefix = fan.path().filename().string();
    if (prefix.size() != 2 || !fan.is_directory(ec)) continue;
    for (const auto& entry : std::filesystem::directory_iterator(fan.path(), ec)) {
      const std::filesystem::path& p = entry.path();
      const std::string stem = p.stem().string();
      if (p.extension() == ".bin" && stem.compare(0, 2, prefix) == 0 && stem.find('.') == std::string::npos)
        result.push_back(stem);
    }
  }
  std::sort(result.begin(), result.end());
  return result;
}

std::string DiskCache::get_or_compute(const std::string& key,
                                      const std::function<std::string()>& compute) const {
  if (std::optional<std::string> cached = get(key)) return *cached;
  std::string value = compute();
  put(key, value);
  return value;
}

nlohmann::json points_to_json(const Points& X) {
  const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> rows = X;
  return std::vector<double>(rows.data(), rows.data() + rows.size());
}

Points points_from_json(const nlohmann::json& j) {
  const std::vector<double> flat = j.get<std::vector<double>>();
  CSHAPES_REQUIRE(flat.size() % 3 == 0, "cache entry: ", flat.size(), " coordinates, not a multiple of 3");
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      flat.data(), static_cast<Index>(flat.size() / 3), 3);
}

nlohmann::json faces_to_json(const Faces& F) {
  const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> rows = F;
  return std::vector<int>(rows.data(), rows.data() + rows.size());
}

Faces faces_from_json(const nlohmann::json& j) {
  const std::vector<int> flat = j.get<std::vector<int>>();
  CSHAPES_REQUIRE(flat.size() % 3 == 0, "cache entry: ", flat.size(), " face indices, not a multiple of 3");
  return Eigen::Map<const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      flat.data(), static_cast<Index>(flat.size() / 3), 3);
}

nlohmann::json mesh_to_json(const Mesh& mesh) {
  return {{"V", points_to_json(mesh.V)}, {"F", faces_to_json(mesh.F)}};
}

Mesh mesh_from_json(const nlohmann::json& j) {
  return Mesh{points_from_json(j.at("V")), faces_from_json(j.at("F"))};
}

std::optional<nlohmann::json> DiskCache::get_json(const std::string& key) const {
  std::optional<std::string> bytes = get(key);
  if (!bytes) return std::nullopt;
  nlohmann::json value = nlohmann::json::from_cbor(*bytes, true, false);  // discarded on any error
  if (value.is_discarded()) return std::nullopt;
  return value;
}

void DiskCache::put_json(const std::string& key, const nlohmann::json& value) const {
  if (!enabled()) return;
  const std::vector<std::uint8_t> bytes = nlohmann::json::to_cbor(value);
  put(key, std::string(bytes.begin(), bytes.end()));
}

nlohmann::json DiskCache::get_or_compute_json(const std::string& key,
                                              const std::function<nlohmann::json()>& compute) const {
  if (std::optional<nlohmann::json> cached = get_json(key)) return *cached;
  nlohmann::json value = compute();
  put_json(key, value);
  return value;
}

}  // namespace cshapes
