#include "python/progress.h"

#include <chrono>
#include <map>
#include <mutex>
#include <optional>

#include "cshapes/support/timing.h"
#include "python/interrupt.h"

namespace cshapes::python {

namespace py = pybind11;

namespace {
// At most ten calls a second: a bar stays smooth, and a callable that plots costs the computation little.
constexpr auto kReportInterval = std::chrono::milliseconds(100);
}  // namespace

struct PythonProgress::State {
  std::shared_ptr<py::object> callback;  // empty: only Ctrl-C is heard
  ProgressFn interrupt = stop_on_python_signals();
  std::mutex mutex;  // one report at a time, whichever thread sends it
  struct Stage {
    double fraction = -1;  // reported last
    WallClock::time_point start;
  };
  std::map<std::string, Stage> stages;  // by name: stages may interleave (an experiment's)
  std::string stage;                    // reported last
  WallClock::time_point last_call{};
  std::optional<py::error_already_set> error;  // what the callable raised (not KeyboardInterrupt)
};

PythonProgress::PythonProgress(const py::object& callback, const std::string& function)
    : state_(std::make_shared<State>()) {
  if (callback.is_none()) return;
  if (!PyCallable_Check(callback.ptr()))
    throw py::type_error(
        function + "(): progress: expected None, True, False or a function progress(stage, " +
        "fraction, seconds_left), got " + py::str(callback.get_type().attr("__name__")).cast<std::string>());
  // Its last reference may go where the GIL is not held (a copy of fn() in the library's options): the
  // deleter takes the GIL.
  state_->callback = std::shared_ptr<py::object>(new py::object(callback), [](py::object* o) {
    py::gil_scoped_acquire gil;
    delete o;
  });
}

ProgressFn PythonProgress::fn() const {
  return [state = state_](const std::string& stage, double done, double total) {
    state->interrupt(stage, done, total);
    if (!state->callback || stage.empty()) return;  // a poll (support/progress.h): nothing to report
    std::lock_guard<std::mutex> lock(state->mutex);
    if (state->error) throw Cancelled();  // the callable raised: every thread stops
    const auto now = WallClock::now();
    const double fraction = total > 0 ? std::min(1.0, std::max(0.0, done / total)) : 1.0;
    auto [it, first] = state->stages.try_emplace(stage, State::Stage{-1, now});
    State::Stage& s = it->second;
    if (s.fraction >= 1 && fraction < 1) s = State::Stage{-1, now};  // the stage runs again (another method)
    if (fraction <= s.fraction) return;                              // a report from a thread behind another
    const bool switched = stage != state->stage;
    if (!first && !switched && fraction < 1 && now - state->last_call < kReportInterval) return;  // too soon
    s.fraction = fraction;
    state->stage = stage;
    state->last_call = now;
    const double elapsed = std::chrono::duration<double>(now - s.start).count();
    const std::optional<double> left = seconds_left_estimate(elapsed, fraction);
    py::gil_scoped_acquire gil;
    try {
      (*state->callback)(stage, fraction, left ? py::object(py::float_(*left)) : py::object(py::none()));
    } catch (py::error_already_set& e) {
      if (!e.matches(PyExc_KeyboardInterrupt)) state->error.emplace(std::move(e));  // raised by run()
      throw Cancelled();
    }
  };
}

void PythonProgress::raise_callback_error() const {
  if (state_->error) {
    py::error_already_set error = std::move(*state_->error);
    state_->error.reset();
    throw error;
  }
}

}  // namespace cshapes::python
