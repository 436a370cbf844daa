#include "cshapes/support/distance_matrix.h"

#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"

namespace cshapes {

namespace {
constexpr char kMagic[8] = {'C', 'S', 'H', 'D', 'I', 'S', 'T', '1'};
}

DistanceMatrix uninitialized_distance_matrix(Index rows, Index cols) {
  DistanceMatrix D(rows, cols);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  // Only the 2 MiB-aligned interior can be huge pages; smaller matrices gain nothing.
  constexpr uintptr_t kHuge = uintptr_t(1) << 21;
  const uintptr_t begin = reinterpret_cast<uintptr_t>(D.data());
  const uintptr_t end = begin + sizeof(float) * static_cast<uintptr_t>(D.size());
  const uintptr_t first = (begin + kHuge - 1) & ~(kHuge - 1), last = end & ~(kHuge - 1);
  if (last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);  // advice only
#endif
  return D;
}

double distance_matrix_bytes(Index n) {
  return 4.0 * static_cast<double>(n) * static_cast<double>(n);
}

namespace {

// A number read from a one-line file (a cgroup's memory.max, ...); false when absent or not a number ("max").
bool read_number(const std::string& path, double& value) {
  std::ifstream in(path);
  std::string text;
  if (!(in >> text) || text.empty() || !std::isdigit(static_cast<unsigned char>(text[0]))) return false;
  value = std::strtod(text.c_str(), nullptr);
  return true;
}

// What memory the process may still take, the smallest of what each rule allows, with the rule's name.
struct MemoryRoom {
  double bytes = -1;  // < 0: unknown
  std::string rule;
  void limit(double room, const std::string& name) {
    if (room < 0) room = 0;
    if (bytes < 0 || room < bytes) {
      bytes = room;
      rule = name;
    }
  }
};

MemoryRoom memory_room() {
  MemoryRoom room;
  // The machine: MemAvailable.
  {
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
    if (kib > 0) room.limit(kib * 1024.0, "of memory is available");
  }
  // The process: its address-space limit (ulimit -v) less what it has mapped already.
  struct rlimit as {};
  if (::getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) {
    std::ifstream statm("/proc/self/statm");
    double pages = 0;
    statm >> pages;
    room.limit(static_cast<double>(as.rlim_cur) - pages * static_cast<double>(::sysconf(_SC_PAGESIZE)),
               "is available under the process's address-space limit (ulimit -v, RLIMIT_AS)");
  }
  // Its control group (a container's or a systemd unit's limit).
  std::string rule;
  const double group_room = control_group_memory_room("/proc/self/cgroup", "/sys/fs/cgroup", &rule);
  if (group_room >= 0) room.limit(group_room, rule);
  return room;
}

}  // namespace

// cgroup v2 memory.max, v1 memory.limit_in_bytes, less the group's usage; the group's folder and each one
// above it.
double control_group_memory_room(const std::string& proc_cgroup, const std::string& cgroup_root,
                                 std::string* rule) {
  MemoryRoom room;
  std::ifstream cgroups(proc_cgroup);
  for (std::string line; std::getline(cgroups, line);) {
    const size_t first = line.find(':'), second = line.find(':', first + 1);
    if (first == std::string::npos || second == std::string::npos) continue;
    const std::string controllers = line.substr(first + 1, second - first - 1);
    const bool v2 = line.compare(0, first, "0") == 0 && controllers.empty();
    if (!v2 && controllers.find("memory") == std::string::npos) continue;
    std::string group = line.substr(second + 1);
    const std::vector<std::string> roots =
        v2 ? std::vector<std::string>{cgroup_root, cgroup_root + "/unified"}
           : std::vector<std::string>{cgroup_root + "/memory"};
    const std::string max_file = v2 ? "/memory.max" : "/memory.limit_in_bytes";
    const std::string used_file = v2 ? "/memory.current" : "/memory.usage_in_bytes";
    while (true) {
      for (const std::string& root : roots) {
        double limit = 0, used = 0;
        const std::string folder = root + (group == "/" ? "" : group);
        // v1 reports "no limit" as a huge number: beyond 2^60 bytes it means none.
        if (read_number(folder + max_file, limit) && limit < 1e18) {
          if (!read_number(folder + used_file, used)) used = 0;
          room.limit(limit - used,
                     "is available under the control group's memory limit (" + folder + max_file + ")");
        }
      }
      if (group.empty() || group == "/") break;
      const size_t slash = group.find_last_of('/');
      group = slash == 0 || slash == std::string::npos ? "/" : group.substr(0, slash);
    }
  }
  if (rule) *rule = room.rule;
  return room.bytes;
}

double available_memory_bytes() { return memory_room().bytes; }

void require_memory(double bytes, const std::string& what) {
  const MemoryRoom room = memory_room();
  if (room.bytes < 0) return;  // unknown: let the allocation decide
  if (bytes > 0.9 * room.bytes)
    fail(what, " needs ", bytes / 1e9, " GB but only ", room.bytes / 1e9, " GB ", room.rule);
}

void write_distance_matrix(const std::string& path, const DistanceMatrix& D) {
  CSHAPES_REQUIRE(D.rows() == D.cols(), path, ": distance matrix must be square, got ", D.rows(), "x",
                  D.cols());
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
  // The declared size is checked before it sizes anything: a negative n (-600 read as 2^64 - 600) passed
  // the file-size check after the cast to Index and ended in an unnamed "out of memory".
  constexpr uint64_t kMaxPoints = uint64_t{1} << 31;  // 4·n² bytes far beyond any memory, still exact
  if (n > kMaxPoints)
    fail(path, ": header says n = ",
         static_cast<int64_t>(n) < 0 ? std::to_string(static_cast<int64_t>(n)) : std::to_string(n),
         ", expected a point count from 0 to ", kMaxPoints);
  in.seekg(0, std::ios::end);
  const double expected = 16.0 + distance_matrix_bytes(static_cast<Index>(n));
  if (static_cast<double>(in.tellg()) != expected)
    fail(path, ": truncated or oversized: header says n = ", n, " (", expected, " bytes), file has ",
         static_cast<double>(in.tellg()), " bytes");
  require_memory(distance_matrix_bytes(n), path);
  DistanceMatrix D = uninitialized_distance_matrix(static_cast<Index>(n), static_cast<Index>(n));
  in.seekg(16);
  in.read(reinterpret_cast<char*>(D.data()), static_cast<std::streamsize>(4 * n * n));
  if (!in) fail(path, ": read error");
  // The file is row-major and Eigen column-major: transposing makes D(i, j) the file's entry (i, j).
  D.transposeInPlace();
  return D;
}

}  // namespace cshapes
