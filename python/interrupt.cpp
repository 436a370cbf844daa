#include "python/interrupt.h"

#include <atomic>
#include <csignal>
#include <mutex>

namespace cshapes::python {

namespace {

std::atomic<bool> interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the flag is set from a signal handler");
struct sigaction previous;  // Python's handler while a scope is open
bool installed = false;
int depth = 0;
std::mutex scopes;

void on_sigint(int signal_number) {
  interrupted.store(true);
  if (!(previous.sa_flags & SA_SIGINFO) && previous.sa_handler != SIG_DFL && previous.sa_handler != SIG_IGN)
    previous.sa_handler(signal_number);
}

}  // namespace

InterruptScope::InterruptScope() {
  std::lock_guard<std::mutex> lock(scopes);
  if (depth++ > 0) return;
  interrupted.store(false);
  struct sigaction current {};
  if (sigaction(SIGINT, nullptr, &current) != 0) return;
  // Only in front of a handler function (Python's): SIG_IGN and SIG_DFL keep their meaning.
  if ((current.sa_flags & SA_SIGINFO) || current.sa_handler == SIG_DFL || current.sa_handler == SIG_IGN)
    return;
  struct sigaction ours {};
  ours.sa_handler = on_sigint;
  sigemptyset(&ours.sa_mask);
  ours.sa_flags = 0;
  previous = current;
  installed = sigaction(SIGINT, &ours, nullptr) == 0;
}

InterruptScope::~InterruptScope() {
  std::lock_guard<std::mutex> lock(scopes);
  if (--depth > 0) return;
  if (installed) sigaction(SIGINT, &previous, nullptr);
  installed = false;
}

ProgressFn stop_on_python_signals() {
  return [](const std::string&, double, double) {
    if (interrupted.load()) throw Cancelled();
  };
}

}  // namespace cshapes::python
