#include "cshapes/support/threads.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
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

namespace cshapes {

namespace {
std::atomic<int> g_thread_request{-1};  // -1: none recorded
}  // namespace

void set_thread_request(int requested) {
  g_thread_request.store(requested < 0 ? -1 : requested);
}

int refresh_threads() {
  const int requested = g_thread_request.load();
  if (requested < 0 || omp_in_parallel()) return omp_get_max_threads();
  const int threads = threads_for_computation(requested);
  omp_set_num_threads(threads);
  return threads;
}

}  // namespace cshapes
