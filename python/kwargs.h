// Keyword options of the Python functions, named as the CLI names them (--tear-fraction → tear_fraction),
// with the library's defaults. Each function reads what it knows and then calls done(), which refuses any
// other name (TypeError listing the known ones), as the CLI refuses an unknown option.
#pragma once

#include <pybind11/pybind11.h>

#include <climits>
#include <set>
#include <string>
#include <vector>

#include "cshapes/support/option_limits.h"
#include "cshapes/support/option_declaration.h"

namespace cshapes::python {

namespace py = pybind11;

class Kwargs {
 public:
  Kwargs(const py::kwargs& kwargs, std::string function) : kwargs_(kwargs), function_(std::move(function)) {}

  bool given(const std::string& name) const { return kwargs_.contains(name.c_str()); }
  double number(const std::string& name, double fallback);
  // An integer keyword; one beyond [minimum, maximum] (2**70, or past a C int for int32) is refused naming
  // the keyword (ValueError), never wrapped or left to pybind11's "Unable to cast".
  long long integer(const std::string& name, long long fallback, long long minimum = LLONG_MIN,
                    long long maximum = LLONG_MAX);
  int int32(const std::string& name, int fallback) {
    return static_cast<int>(integer(name, fallback, INT_MIN, INT_MAX));
  }
  // A keyword with a library limit (support/option_limits.h): refused naming the keyword, in the limit's words
  // ("coulomb(): coulomb_max_iterations: expected an integer 0..100000000, got -5").
  double number(const std::string& name, double fallback, const Limit& limit);
  int int32(const std::string& name, int fallback, const Limit& limit);
  bool flag(const std::string& name, bool fallback);
  // A declared option's keyword (support/option_declaration.h), checked against its limit when it has one.
  double number(const OptionDeclaration& option, double fallback) {
    return option.limit ? number(option.keyword, fallback, *option.limit) : number(option.keyword, fallback);
  }
  int int32(const OptionDeclaration& option, int fallback) {
    return option.limit ? int32(option.keyword, fallback, *option.limit) : int32(option.keyword, fallback);
  }
  bool flag(const OptionDeclaration& option, bool fallback) { return flag(option.keyword, fallback); }
  std::string text(const std::string& name, const std::string& fallback);
  // The object itself (None when absent); for arrays and other non-scalar options.
  py::object object(const std::string& name);
  // Refuses every keyword not read so far (TypeError naming it and listing the known ones).
  void done() const;

 private:
  py::object take(const std::string& name);
  const py::kwargs& kwargs_;
  std::string function_;
  std::set<std::string> known_;
};

}  // namespace cshapes::python
