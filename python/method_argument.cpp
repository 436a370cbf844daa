#include "python/method_argument.h"

#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/support/error.h"
#include "cshapes/support/progress.h"
#include "cshapes/support/sha256.h"
#include "python/convert.h"

namespace cshapes::python {

namespace py = pybind11;

namespace {

// What identifies a Python function's code in the cache key: its module, qualified name and source.
std::string function_key(const py::object& fn) {
  std::string key = py::str(py::getattr(fn, "__module__", py::str("?"))).cast<std::string>() + "." +
                    py::str(py::getattr(fn, "__qualname__", py::str(py::repr(fn)))).cast<std::string>();
  try {
    key += ";source=" + sha256_hex(py::module_::import("inspect").attr("getsource")(fn).cast<std::string>());
  } catch (const py::error_already_set&) {
    key += ";source=unavailable";  // a builtin or a lambda typed at the prompt: --method-version decides
  }
  return key;
}

OutsideDoor function_door(const py::object& fn, const std::string& name) {
  OutsideDoor door;
  door.kind = OutsideDoor::Kind::Function;
  door.text = py::str(py::getattr(fn, "__qualname__", py::str(py::repr(fn)))).cast<std::string>();
  door.function_key = function_key(fn);
  // Called from the library's threads without the GIL: it takes the GIL for the call, and a Python exception
  // becomes this shape's failure (KeyboardInterrupt stops the run).
  door.function = [fn = std::make_shared<py::object>(fn), name](const Mesh& mesh,
                                                                 const std::string& shape) -> Points {
    py::gil_scoped_acquire gil;
    try {
      py::object X = (*fn)(to_numpy(mesh.V), to_numpy(mesh.F));
      return to_points(X, shape + ": method " + name + ": the form returned", true);
    } catch (py::error_already_set& e) {
      if (e.matches(PyExc_KeyboardInterrupt)) throw Cancelled();
      fail(shape, ": method ", name, ": the function raised ", e.what());
    }
  };
  return door;
}

}  // namespace

MethodArgument method_argument(const py::object& methods, const char* function, Kwargs& k) {
  OutsideMethodSettings settings;
  settings.timeout_seconds = k.number("method_timeout", settings.timeout_seconds);
  CSHAPES_REQUIRE(settings.timeout_seconds > 0, function, "(): method_timeout: expected seconds > 0, got ",
                  settings.timeout_seconds);
  settings.version = k.text("method_version", "");
  MethodArgument out;
  if (methods.is_none()) return out;
  auto add_text = [&](const std::string& text) {  // the CLI's rule: commas separate, "\," is a comma
    for (const std::string& item : split_method_items(text, std::string(function) + "(): methods")) {
      if (is_outside_method_item(item)) {
        auto [name, door] = parse_outside_method(item);
        out.outside.push_back(std::make_unique<OutsideMethod>(name, std::move(door), settings));
        out.names.push_back(name);
      } else {
        out.names.push_back(item);
      }
    }
  };
  if (py::isinstance<py::str>(methods)) {
    add_text(methods.cast<std::string>());
    return out;
  }
  CSHAPES_REQUIRE(py::isinstance<py::list>(methods) || py::isinstance<py::tuple>(methods), function,
                  "(): methods: expected a list of method names such as ['coulomb', 'lbo'], got ",
                  std::string(py::str(methods.get_type().attr("__name__"))));
  for (py::handle m : methods) {
    if (py::isinstance<py::str>(m)) {
      const std::string text = m.cast<std::string>();
      // One item of a list is one method: a command may hold commas.
      if (is_outside_method_item(text)) {
        auto [name, door] = parse_outside_method(text);
        out.outside.push_back(std::make_unique<OutsideMethod>(name, std::move(door), settings));
        out.names.push_back(name);
      } else {
        add_text(text);
      }
      continue;
    }
    CSHAPES_REQUIRE(py::isinstance<py::tuple>(m) && py::len(m) == 2 && py::isinstance<py::str>(m[py::int_(0)]),
                    function, "(): methods: expected method names (str) or pairs (name, fn) with fn(V, F) -> X, got ",
                    std::string(py::str(m.get_type().attr("__name__"))));
    const std::string name = m[py::int_(0)].cast<std::string>();
    const py::object what = py::reinterpret_borrow<py::object>(m[py::int_(1)]);
    if (py::isinstance<py::str>(what)) {
      auto [parsed, door] = parse_outside_method(name + "=" + what.cast<std::string>());
      out.outside.push_back(std::make_unique<OutsideMethod>(parsed, std::move(door), settings));
    } else {
      CSHAPES_REQUIRE(PyCallable_Check(what.ptr()), function, "(): methods: (", name,
                      ", …): expected a function fn(V, F) -> X or a door 'cmd:COMMAND' / 'forms:DIR', got ",
                      std::string(py::str(what.get_type().attr("__name__"))));
      out.outside.push_back(std::make_unique<OutsideMethod>(name, function_door(what, name), settings));
    }
    out.names.push_back(name);
  }
  require_canonical_form_methods(out.names, std::string(function) + "(): methods");
  return out;
}


}  // namespace cshapes::python
