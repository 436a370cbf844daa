#include "core/distance_matrix.h"

#include <cstdint>
#include <cstring>
#include <fstream>

#include "core/atomic_file.h"
#include "core/error.h"

namespace cshapes {

namespace {
constexpr char kMagic[8] = {'C', 'S', 'H', 'D', 'I', 'S', 'T', '1'};
}

double distance_matrix_bytes(Index n) { return 4.0 * static_cast<double>(n) * static_cast<double>(n); }

void require_memory(double bytes, const std::string& what) {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  double kib = 0;
  while (meminfo >> key) {
    if (key == "MemAvailable:") {
      meminfo >> kib;
      break;
    }
    meminfo.ignore(1 << 20, '\n');
  }
  if (kib <= 0) return;  // unknown: let the allocation decide
  double available = kib * 1024.0;
  if (bytes > 0.9 * available)
    fail(what, " needs ", bytes / 1e9, " GB but only ", available / 1e9, " GB of memory is available");
}

void write_distance_matrix(const std::string& path, const DistanceMatrix& D) {
  CSHAPES_REQUIRE(D.rows() == D.cols(), path, ": distance matrix must be square, got ", D.rows(), "x", D.cols());
  write_file_atomically(
      path,
      [&](std::ostream& out) {
        out.write(kMagic, 8);
        uint64_t n = D.rows();
        out.write(reinterpret_cast<const char*>(&n), 8);
        // Column-major storage of a symmetric matrix is also its row-major storage.
        out.write(reinterpret_cast<const char*>(D.data()), static_cast<std::streamsize>(4 * n * n));
      },
      true);
}

DistanceMatrix read_distance_matrix(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail_file(path, ": cannot open distance matrix");
  char magic[8];
  uint64_t n = 0;
  in.read(magic, 8);
  in.read(reinterpret_cast<char*>(&n), 8);
  if (!in || std::memcmp(magic, kMagic, 8) != 0)
    fail(path, ": not a cshapes distance matrix (expected the CSHDIST1 header)");
  in.seekg(0, std::ios::end);
  const double expected = 16.0 + distance_matrix_bytes(static_cast<Index>(n));
  if (static_cast<double>(in.tellg()) != expected)
    fail(path, ": truncated or oversized: header says n = ", n, " (", expected, " bytes), file has ",
         static_cast<double>(in.tellg()), " bytes");
  require_memory(distance_matrix_bytes(n), path);
  DistanceMatrix D(n, n);
  in.seekg(16);
  in.read(reinterpret_cast<char*>(D.data()), static_cast<std::streamsize>(4 * n * n));
  if (!in) fail(path, ": read error");
  // The file is row-major and Eigen column-major: transposing makes D(i, j) the file's entry (i, j).
  D.transposeInPlace();
  return D;
}

}  // namespace cshapes
