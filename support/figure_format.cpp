#include "cshapes/support/figure_format.h"

#include "cshapes/support/error.h"

namespace cshapes {

const std::vector<std::string>& figure_format_names() {
  static const std::vector<std::string> names = {"png", "pdf", "svg"};
  return names;
}

std::string to_string(FigureFormat format) {
  return figure_format_names()[static_cast<size_t>(format)];
}

FigureFormat parse_figure_format(const std::string& name) {
  const std::vector<std::string>& names = figure_format_names();
  for (size_t k = 0; k < names.size(); ++k)
    if (names[k] == name) return static_cast<FigureFormat>(k);
  fail("figure format: expected png, pdf or svg, got '", name, "'");
}

std::string figure_file_name(const std::string& name, FigureFormat format) {
  return name + "." + to_string(format);
}

}  // namespace cshapes
