#include "cshapes/pipeline/canonical_form_methods.h"

#include <algorithm>

#include "cshapes/support/error.h"
#include "cshapes/support/option_limits.h"

namespace cshapes {

const std::vector<CanonicalFormMethod>& canonical_form_method_registry() {
  // A function-local static: built on first use, so callers during static initialisation (the CLI's option
  // defaults) find it complete.
  static const std::vector<CanonicalFormMethod> methods = {coulomb_method(), cmds_method(), smacof_method(),
                                                           lbo_method(), diffusion_method(),
                                                           spectral_mds_method()};
  return methods;
}

const std::vector<std::string>& canonical_form_methods() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const CanonicalFormMethod& m : canonical_form_method_registry()) out.push_back(m.name);
    return out;
  }();
  return names;
}

const CanonicalFormMethod* find_canonical_form_method(const std::string& name) {
  for (const CanonicalFormMethod& m : canonical_form_method_registry())
    if (m.name == name) return &m;
  return nullptr;
}

std::string canonical_form_method_list(const std::string& separator) {
  std::string out;
  for (const std::string& name : canonical_form_methods()) out += (out.empty() ? "" : separator) + name;
  return out;
}

const CanonicalFormMethod& canonical_form_method(const std::string& name) {
  const CanonicalFormMethod* method = find_canonical_form_method(name);
  if (!method) fail("unknown canonization method '", name, "'; known: ", canonical_form_method_list());
  return *method;
}

void require_canonical_form_methods(const std::vector<std::string>& methods, const std::string& context) {
  for (const std::string& name : methods)
    if (!find_canonical_form_method(name))
      fail(context, ": unknown canonization method '", name, "'; known: ", canonical_form_method_list());
  check_distinct(methods, context);
}

std::string canonical_form_method_title(const std::string& name) {
  const CanonicalFormMethod* method = find_canonical_form_method(name);
  return method ? method->title : name;
}

bool reads_any_option(const CanonicalFormMethod& method, const std::vector<std::string>& fields) {
  const std::vector<std::string>& not_read = method.options_not_read;
  for (const std::string& field : fields) {
    const std::string top = field.substr(0, field.find('.'));
    if (std::find(not_read.begin(), not_read.end(), field) == not_read.end() &&
        std::find(not_read.begin(), not_read.end(), top) == not_read.end())
      return true;
  }
  return false;
}

std::vector<std::string> canonical_form_methods_where(
    const std::function<bool(const CanonicalFormMethod&)>& predicate) {
  std::vector<std::string> names;
  for (const CanonicalFormMethod& m : canonical_form_method_registry())
    if (predicate(m)) names.push_back(m.name);
  return names;
}

std::vector<std::string> canonical_form_methods_reading(const std::vector<std::string>& fields) {
  return canonical_form_methods_where(
      [&fields](const CanonicalFormMethod& m) { return reads_any_option(m, fields); });
}

std::string either_of(const std::vector<std::string>& names, const std::string& quote) {
  std::string text;
  for (size_t k = 0; k < names.size(); ++k)
    text += (k == 0 ? "" : k + 1 == names.size() ? " or " : ", ") + quote + names[k] + quote;
  return text;
}

MeshRequirements canonical_form_requirements(const std::string& method) {
  return canonical_form_method(method).requirements;
}

CanonicalFormOptions experiment_canonical_form_options() {
  return CanonicalFormOptions{};
}

}  // namespace cshapes
