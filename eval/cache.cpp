#include "eval/cache.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"

namespace cshapes {

namespace {

// FIPS 180-4, §4.2.2: the first 32 bits of the fractional parts of the cube roots of the first 64 primes.
constexpr std::array<uint32_t, 64> kRound = {
    0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4, 0xab1c5ed5,
    0xd807aa98, 0x12835b01, 0x243185be, 0x550c7dc3, 0x72be5d74, 0x80deb1fe, 0x9bdc06a7, 0xc19bf174,
    0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f, 0x4a7484aa, 0x5cb0a9dc, 0x76f988da,
    0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7, 0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967,
    0x27b70a85, 0x2e1b2138, 0x4d2c6dfc, 0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85,
    0xa2bfe8a1, 0xa81a664b, 0xc24b8b70, 0xc76c51a3, 0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070,
    0x19a4c116, 0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f, 0x682e6ff3,
    0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7, 0xc67178f2};

uint32_t rotr(uint32_t x, int n) {
  return (x >> n) | (x << (32 - n));
}

void compress(std::array<uint32_t, 8>& h, const unsigned char* block) {
  uint32_t w[64];
  for (int t = 0; t < 16; ++t)
    w[t] = (uint32_t(block[4 * t]) << 24) | (uint32_t(block[4 * t + 1]) << 16) |
           (uint32_t(block[4 * t + 2]) << 8) | uint32_t(block[4 * t + 3]);
  for (int t = 16; t < 64; ++t) {
    uint32_t s0 = rotr(w[t - 15], 7) ^ rotr(w[t - 15], 18) ^ (w[t - 15] >> 3);
    uint32_t s1 = rotr(w[t - 2], 17) ^ rotr(w[t - 2], 19) ^ (w[t - 2] >> 10);
    w[t] = w[t - 16] + s0 + w[t - 7] + s1;
  }
  uint32_t a = h[0], b = h[1], c = h[2], d = h[3], e = h[4], f = h[5], g = h[6], k = h[7];
  for (int t = 0; t < 64; ++t) {
    uint32_t t1 = k + (rotr(e, 6) ^ rotr(e, 11) ^ rotr(e, 25)) + ((e & f) ^ (~e & g)) + kRound[t] + w[t];
    uint32_t t2 = (rotr(a, 2) ^ rotr(a, 13) ^ rotr(a, 22)) + ((a & b) ^ (a & c) ^ (b & c));
    k = g;
    g = f;
    f = e;
    e = d + t1;
    d = c;
    c = b;
    b = a;
    a = t1 + t2;
  }
  h[0] += a;
  h[1] += b;
  h[2] += c;
  h[3] += d;
  h[4] += e;
  h[5] += f;
  h[6] += g;
  h[7] += k;
}

// Format 2 (current): "CSHCACHE2 <size> <sha256 of the value>\n" then the value. Format 1 (before
// checksums): "CSHCACHE1 <size>\n" then the value; still read, unverified.
constexpr const char* kMagic = "CSHCACHE2 ";
constexpr const char* kMagicUnverified = "CSHCACHE1 ";

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

std::string sha256_hex(const std::string& bytes) {
  // §5.3.3: the initial hash value.
  std::array<uint32_t, 8> h = {0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a,
                               0x510e527f, 0x9b05688c, 0x1f83d9ab, 0x5be0cd19};
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const size_t n = bytes.size();
  size_t full = n / 64 * 64;
  for (size_t off = 0; off < full; off += 64) compress(h, data + off);
  // §5.1.1 padding: a 1 bit, zeros, the message length in bits as 64-bit big endian.
  unsigned char tail[128] = {};
  size_t rest = n - full;
  for (size_t i = 0; i < rest; ++i) tail[i] = data[full + i];
  tail[rest] = 0x80;
  size_t tail_len = rest + 1 + 8 <= 64 ? 64 : 128;
  uint64_t bits = static_cast<uint64_t>(n) * 8;
  for (int i = 0; i < 8; ++i) tail[tail_len - 1 - i] = static_cast<unsigned char>(bits >> (8 * i));
  for (size_t off = 0; off < tail_len; off += 64) compress(h, tail + off);
  char hex[65];
  for (int i = 0; i < 8; ++i) std::snprintf(hex + 8 * i, 9, "%08x", h[i]);
  return std::string(hex, 64);
}

std::string file_content_hash(const std::string& path) {
  return sha256_hex(read_file(path));
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
      const std::string magic = kMagic, unverified = kMagicUnverified;
      unsigned long long size = 0;
      if (header.compare(0, magic.size(), magic) == 0) {
        const std::string fields = header.substr(magic.size());
        const size_t space = fields.find(' ');
        const std::string checksum = space == std::string::npos ? "" : fields.substr(space + 1);
        if (space != std::string::npos && parse_size(fields.substr(0, space), size) &&
            content.size() - newline - 1 == size && checksum.size() == 64) {
          std::string value = content.substr(newline + 1);
          if (sha256_hex(value) == checksum) {
            ++hits_;
            return value;
          }
          // Bytes changed after they were written: never served. The entry goes, so that the recomputed
          // value replaces it (and a content-named entry, which is not rewritten under its name, stops
          // warning).
          ++damaged_;
          cache_warning("cache entry " + path +
                        ": content does not match its checksum (changed on disk), recomputing it");
          std::remove(path.c_str());
        }
      } else if (header.compare(0, unverified.size(), unverified) == 0 &&
                 parse_size(header.substr(unverified.size()), size) && content.size() - newline - 1 == size) {
        if (!said_unverified_.exchange(true))
          cache_warning("cache " + directory_ +
                        ": reading entries written before checksums (cache format 1) unverified; delete the "
                        "folder to recompute them");
        ++hits_;
        return content.substr(newline + 1);
      }
    }
  }
  ++misses_;
  return std::nullopt;
}

void DiskCache::put(const std::string& key, const std::string& value) const {
  if (!enabled()) return;
  const std::string checksum = sha256_hex(value);
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
