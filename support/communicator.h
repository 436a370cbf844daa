// The processes of a distributed run, as the libraries see them: a rank among `size` ranks, a barrier, sums
// over ranks and a broadcast from rank 0. The one-process communicator (rank 0 of 1, every call a no-op) is
// the default everywhere, so code written for R ranks runs unchanged in one process; the MPI implementation
// lives in pipeline/distributed.h (the only code that sees MPI), this interface here so that every layer
// (eval's pair loop included) can split its work.
//
// Conventions: every call is collective (all ranks call it, in the same order); sums are element-wise over
// ranks, in rank order, and exact whenever at most one rank contributes a non-zero value per element (x + 0
// is x). The split helpers are pure functions of their arguments, so every rank computes the same split.
// Cost: one-process calls are free; the MPI ones are one MPI collective each (see pipeline/distributed.h).
// A Communicator is owned by whoever created it; the library functions only borrow it (a pointer in their
// options, nullptr meaning one process).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace cshapes {

class Communicator {
 public:
  virtual ~Communicator() = default;
  virtual int rank() const = 0;  // 0 .. size()−1; rank 0 writes every output
  virtual int size() const = 0;  // number of ranks, ≥ 1
  virtual void barrier() const = 0;
  // values[k] becomes the sum over ranks of values[k], on every rank.
  virtual void sum_to_all(double* values, size_t count) const = 0;
  virtual void sum_to_all(long* values, size_t count) const = 0;
  // The same, but only rank 0 receives the sums (the others' values are left unspecified).
  virtual void sum_to_root(double* values, size_t count) const = 0;
  // bytes becomes rank 0's bytes on every rank (any length).
  virtual void broadcast_from_root(std::string& bytes) const = 0;

  bool is_root() const { return rank() == 0; }
  long sum(long value) const {
    sum_to_all(&value, 1);
    return value;
  }
  // Whether any rank passes true (e.g. "I failed"): lets every rank stop together instead of leaving the
  // others waiting in the next collective call.
  bool any(bool flag) const { return sum(flag ? 1 : 0) > 0; }
};

// Rank 0 of 1: every collective returns at once and leaves the values as they are.
class SingleProcessCommunicator : public Communicator {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  void barrier() const override {}
  void sum_to_all(double*, size_t) const override {}
  void sum_to_all(long*, size_t) const override {}
  void sum_to_root(double*, size_t) const override {}
  void broadcast_from_root(std::string&) const override {}
};

// The communicator to use when a caller passes none: a SingleProcessCommunicator.
const Communicator& single_process();

// The half-open range [begin, end) of items 0..count−1 that `rank` of `ranks` takes when the items are split
// into contiguous blocks whose sizes differ by at most one (the first count % ranks blocks are one longer).
struct ItemRange {
  long begin = 0, end = 0;
};
ItemRange contiguous_share(long count, int ranks, int rank);

// Longest-processing-time-first: items sorted by decreasing cost (ties: lower index first), each given to the
// rank with the least total cost so far (ties: lower rank). Returns the owning rank of every item. Within 4/3
// of the best possible makespan [Graham 1969]. costs: ≥ 0.
std::vector<int> longest_first_owners(const std::vector<double>& costs, int ranks);

}  // namespace cshapes
