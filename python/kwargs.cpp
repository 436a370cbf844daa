#include "python/kwargs.h"

#include <algorithm>
#include <cmath>

#include "cshapes/pipeline/method_options.h"
#include "cshapes/pipeline/renamed_options.h"
#include "cshapes/support/error.h"

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

double Kwargs::number(const std::string& name, double fallback, const Limit& limit) {
  const double value = number(name, fallback);
  if (given(name) && !limit.holds(value))
    fail(function_, "(): ", name, ": expected ", limit.describe(), ", got ", format_limit_number(value));
  return value;
}

int Kwargs::int32(const std::string& name, int fallback, const Limit& limit) {
  py::object value = take(name);
  if (value.is_none()) return fallback;
  if (py::isinstance<py::bool_>(value) || !py::hasattr(value, "__index__"))
    fail(function_, "(): ", name, ": expected ", limit.describe(), ", got ",
         py::repr(value).cast<std::string>());
  const py::object index = value.attr("__index__")();
  // Compared as Python integers (2**70 too): refused in the limit's words, never wrapped or cast first.
  const long long minimum =
      std::isfinite(limit.minimum) ? static_cast<long long>(std::ceil(limit.minimum)) : INT_MIN;
  const long long maximum =
      std::isfinite(limit.maximum) ? static_cast<long long>(std::floor(limit.maximum)) : INT_MAX;
  const bool inside = index >= py::int_(std::max<long long>(minimum, INT_MIN)) &&
                      index <= py::int_(std::min<long long>(maximum, INT_MAX));
  if (!inside)
    fail(function_, "(): ", name, ": expected ", limit.describe(), ", got ",
         py::repr(index).cast<std::string>());
  return index.cast<int>();
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

namespace {

// The new name(s) of a keyword renamed (pipeline/renamed_options.h), "" when it was not: the one this
// function reads, else the method options' for the canonical-form functions, else every one.
std::string renamed_to(const std::string& name, const std::string& function,
                       const std::set<std::string>& known) {
  std::vector<RenamedOption> matches;
  for (const RenamedOption& r : renamed_options())
    if (r.python && r.old_name == name) matches.push_back(r);
  for (const RenamedOption& r : matches)
    if (known.count(r.new_name)) return r.new_name;
  const bool canon = function == "canonical_form" || function == "coulomb" || function == "smacof";
  std::string names;
  for (const RenamedOption& r : matches)
    if (!canon || r.scope == "method options")
      if (names.find(r.new_name) == std::string::npos) names += (names.empty() ? "" : " or ") + r.new_name;
  return names;
}

}  // namespace

void Kwargs::done() const {
  for (auto item : kwargs_) {
    const std::string name = item.first.cast<std::string>();
    if (known_.count(name)) continue;
    const std::string renamed = renamed_to(name, function_, known_);
    if (!renamed.empty())
      throw py::type_error(function_ + "() got an unexpected keyword argument '" + name + "': '" + name +
                           "' is now " + renamed + " (one name per meaning, as the CLI's " +
                           option_flag(renamed.substr(0, renamed.find(' '))) + ")");
    std::string list;
    for (const std::string& k : known_) list += (list.empty() ? "" : ", ") + k;
    throw py::type_error(function_ + "() got an unexpected keyword argument '" + name +
                         "'; its options: " + list);
  }
}

}  // namespace cshapes::python
