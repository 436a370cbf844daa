#include "python/declared_options.h"

#include <map>

namespace cshapes::python {

namespace py = pybind11;

namespace {
std::map<std::string, std::vector<const OptionDeclaration*>>& declared() {
  static std::map<std::string, std::vector<const OptionDeclaration*>> by_function;
  return by_function;
}
}  // namespace

void declare_keywords(const std::string& function, const std::vector<const OptionDeclaration*>& options) {
  std::vector<const OptionDeclaration*>& list = declared()[function];
  list.insert(list.end(), options.begin(), options.end());
}

void bind_option_declarations(py::module_& m) {
  m.def(
      "option_declarations",
      [] {
        py::dict out;
        for (const auto& [function, options] : declared()) {
          py::list list;
          for (const OptionDeclaration* o : options) {
            py::dict d;
            d["keyword"] = o->keyword;
            d["flag"] = o->flag;
            d["help"] = option_help(*o, OptionSkin::Python);
            d["cli_help"] = option_help(*o, OptionSkin::Cli);
            d["limit"] = o->limit ? py::object(py::str(o->limit->describe())) : py::object(py::none());
            py::list choices;
            for (const std::string& c : o->choices) choices.append(c);
            d["choices"] = choices;
            d["negated"] = o->negated;
            list.append(d);
          }
          out[py::str(function)] = list;
        }
        return out;
      },
      "The keywords each function shares with a CLI option: see help(cshapes.option_declarations).");
}

}  // namespace cshapes::python
