// Drawing the experiments' figures, and the one place where cshapes finds a Python interpreter and quotes
// for the shell (the benchmarks' anchors use both: experiments/bench_support.h).
//
// The figure scripts (experiments/plots/*.py) are installed beside the binaries: build/share/cshapes/plots in
// the build tree, PREFIX/share/cshapes/plots once installed. They are found from the binary that holds this
// code (the cshapes executable, or the Python module's shared object), so no source path is compiled in;
// $CSHAPES_PLOTS names another folder. The interpreter is the first of $CSHAPES_PYTHON, /usr/bin/python3 and
// python3 that imports matplotlib and numpy (Debian's python3-matplotlib installs for /usr/bin/python3,
// while the python3 first on PATH may be another interpreter).
//
// Drawing is never part of a computation: drivers return data and write their CSV/JSON, and a figure is
// drawn from those files afterwards. A figure that cannot be drawn is not an error: FigureRun says why.
#pragma once

#include <string>
#include <vector>

#include "cshapes/support/progress.h"
#include "cshapes/support/figure_format.h"
#include "cshapes/support/option_declaration.h"

namespace cshapes {

// `cshapes evaluate --no-draw` (declared once, support/option_declaration.h).
inline const OptionDeclaration kEvaluateDrawOption = negated_option(
    "draw", "--no-draw", "draw pr.png, confusion.png and matrix.png (drawing needs Python with matplotlib)");

// The folder of the figure scripts; "" when none is found.
std::string plot_scripts_directory();
// The first of $CSHAPES_PYTHON, /usr/bin/python3 and python3 that imports every module of `imports`
// ("matplotlib, numpy"); "" when none does. The one place cshapes looks for an interpreter (figures, and the
// benchmarks' scikit-learn and Open3D anchors).
std::string find_python(const std::string& imports);
// s in single quotes for /bin/sh (a quote inside becomes '\'').
std::string shell_quote(const std::string& s);

// FOLDER/methods.json: {"coulomb": "Coulomb", "cmds": "classical MDS", ...}: the one name of each method in
// figures, read by experiments/plots/figure_style.py. `methods`: the run's methods, in its order (a method no
// one registered under its own name); empty: every registered method (pipeline/canonical_form_methods.h), in
// registration order, for a command that does not know which methods its data holds. Atomic; throws
// WriteError when it cannot write.
void write_method_titles(const std::string& folder, const std::vector<std::string>& methods = {});

struct FigureRun {
  bool drawn = false;
  std::string problem;  // why not, when not drawn; names the script and how to run it by hand
};
// Runs `PYTHON SCRIPT ARGS...` (script: a file name in plot_scripts_directory(), e.g. "noise_figure.py"),
// quietly; drawn when it exits 0 and `expected` (a file it writes) exists afterwards. `expected` is removed
// first, so an old figure is never taken for a new one. When the script fails, `problem` quotes the last
// line it printed on stderr. With `progress`, the script runs with CSHAPES_FIGURE_PROGRESS=1, and each line
// "progress K N" it prints on stdout is reported as ("figures", K, N); its other output is ignored.
FigureRun run_figure_script(const std::string& script, const std::vector<std::string>& args,
                            const std::string& expected, const ProgressFn& progress = {});
// run_figure_script for every figure a command draws, in `format`: the script is given `--format=FORMAT`
// after `args` (figure_style.py's add_format_argument), and `figure` is the path of the figure it writes last
// without its extension (OUT/noise: drawn when OUT/noise.svg exists afterwards). methods.json is written into
// that figure's folder first (write_method_titles, of `methods`), so the script names every method as the
// tables do.
FigureRun draw_figure(const std::string& script, const std::vector<std::string>& args,
                      const std::string& figure, FigureFormat format,
                      const std::vector<std::string>& methods = {}, const ProgressFn& progress = {});

// A figure's line in a report.md: "![caption](file)" for a picture Markdown shows (PNG, SVG), "[caption
// (PDF)](file)", a link, for a PDF, which no Markdown viewer shows inline.
std::string figure_markdown(const std::string& caption, const std::string& file);

}  // namespace cshapes
