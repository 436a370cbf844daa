#include "core/threads.h"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstdlib>
#include <fstream>
#include <thread>

namespace cshapes {

int busy_cores(int samples) {
  int least = INT_MAX;
  for (int k = 0; k < std::max(1, samples); ++k) {
    if (k) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    std::ifstream loadavg("/proc/loadavg");
    double one, five, fifteen;
    int running = 0;
    if (!(loadavg >> one >> five >> fifteen >> running) || running < 1) return 0;
    least = std::min(least, running - 1);
  }
  return least;
}

int threads_for_computation(int requested, int samples, const std::function<void(const std::string&)>& warn) {
  const int cores = std::max(1, omp_get_num_procs());
  int wanted = requested > 0 ? requested : omp_get_max_threads();
  if (wanted > 4 * cores) {
    if (warn)
      warn(std::to_string(wanted) + " is more than 4 per core (" + std::to_string(cores) + " cores); using " +
           std::to_string(4 * cores));
    wanted = 4 * cores;
  }
  const char* exact = std::getenv("CSHAPES_EXACT_THREADS");
  const int busy = exact && *exact && std::string(exact) != "0" ? 0 : busy_cores(samples);
  if (busy > 0 && wanted + busy > cores) wanted = std::max(1, std::min(wanted, cores - busy));
  return wanted;
}

}  // namespace cshapes
