// The canonical-form methods' options on the command line, all made from the methods' own declarations
// (pipeline/method_options.h): one option group per method ("coulomb options", ...) holding the options it is
// the first to list, each with its library limit or choices and its default; the values given set
// CanonicalFormOptions, and the options a method does not list are refused naming the methods that do.
#include <map>

#include "cli/command.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/renamed_options.h"

namespace cshapes::cli {

namespace {

struct MethodOptionsState {
  std::map<std::string, std::string> values;  // by option name: the text given (CLI11 writes it)
  // Every CLI option made (one per option and command that takes method options), by option name.
  std::vector<std::pair<std::string, CLI::Option*>> made;
  KnnGraphOptions knn;  // the point-cloud option every method reads
  bool show_advanced = false;  // --help-all: the advanced options' groups are listed
};
MethodOptionsState& state() {
  static MethodOptionsState s;
  return s;
}

// "cmds/smacof: " before the help of an option several methods read; nothing for one only its group's reads.
std::string readers_prefix(const MethodOption& option) {
  const std::vector<std::string> readers = canonical_form_methods_reading(option.name);
  if (readers.size() < 2) return "";
  std::string prefix;
  for (const std::string& r : readers) prefix += (prefix.empty() ? "" : "/") + r;
  return prefix + ": ";
}

OptionFace cli_face(bool single_mesh) {
  OptionFace face;
  face.cli = true;
  face.single_mesh = single_mesh;
  face.given = [](const std::string& name) {
    for (const auto& [option, made] : state().made)
      if (option == name && made->count() > 0) return true;
    return false;
  };
  return face;
}

// Runs a library check, its cshapes::Error a mistake on the command line.
template <class Check>
void as_usage(const Check& check) {
  try {
    check();
  } catch (const UsageError&) {
    throw;
  } catch (const Error& error) {
    throw UsageError(error.what());
  }
}

}  // namespace

void show_advanced_method_options(bool show) { state().show_advanced = show; }

void add_canon_method_options(CLI::App& app) {
  std::vector<std::string> added;
  for (const CanonicalFormMethod& method : canonical_form_method_registry()) {
    CLI::Option_group* group = nullptr;
    CLI::Option_group* advanced = nullptr;  // named only under --help-all: CLI11 hides a group without a name
    for (const MethodOption& option : method.options) {
      if (std::find(added.begin(), added.end(), option.name) != added.end()) continue;
      added.push_back(option.name);
      CLI::Option_group*& into = option.advanced ? advanced : group;
      if (!into)
        into = app.add_option_group(!option.advanced ? method.name + " options"
                                    : state().show_advanced ? "advanced " + method.name + " options"
                                                            : "");
      CLI::Option* made =
          into->add_option(cli_flag(option), state().values[option.name], readers_prefix(option) + option.help);
      made->type_name(option.type == MethodOption::Type::Integer  ? "INT"
                      : option.type == MethodOption::Type::Number ? "FLOAT"
                                                                  : "TEXT");
      const std::string fallback = option_text(option_default(option));
      if (!fallback.empty()) made->default_str(fallback);
      if (option.limit) made->check(within(*option.limit));
      if (option.type == MethodOption::Type::Choice) made->check(one_of(option.choices));
      state().made.emplace_back(option.name, made);
    }
  }
  // Not a method's: Coulomb's constraint edges, the MDS methods' graph geodesics and the spectral methods'
  // graph Laplacian are all this graph on a point cloud.
  CLI::Option_group* clouds = app.add_option_group("point-cloud options (every method)");
  clouds
      ->add_option(
          "--knn", state().knn.k,
          "point clouds (no faces): neighbours per point of the symmetric kNN graph that stands in for "
          "the mesh's edges")
      ->capture_default_str()
      ->check(within(kKnnLimit));
  // The old spellings (pipeline/renamed_options.h), refused naming the new ones.
  for (const RenamedOption& renamed : renamed_options_in("method options"))
    add_renamed(app, option_flag(renamed.old_name), option_flag(renamed.new_name), true);
}

bool canon_option_given(const std::string& flag) {
  for (const auto& [name, made] : state().made)
    if (made->count() > 0 && made->get_name() == flag) return true;
  return false;
}

void check_canon_method_options(const std::vector<std::string>& methods) {
  as_usage([&] { refuse_options_not_read(methods, cli_face(true)); });
}

void configure_canonical_form(CanonicalFormOptions& options, bool single_mesh) {
  options.knn = state().knn;
  const OptionFace face = cli_face(single_mesh);
  std::vector<std::string> concerned;  // the methods that read an option given: their checks run
  for (const MethodOption* option : all_method_options()) {
    if (!face.given(option->name)) continue;
    option->set(options, parse_option_text(*option, state().values[option->name]));
    for (const std::string& m : canonical_form_methods_reading(option->name))
      if (std::find(concerned.begin(), concerned.end(), m) == concerned.end()) concerned.push_back(m);
  }
  as_usage([&] { check_method_options(concerned, options, face); });
}

void check_options_read_by(const std::string& method_name, bool history_given) {
  const CanonicalFormMethod& method = canonical_form_method(method_name);
  check_canon_method_options({method_name});
  if (history_given && !method.has_history)
    usage_fail(
        "--history applies to --method ",
        either_of(canonical_form_methods_where([](const CanonicalFormMethod& m) { return m.has_history; })),
        " only (", method_name, " has no iterations)");
}

}  // namespace cshapes::cli
