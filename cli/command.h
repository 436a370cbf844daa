// The cshapes command registry. Each cli/cmd_*.cpp registers its sub-commands with a static
// registrar, so adding a command touches no shared file:
//
//   static const bool registered = cshapes::cli::register_command(
//       {{"bench", "coulomb"}, "Coulomb gradient: fast vs direct", add_options, run});
//
// A command file keeps its own names (its arguments, run(), the registrar) in a namespace named after the file,
// `namespace cmd_canon { namespace { ... } }`: the CLI's files are compiled in batches (CMakeLists.txt,
// cshapes_unity), where two files' anonymous namespaces would be one.
//
// `cshapes canon` is one command for every method; each method's options come from its registration
// (pipeline/canonical_form_methods.h) as its own option group ("coulomb options", ...): cli/method_options.cpp.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/support/figure_format.h"
#include "cshapes/mesh/io.h"
#include "cshapes/mesh/mesh.h"
#include "cshapes/support/option_limits.h"
#include "cshapes/support/progress.h"
#include "cshapes/pipeline/canonical_forms.h"
#include "cshapes/pipeline/shape_failures.h"
#include "cshapes/support/option_declaration.h"

namespace cshapes::cli {

struct Command {
  std::vector<std::string> path;               // {"info"} or {"bench", "coulomb"}
  std::string summary;                         // one line for --help
  std::function<void(CLI::App&)> add_options;  // declares options, bound to the command's own variables
  std::function<int()> run;                    // runs after a successful parse; returns the exit code
};
bool register_command(Command command);

// Adds every method's option group ("coulomb options", ...) to app: `canon`, `distmat` and `experiment paper`
// take the same method options, with the same names and defaults.
void add_canon_method_options(CLI::App& app);
// Whether the help lists the advanced options (the single settings a preset covers): under --help-all only.
// Called before the commands' options are added.
void show_advanced_method_options(bool show);
// Applies every method's parsed options to `options` (after a successful parse of such a command).
void configure_canonical_form(CanonicalFormOptions& options, bool single_mesh = false);
// After a parse: a method option given on the command line that none of `methods` reads is refused
// (UsageError naming it: "--scheme applies to --method coulomb only") before any work, on every command that
// takes method options (canon, distmat, the experiments). An option that one of several methods reads is
// fine.
void check_canon_method_options(const std::vector<std::string>& methods);
// For a command that runs one method (canon, distmat): an option of a shared group (--geodesics, --distances,
// --mds-solver, --mds-landmarks, --eigenpairs, ...) that the method reads none of the fields of is refused
// (UsageError naming the methods that read it), as is --history (history_given) for a method without
// iterations. The table is the methods' own option lists (pipeline/canonical_form_methods.h).
void check_options_read_by(const std::string& method, bool history_given = false);
// What every experiment command does once its own options are parsed, before any work: the method options
// given are checked against `methods` (check_canon_method_options), the output folder `out` is checked
// (require_output_directory; created by the run when missing), and the method options given are applied to
// `canon` (configure_canonical_form). On every rank of an MPI run, so that each stops on a bad command line.
void prepare_experiment(const std::vector<std::string>& methods, const std::string& out,
                        CanonicalFormOptions& canon);
// --data, --allow-outside, --out and --force as every experiment takes them; data_option declares --data (what
// it may be, in the experiment's words).
void add_data_and_out_options(CLI::App& app, std::string& data, std::string& out, bool& force,
                              bool& allow_outside, const OptionDeclaration& data_option);
// --allow-outside: a dataset's manifest or .cla may list files outside its folder (data/dataset.h).
void add_allow_outside_flag(CLI::App& app, bool& allow_outside);
// --force: write into an output folder (or over an output file) that holds what cshapes did not write
// (support/output_folder.h).
void add_force_flag(CLI::App& app, bool& force);
// --resample N (pipeline/resampled_dataset.h): every shape of the dataset remeshed to about N vertices first
// (cached by content); 0, the default: the shapes as they are. On every command that takes a dataset.
void add_resample_option(CLI::App& app, Index& vertices);
// One name per meaning in every command: `--out DIR` for an output folder, `-o, --output FILE` for an output
// file, `--no-draw` for "do not draw the figures", `--json` for JSON on stdout. add_no_draw_flag declares
// `--no-draw` from the command's declaration of draw (negated: "draw noise.png ..."); add_renamed keeps an
// old spelling only to refuse it (exit 2) with a hint naming the new one; `takes_value`: whether the old
// spelling took a value.
void add_no_draw_flag(CLI::App& app, bool& no_draw, const OptionDeclaration& draw);
// `--figure-format png|pdf|svg` on every command that draws: the format, and so the extension, of its figures
// (support/figure_format.h; the figure scripts' --format); its default is `format`'s value (png).
CLI::Option* add_figure_format_option(CLI::App& app, FigureFormat& format);
// `--out DIR` for a command whose output is a folder, with its old spellings `-o` and `--output` refused.
CLI::Option* add_out_folder_option(CLI::App& app, std::string& folder, const std::string& help);
// The titles of the registered methods, "Coulomb, classical MDS, …" (`separator` between them, " or " before
// the last when `last` is given): help texts name every method from the registry, never a copy of it.
std::string method_titles(const std::string& last = ", ");
void add_renamed(CLI::App& app, const std::string& old_name, const std::string& new_name, bool takes_value,
                 const std::string& why = "");
// CLI11's parse error of the command line `argv` for `command` (its path, "bench smacof"; "" for none) as one
// line, with a hint: an unknown option is named first with the option meant, by edit distance among the
// command's options or the one it begins ("unknown option --methods; did you mean --method?"), an old
// spelling misspelt with its new name; a required option the user wrote another way says how to write it
// ("--output is required: --out is not an option of canon; use -o/--output").
std::string parse_error_with_hint(const CLI::ParseError& error, CLI::App& app, const std::string& command,
                                  int argc, char** argv);
// Whether the user gave this option of a method group (e.g. "--fixed-step") on the command line.
bool canon_option_given(const std::string& name);
// The experiments' --methods: canonical-form methods (pipeline/canonical_form_methods.h), comma-separated;
// every registered one by default ("coulomb,cmds,smacof"). The help and the default come from the registry.
void add_methods_option(CLI::App& app, std::string& methods);
// --methods' value: each item a registered method, at least one; UsageError naming an unknown one and the
// known ones otherwise.
std::vector<std::string> methods_option(const std::string& text);
// --method's value (distmat): a registered method or one from outside (NAME=cmd:…, NAME=forms:…), registered
// for the rest of the process; UsageError otherwise. add_outside_method_options adds --method-timeout and
// --method-version (add_methods_option adds them too).
std::string method_option(const std::string& text);
void add_outside_method_options(CLI::App& app);
// The folder outside command methods keep their output in: FOLDER/method-logs.
void keep_outside_method_logs(const std::string& folder);

// Exit codes of every command (docs/cli.md): every failure prints one line
// "cshapes <command>: error: <what>" on stderr.
enum ExitCode : int {
  kExitOk = 0,
  kExitDataError = 1,  // an input that cannot be read or is invalid, a computation that fails, out of memory
  kExitUsage = 2,    // the command line: unknown command or option, bad value, an option that does not apply,
                     // an output path that cannot be written
  kExitPartial = 3,  // experiments and distmat: the run finished but left shapes out (each named on stderr,
                     // in the report and the JSON); --strict stops at the first instead (exit code 1)
};
// The help epilogue of the commands that can end with kExitPartial.
extern const char* const kPartialResultHelp;
// The end of such a run: one warning line per record (shapes left out, geodesic fallbacks), then
// kExitPartial when a shape was left out, else kExitOk.
int exit_code_for(const std::vector<ShapeFailure>& failures);
// A mistake on the command line (exit code kExitUsage). Commands throw it for what the parser cannot see.
class UsageError : public Error {
 public:
  explicit UsageError(const std::string& message) : Error(message) {}
};
template <typename... Args>
[[noreturn]] void usage_fail(const Args&... args) {
  throw UsageError(detail::concat(args...));
}

// Value checks for options, all in one wording ("--iterations: expected an integer >= 1, got '-3'"); each
// also refuses what is not a number. Use them instead of CLI11's (whose messages print the type's whole
// range).
CLI::Validator integer_at_least(long long minimum);
CLI::Validator integer_in(long long minimum, long long maximum);
CLI::Validator number_at_least(double minimum);            // >= minimum
CLI::Validator number_above(double minimum);               // > minimum
CLI::Validator number_in(double minimum, double maximum);  // [minimum, maximum]
CLI::Validator one_of(const std::vector<std::string>& names);
// A value as the messages show it: in single quotes.
std::string in_quotes(const std::string& text);
// The library's limit of an option (support/option_limits.h): the help shows it, the parser applies it, in the
// library's own words, so the CLI, the Python module and the library agree.
CLI::Validator within(const Limit& limit);

// An option declared in the library (support/option_declaration.h): its flag, its help as the CLI spells it
// (option_help), and its limit (within) or choices (one_of) as the check. The caller chains the rest
// (capture_default_str, a default_str, ...).
template <class T>
CLI::Option* add_declared(CLI::App& app, const OptionDeclaration& declaration, T& value) {
  CLI::Option* option = app.add_option(declaration.flag, value, option_help(declaration, OptionSkin::Cli));
  if (declaration.limit) option->check(within(*declaration.limit));
  if (!declaration.choices.empty()) option->check(one_of(declaration.choices));
  return option;
}
// A declared flag (no value): --no-reflections.
CLI::Option* add_declared_flag(CLI::App& app, const OptionDeclaration& declaration, bool& value);

// Refuses (UsageError) an output path that cannot be written, before any work: see check_output_path in
// support/atomic_file.h. mesh: the extensions write_mesh knows.
void require_output_path(const std::string& path, const std::vector<std::string>& extensions);
void require_mesh_output_path(const std::string& path);
void require_output_directory(const std::string& path);
// No output may be an input: refuses (UsageError) an output path that is already one of the files the
// command reads (check_output_not_input in support/atomic_file.h: "./X", links and hard links are X), before
// any work. option: how the output was given ("-o", "OUT"). Every command that writes files calls it with
// each output and all of its inputs (meshes, matrices, labels, a dataset's manifest or .cla).
void require_output_not_input(const std::string& output, const std::vector<std::string>& inputs,
                              const std::string& option);
// For the experiments, whose output folder holds many files (reports, matrices, .cla, caches): the folder
// `out` may not be the dataset's own folder (`data` a folder, or the folder of its manifest or .cla), where
// they would replace or mix with the dataset's files. UsageError naming both, before any work.
void require_output_folder_apart(const std::string& out, const std::string& data);
// The same for the files `names` that a command writes into the folder `folder`.
void require_outputs_not_inputs(const std::string& folder, const std::vector<std::string>& names,
                                const std::vector<std::string>& inputs, const std::string& option);

// Warns, naming the file, when a PLY's invalid vertices (NaN rows with valid = 0, as canonical forms write
// dropped vertices) were dropped on reading, with the faces on them.
void warn_invalid_vertices_dropped(const MeshFile& file, const std::string& path);

// Global options (given before or after the command).
bool quiet();
int threads();  // 0: OpenMP's default
// Prints "[stage] 42% (ETA 3 s)" to stderr, at most a few times a second; silent with --quiet.
ProgressFn progress_printer();
// Prints a line to stderr unless --quiet.
void note(const std::string& line);
// Prints "cshapes <command>: warning: <line>" to stderr (also with --quiet).
void warn(const std::string& line);

// "a,b,,c" -> {"a", "b", "c"}: a comma-separated option value, empty items dropped.
std::vector<std::string> split_list(const std::string& text);
// A comma-separated option's items, strictly: an empty item ("1,,2", a trailing comma) is refused, and so is
// an empty value when the option was given (`--shapes ''` is not "all": leave the option out for its
// default). Throws UsageError naming the option.
std::vector<std::string> list_option(const std::string& option, const std::string& text);
// Whether the running command's option (e.g. "--knn") was given on the command line.
bool option_given(const std::string& option);
// An integer option that also takes the word `word` (e.g. "all"), parsed strictly ("2abc", "2.7", "1e400"
// refused): returns word_value for the word, else the integer, which must lie in [minimum, maximum].
int integer_or_word(const std::string& option, const std::string& text, long long minimum, long long maximum,
                    const std::string& word, int word_value);

}  // namespace cshapes::cli
