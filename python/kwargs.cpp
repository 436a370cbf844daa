#include "python/kwargs.h"

#include <cmath>

#include "core/error.h"

namespace cshapes::python {

py::object Kwargs::take(const std::string& name) {
  known_.insert(name);
  if (!given(name)) return py::none();
  return kwargs_[name.c_str()];
}

py::object Kwargs::object(const std::string& name) {
  return take(name);
}

double Kwargs::number(const std::string& name, double fallback) {
  py::object value = take(name);
  if (value.is_none()) return fallback;
  if (py::isinstance<py::bool_>(value) ||
      !(py::isinstance<py::float_>(value) || py::isinstance<py::int_>(value) ||
        py::hasattr(value, "__float__")))
    fail(function_, "(): ", name, ": expected a number, got ", py::repr(value).cast<std::string>());
  return value.cast<double>();
}

long long Kwargs::integer(const std::string& name, long long fallback, long long minimum, long long maximum) {
  py::object value = take(name);
  if (value.is_none()) return fallback;
  if (py::isinstance<py::bool_>(value) || !py::hasattr(value, "__index__"))
    fail(function_, "(): ", name, ": expected an integer, got ", py::repr(value).cast<std::string>());
  const py::object index = value.attr("__index__")();
  // Compared as Python integers: any size, no cast that could fail or wrap first.
  const bool below = index<py::int_(minimum), above = index> py::int_(maximum);
  if (below || above)
    fail(function_, "(): ", name, ": ", py::repr(index).cast<std::string>(),
         " is out of range, expected an integer ", below ? ">= " : "<= ", below ? minimum : maximum);
  return index.cast<long long>();
}

bool Kwargs::flag(const std::string& name, bool fallback) {
  py::object value = take(name);
  if (value.is_none()) return fallback;
  if (!py::isinstance<py::bool_>(value))
    fail(function_, "(): ", name, ": expected True or False, got ", py::repr(value).cast<std::string>());
  return value.cast<bool>();
}

std::string Kwargs::text(const std::string& name, const std::string& fallback) {
  py::object value = take(name);
  if (value.is_none()) return fallback;
  if (!py::isinstance<py::str>(value))
    fail(function_, "(): ", name, ": expected a string, got ", py::repr(value).cast<std::string>());
  return value.cast<std::string>();
}

void Kwargs::done() const {
  for (auto item : kwargs_) {
    const std::string name = item.first.cast<std::string>();
    if (known_.count(name)) continue;
    std::string list;
    for (const std::string& k : known_) list += (list.empty() ? "" : ", ") + k;
    throw py::type_error(function_ + "() got an unexpected keyword argument '" + name +
                         "'; its options: " + list);
  }
}

}  // namespace cshapes::python
