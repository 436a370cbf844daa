// The formats cshapes draws its figures in: `--figure-format png|pdf|svg` on every command that draws,
// Python's figure_format=, and the figure scripts' --format (experiments/plots/figure_style.py). PNG for the
// screen and the reports; PDF and SVG for a paper (lines and text stay vectors, text stays text: what LaTeX
// includes).
#pragma once

#include <string>
#include <vector>
#include "cshapes/support/option_declaration.h"

namespace cshapes {

enum class FigureFormat { png, pdf, svg };

// {"png", "pdf", "svg"}: each format's name, which is also its file extension, in the enum's order.
const std::vector<std::string>& figure_format_names();
std::string to_string(FigureFormat format);
// The format of a name ("svg"); throws cshapes::Error naming the formats for any other.
FigureFormat parse_figure_format(const std::string& name);
// `--figure-format` and figure_format= on every command and function that draws (declared once,
// support/option_declaration.h).
inline const OptionDeclaration kFigureFormatOption{"figure_format", "--figure-format",
                                                   "the figures' format and extension: png, or pdf or svg "
                                                   "for a paper (lines and text stay vectors, text stays "
                                                   "text)",
                                                   std::nullopt, figure_format_names()};
// "NAME.EXT": the file a figure called NAME is written to in `format` ("pr", svg -> "pr.svg").
std::string figure_file_name(const std::string& name, FigureFormat format);

}  // namespace cshapes
