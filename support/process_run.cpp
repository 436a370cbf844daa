#include "cshapes/support/process_run.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <thread>

#include "cshapes/support/error.h"
#include "cshapes/support/timing.h"

namespace cshapes {

ProcessRun run_process(const std::string& command, const std::string& out_path, const std::string& err_path,
                       double timeout_seconds, const ProgressFn& progress, const std::string& stage,
                       const std::string& where) {
  const auto start = WallClock::now();
  const pid_t pid = fork();
  CSHAPES_REQUIRE(pid >= 0, where, ": cannot start the command: ", std::strerror(errno));
  if (pid == 0) {  // the child: only async-signal-safe calls until exec
    setpgid(0, 0);
    const int out = open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int in = open("/dev/null", O_RDONLY);
    if (out < 0 || err < 0 || in < 0) _exit(126);
    dup2(in, 0);
    dup2(out, 1);
    dup2(err, 2);
    execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  setpgid(pid, pid);  // also here: whichever runs first
  ProcessRun run;
  struct rusage& usage = run.usage;
  int& status = run.status;
  bool& timed_out = run.timed_out;
  auto kill_group = [pid] {
    killpg(pid, SIGTERM);
    for (int k = 0; k < 100; ++k) {  // two seconds to end, then killed
      if (waitpid(pid, nullptr, WNOHANG) == pid) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    killpg(pid, SIGKILL);
    waitpid(pid, nullptr, 0);
  };
  try {
    for (int k = 0;; ++k) {
      const pid_t done = wait4(pid, &status, WNOHANG, &usage);
      if (done == pid) break;
      CSHAPES_REQUIRE(done == 0 || errno == EINTR, where, ": waiting for the command: ", std::strerror(errno));
      if (seconds_since(start) > timeout_seconds) {
        timed_out = true;
        kill_group();
        break;
      }
      if (progress && k % 5 == 0) progress(stage, 0, 1);  // a stop throws here
      std::this_thread::sleep_for(std::chrono::milliseconds(k < 50 ? 2 : 20));
    }
  } catch (...) {
    kill_group();
    throw;
  }
  // The program's own processes may outlive the shell: none is left behind.
  killpg(pid, SIGKILL);
  run.seconds = seconds_since(start);
  return run;
}

}  // namespace cshapes
