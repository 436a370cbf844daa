// The methods argument of the experiment functions and canonical_form(): names, doors from outside
// (pipeline/outside_methods.h) and Python functions, registered while the MethodArgument lives.
#pragma once

#include <pybind11/pybind11.h>

#include <memory>
#include <string>
#include <vector>

#include "cshapes/pipeline/outside_methods.h"
#include "python/kwargs.h"

namespace cshapes::python {

// A list (or tuple) of names, or one string of comma-separated names ('lbo', 'coulomb,cmds'), never a string
// taken letter by letter. An item may be a method from outside: "NAME=cmd:COMMAND", "NAME=forms:DIR", a pair
// (NAME, fn) with fn(V, F) -> X (n×3), or (NAME, "cmd:COMMAND"|"forms:DIR"). Reads the keywords
// method_timeout and method_version from k.
struct MethodArgument {
  std::vector<std::string> names;
  // A function door holds a Python object: released when this goes, with the GIL held (at the end of the
  // binding's call, after Computing).
  std::vector<std::unique_ptr<OutsideMethod>> outside;
};
MethodArgument method_argument(const pybind11::object& methods, const char* function, Kwargs& k);

}  // namespace cshapes::python
