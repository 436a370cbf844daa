#include "pipeline/canonical_form_methods.h"

#include "core/error.h"
#include "core/option_limits.h"

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

MeshRequirements canonical_form_requirements(const std::string& method) {
  return canonical_form_method(method).requirements;
}

CanonicalFormOptions experiment_canonical_form_options() {
  return CanonicalFormOptions{};
}

}  // namespace cshapes
