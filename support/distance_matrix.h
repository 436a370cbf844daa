// All-pairs distance matrices (geodesic distances for MDS) and their binary file format.
//
// File format (.bin), little endian:
//   bytes 0-7    magic "CSHDIST1"
//   bytes 8-15   n, uint64
//   then n×n float32, row-major: entry (i, j) at offset 16 + 4·(i·n + j)
// The matrix is symmetric with a zero diagonal; infinity marks unreachable pairs (disconnected meshes).
#pragma once

#include <cmath>
#include <string>

#include "cshapes/support/types.h"

namespace cshapes {

// n×n single precision (22,738 vertices: 2.07 GB). Symmetric, so storage order does not matter.
using DistanceMatrix = Eigen::MatrixXf;

// An n×n matrix with its entries not yet written, its memory advised for transparent huge pages (Linux;
// elsewhere a plain allocation). Every pass of SMACOF and classical MDS streams the whole matrix: with 4 KiB
// pages each row of a tile is a TLB miss at the matrices' sizes (tens of MB and up), with 2 MiB pages almost
// none (SMACOF at 3,505 points: 10-20% per iteration). Write the entries after the call: the advice applies to
// pages not yet touched.
DistanceMatrix uninitialized_distance_matrix(Index rows, Index cols);

void write_distance_matrix(const std::string& path, const DistanceMatrix& D);  // atomic (temp + rename)
DistanceMatrix read_distance_matrix(const std::string& path);

// Bytes needed for an n×n float matrix.
double distance_matrix_bytes(Index n);
// Throws, with the figures and the rule that limits, when `bytes` (for `what`) exceed the memory this process
// can still take: the machine's (MemAvailable), its address-space limit (RLIMIT_AS, `ulimit -v`) less what it
// maps, and its control group's limit (cgroup v2 memory.max, v1 memory.limit_in_bytes) less the group's use.
void require_memory(double bytes, const std::string& what);
// The memory this process can still take by the rules require_memory applies, in bytes; < 0 when unknown.
double available_memory_bytes();
// The control-group part of require_memory, on the files given (require_memory reads /proc/self/cgroup and
// /sys/fs/cgroup; tests give a fake tree): the least room in bytes over the process's groups and each group
// above them, limit less use (< 0: no limit found), and in `rule` the file that sets it.
double control_group_memory_room(const std::string& proc_cgroup, const std::string& cgroup_root,
                                 std::string* rule = nullptr);

// What an invalid entry D(i, j) means, as a suffix for an error message: for an infinite entry, whether
// the two points are connected through a third point at finite distance from both (then the distance
// computation failed) or not (a disconnected mesh); empty for other values (negative, NaN).
template <class Matrix>
std::string bad_distance_hint(const Matrix& D, Index i, Index j) {
  const double value = static_cast<double>(D(i, j));
  if (!std::isinf(value)) return "";
  for (Index k = 0; k < D.rows(); ++k)
    if (std::isfinite(static_cast<double>(D(k, i))) && std::isfinite(static_cast<double>(D(k, j))))
      return " (both points are at finite distances from point " + std::to_string(k) +
             ", so they are connected: the distance computation failed; try another geodesic method, "
             "e.g. --method fmm)";
  return " (an infinite distance means a disconnected mesh: keep its largest component)";
}

}  // namespace cshapes
