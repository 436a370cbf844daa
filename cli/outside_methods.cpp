// The methods option of the experiments and distmat, with methods from outside (pipeline/outside_methods.h):
// NAME=cmd:COMMAND and NAME=forms:DIR items are registered under NAME for the rest of the process.
#include <filesystem>
#include <memory>

#include "cli/command.h"
#include "cshapes/pipeline/canonical_form_methods.h"
#include "cshapes/pipeline/outside_methods.h"
#include "cshapes/support/error.h"

namespace cshapes::cli {

namespace {
// The outside methods of this run (NAME=cmd:…, NAME=forms:…), registered until the process ends, and the
// settings of their doors (--method-timeout, --method-version).
OutsideMethodSettings g_outside_settings;
std::vector<std::unique_ptr<OutsideMethod>>& outside_methods() {
  static std::vector<std::unique_ptr<OutsideMethod>> registered;
  return registered;
}
}  // namespace

void add_outside_method_options(CLI::App& app) {
  add_declared(app, outside_method_options::kTimeout, g_outside_settings.timeout_seconds)
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  add_declared(app, outside_method_options::kVersion, g_outside_settings.version);
}

void add_methods_option(CLI::App& app, std::string& methods) {
  methods = canonical_form_method_list(",");
  app.add_option("--methods", methods,
                 "comma-separated: " + canonical_form_method_list() +
                     ", or a method from outside: NAME=cmd:'COMMAND with {mesh} and {form}' (a program run per "
                     "shape) or NAME=forms:DIR (forms computed beforehand, DIR/SHAPE.ply|off|obj|xyz|npy); a "
                     "comma inside a command is written \\,")
      ->capture_default_str();
  add_outside_method_options(app);
}

std::vector<std::string> method_items(const std::string& option, const std::string& text) {
  try {
    return split_method_items(text, option);
  } catch (const Error& error) {
    throw UsageError(error.what());
  }
}

std::vector<std::string> registered_methods(const std::string& option, const std::vector<std::string>& items) {
  try {
    OutsideMethodList list = register_outside_methods(items, g_outside_settings);
    for (auto& m : list.registered) outside_methods().push_back(std::move(m));
    require_canonical_form_methods(list.names, option);
    return list.names;
  } catch (const Error& error) {
    throw UsageError(option + ": " + error.what());
  }
}

std::vector<std::string> methods_option(const std::string& text) {
  if (text.empty() && option_given("--methods"))
    usage_fail("--methods: empty list; give at least one item, or leave the option out for its default");
  if (text.empty()) usage_fail("--methods: give at least one of ", canonical_form_method_list());
  return registered_methods("--methods", method_items("--methods", text));
}

std::string method_option(const std::string& text) {
  return registered_methods("--method", {text}).front();
}

void keep_outside_method_logs(const std::string& folder) {
  set_outside_method_logs((std::filesystem::path(folder) / kMethodLogsFolder).string());
}

}  // namespace cshapes::cli
