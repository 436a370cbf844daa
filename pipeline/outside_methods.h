// Canonical forms from outside the library: three doors, one name afterwards. A method that enters by a
// door is registered under its name for the length of a run (OutsideMethod), and from then on every
// experiment, `distmat` and canonical_form() treat it exactly as a built-in method: the same ICP, distances,
// measures, figures, failure records and cache.
//
//   NAME=cmd:COMMAND  a program run once per shape (any language): {mesh} (or {mesh.ply}) in COMMAND becomes
//                     the path of the mesh cshapes writes for it, {form} (or {form.npy}, {form.ply},
//                     {form.off}, {form.obj}) the path where it must write the form, {name} the shape's name
//                     (for the program's own records); run by /bin/sh, under a
//                     time limit, its wall time and peak memory recorded, its stdout and stderr kept.
//   NAME=forms:DIR    forms computed beforehand: DIR/SHAPE.{ply,off,obj,xyz,npy} by the shape's name (the
//                     stem of the mesh's file name). A shape without one is left out by name and listed in
//                     OUT/forms-needed/NAME.csv with its mesh (write_forms_needed), for the user to compute.
//   a function        a callable (V, F) -> X from a front end (Python's methods=[("mine", fn)]).
//
// The form contract, checked before use: n×3, one row per vertex of the mesh given, in its order (the mesh
// as the experiment has it: an outside method is given no repaired or rescaled copy), every coordinate
// finite, the points spanning a plane. A form that breaks it, a command that fails, runs past its limit or
// writes nothing throws cshapes::Error naming the shape, the reason and the command's last lines of output:
// the experiments leave that shape out for that method and go on.
#pragma once

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cshapes/mesh/mesh.h"
#include "cshapes/pipeline/canonical_forms.h"
#include "cshapes/support/option_declaration.h"

namespace cshapes {

// The door's options a user sets, each declared once (support/option_declaration.h): `--method-timeout` and
// `--method-version` of every command that takes a method from outside, and the same keywords in Python.
namespace outside_method_options {
inline const OptionDeclaration kTimeout{"method_timeout", "--method-timeout",
                                        "a method from outside (NAME=cmd:COMMAND): the limit of one run, in "
                                        "seconds; a run past it is stopped and "
                                        "its shape left out for that method"};
inline const OptionDeclaration kVersion{"method_version", "--method-version",
                                        "a method from outside: a tag in its cache key; change it to "
                                        "recompute forms the cache holds (the command "
                                        "string and the files it names are in the key already)"};
inline const std::vector<const OptionDeclaration*> kAll = {&kTimeout, &kVersion};
}  // namespace outside_method_options

// A door's settings, the same for every outside method of a run.
struct OutsideMethodSettings {
  double timeout_seconds = 24 * 3600;  // cmd: one run's limit (--method-timeout)
  std::string version;                 // part of the cache key (--method-version): a change recomputes
  std::string logs;                    // cmd: LOGS/NAME/SHAPE.{out,err}; "" keeps none
};

struct OutsideDoor {
  enum class Kind { Command, Forms, Function };
  Kind kind = Kind::Command;
  std::string text;  // the command, the folder, or the function's name
  // Kind::Function: the form of one mesh (its name for messages), and what identifies the function's code
  // in the cache key (its source's digest, from the front end).
  std::function<Points(const Mesh& mesh, const std::string& name)> function;
  std::string function_key;
};

// "command", "forms", "python".
std::string door_name(OutsideDoor::Kind kind);

// Whether a --methods item is a door ("NAME=cmd:…", "NAME=forms:…"), not a plain method name.
bool is_outside_method_item(const std::string& item);
// The items of a comma-separated methods text ("lbo,pca=cmd:python3 pca.py {mesh} {form.npy}"): commas
// separate items, "\," is a comma inside a command. Throws cshapes::Error naming `context` for an empty item.
std::vector<std::string> split_method_items(const std::string& text, const std::string& context);
// Splits "NAME=cmd:COMMAND" or "NAME=forms:DIR". Throws cshapes::Error for another door, an empty command
// or folder, a folder that does not exist, or a NAME that is not letters, digits, '-', '_' (it names files).
std::pair<std::string, OutsideDoor> parse_outside_method(const std::string& item);

// A method from outside, registered under `name` while this object lives (pipeline/canonical_form_methods.h:
// register_outside_canonical_form_method). Movable through a unique_ptr only.
class OutsideMethod {
 public:
  OutsideMethod(std::string name, OutsideDoor door, OutsideMethodSettings settings = {});
  ~OutsideMethod();
  OutsideMethod(const OutsideMethod&) = delete;
  OutsideMethod& operator=(const OutsideMethod&) = delete;
  const std::string& name() const { return name_; }

  struct State;  // what the door keeps between shapes (the shapes it lacked forms for)

 private:
  std::string name_;
  std::shared_ptr<State> state_;
};

// The outside methods of a --methods list: each door item registered (its name then stands in the list),
// plain names passed through. Keep the returned objects alive for the run.
struct OutsideMethodList {
  std::vector<std::string> names;
  std::vector<std::unique_ptr<OutsideMethod>> registered;
};
OutsideMethodList register_outside_methods(const std::vector<std::string>& items,
                                           const OutsideMethodSettings& settings);

// Sets the folder every outside command method keeps its output in (OUT/method-logs): a front end calls it
// once it knows the run's output folder. "" keeps none.
void set_outside_method_logs(const std::string& folder);

// For a report: one entry per outside method among `methods` {name, door, text}; empty for built-ins.
nlohmann::json outside_methods_json(const std::vector<std::string>& methods);
// The --methods value that names `methods` again on a command line, each outside method with its door
// ("lbo,pca=cmd:python3 pca.py {mesh} {form.npy}", a comma in a command as \,), in single quotes when it holds
// a door; a Python function's door cannot be given on a command line: it shows as NAME=python:FUNCTION.
std::string methods_command_argument(const std::vector<std::string>& methods);
// "mine: command `python3 mine.py {mesh} {form}`" lines, one per outside method among `methods`, for reports
// (Markdown); "" when there are none.
std::string outside_methods_markdown(const std::vector<std::string>& methods);

// For each forms-door method among `methods` that lacked forms during the run: OUT/forms-needed/NAME.csv
// (shape,mesh,expected_form) with each shape's mesh beside it (NAME/SHAPE.off). Returns the files written.
std::vector<std::string> write_forms_needed(const std::vector<std::string>& methods, const std::string& out);

// A command door runs one program per shape, which cshapes cannot parallelise from inside. run_commands_ahead
// runs the programs for `shapes` (each mesh with the name the caller's pass gives it as options.name)
// `workers` at a time before that pass, and hands each result, the form or the failure, to the pass's call
// for the same mesh and name, which then runs nothing: the pass counts, caches, reports and orders everything
// as without it. Shapes whose form `cache` holds are skipped. Does nothing for a method that is not a command
// door, or for workers < 2. A stop (options.progress) ends every program and is rethrown.
struct ShapeAhead {
  const Mesh* mesh = nullptr;
  std::string name;
};
void run_commands_ahead(const DiskCache& cache, const std::vector<ShapeAhead>& shapes,
                        const CanonicalFormOptions& options, int workers);
// The same for every command-door method among `methods`, each shape under the options
// options_per_method(base, methods, shape.name) gives it, as many at a time as refresh_threads() allows.
void run_commands_ahead(const DiskCache& cache, const std::vector<ShapeAhead>& shapes,
                        const CanonicalFormOptions& base, const std::vector<std::string>& methods);
// Whether `method` is an outside method that enters by the command door.
bool is_command_door_method(const std::string& method);

// The folders a run keeps between reruns for outside methods (method-logs), beside its cache.
inline constexpr const char* kMethodLogsFolder = "method-logs";

// Reads a form file (.ply, .off, .obj, .xyz, .npy of float64 or float32, shape (n, 3), C or Fortran order).
// Throws cshapes::Error naming the file.
Points read_form_file(const std::string& path);

}  // namespace cshapes
