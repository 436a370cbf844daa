// How many OpenMP threads a computation should use, for every front end (the CLI once per process, the
// Python module per call).
//
// Every parallel loop ends at a barrier, so one thread that shares its core with another busy process holds
// all the others back: with a core busy, two threads can take many times longer than one, and libgomp's
// default spinning between loops makes it worse (measured in docs/cli.md, "Threads"). So: the
// requested count (0: OpenMP's default), at most 4 per core, and no more than the cores that other runnable
// tasks leave idle (/proc/loadavg), unless CSHAPES_EXACT_THREADS is set (to anything but 0).
#pragma once

#include <functional>
#include <string>

namespace cshapes {

// libgomp's spin before a waiting thread sleeps, as the front ends set it (GOMP_SPINCOUNT) when the user
// did not choose (OMP_WAIT_POLICY or GOMP_SPINCOUNT): the measured middle between spinning and sleeping.
inline constexpr const char* kGompSpinCount = "1000";

// Other runnable tasks right now: /proc/loadavg's "running/total" counts every runnable thread on the
// machine, the caller included (so one less). The least of `samples` reads 1 ms apart, so a task that only
// runs for an instant does not count. 0 when unknown.
int busy_cores(int samples = 3);

// The thread count as described above. warn: told "N is more than 4 per core (C cores); using 4C" when the
// request is above that.
int threads_for_computation(int requested, int samples = 3,
                            const std::function<void(const std::string&)>& warn = {});

// Threads that follow the machine during a long run. A front end records its request once
// (set_thread_request: the CLI after parsing, the Python module at each call); the library calls
// refresh_threads() between stages and blocks of work (before each canonical form, each block of ICP pairs),
// which chooses the count again from the load at that moment (threads_for_computation) and sets it for later
// parallel regions. Every result is the same for any thread count, so choosing again changes timings only.
// Without a recorded request refresh_threads() changes nothing (library users keep OpenMP's setting).
// requested: 0 for OpenMP's default count, a negative value to forget the request.
void set_thread_request(int requested);
// The count for the next block of work (also set with omp_set_num_threads); inside a parallel region, or
// without a request, the current count unchanged.
int refresh_threads();

}  // namespace cshapes
