#include "cshapes/support/communicator.h"

#include <algorithm>
#include <numeric>

#include "cshapes/support/error.h"

namespace cshapes {

const Communicator& single_process() {
  static const SingleProcessCommunicator one;
  return one;
}

ItemRange contiguous_share(long count, int ranks, int rank) {
  CSHAPES_REQUIRE(count >= 0 && ranks >= 1 && rank >= 0 && rank < ranks, "contiguous_share: count ", count,
                  ", rank ", rank, " of ", ranks);
  const long base = count / ranks, extra = count % ranks;
  const long begin = rank * base + std::min<long>(rank, extra);
  return {begin, begin + base + (rank < extra ? 1 : 0)};
}

std::vector<int> longest_first_owners(const std::vector<double>& costs, int ranks) {
  CSHAPES_REQUIRE(ranks >= 1, "longest_first_owners: ", ranks, " ranks");
  std::vector<size_t> order(costs.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return costs[a] > costs[b]; });
  std::vector<double> load(static_cast<size_t>(ranks), 0.0);
  std::vector<int> owner(costs.size(), 0);
  for (size_t item : order) {
    CSHAPES_REQUIRE(costs[item] >= 0, "longest_first_owners: negative cost of item ", item);
    const int least = static_cast<int>(std::min_element(load.begin(), load.end()) - load.begin());
    owner[item] = least;
    load[static_cast<size_t>(least)] += costs[item];
  }
  return owner;
}

}  // namespace cshapes
