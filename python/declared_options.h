// Which options declared in the library (support/option_declaration.h) each Python function takes as
// keywords: each bind_*.cpp names its functions' declarations beside the code that reads them, and
// cshapes.option_declarations() exports them, so that cshapes/_api.py documents those keywords with the text
// `cshapes ... --help` shows (and their limits or choices), never with a copy of it.
#pragma once

#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "cshapes/support/option_declaration.h"

namespace cshapes::python {

// Records that `function` (its Python name) takes these declared options as keywords.
void declare_keywords(const std::string& function, const std::vector<const OptionDeclaration*>& options);
// Adds cshapes.option_declarations(): {function: [{keyword, flag, help, cli_help, limit, choices, negated},
// ...]}; help as Python spells it, cli_help as `--help` shows it, limit in words ("a number in [0, 0.9]") or
// None, negated: the flag turns off what the keyword turns on (--no-draw, draw=True).
void bind_option_declarations(pybind11::module_& m);

}  // namespace cshapes::python
