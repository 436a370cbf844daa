#include "python/interrupt.h"

#include <pybind11/pybind11.h>

#include <thread>

namespace cshapes::python {

namespace py = pybind11;

ProgressFn stop_on_python_signals() {
  const std::thread::id caller = std::this_thread::get_id();
  return [caller](const std::string&, double, double) {
    if (std::this_thread::get_id() != caller) return;
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
  };
}

}  // namespace cshapes::python
