#include "cshapes/pipeline/canonical_form_methods.h"

#include <algorithm>
#include <list>
#include <mutex>

#include "cshapes/support/error.h"
#include "cshapes/support/option_limits.h"

namespace cshapes {

namespace {

std::vector<CanonicalFormMethod>& registry() {
  // A function-local static: built on first use, so callers during static initialisation (the CLI's option
  // defaults, a registrar) find it complete.
  static std::vector<CanonicalFormMethod> methods = {coulomb_method(), cmds_method(),      smacof_method(),
                                                     lbo_method(),     diffusion_method(), spectral_mds_method()};
  return methods;
}

// What every option needs: a name, get and set, a limit for a number, choices for a choice.
void require_declared(const MethodOption& o, const std::string& method) {
  const bool numeric = o.type == MethodOption::Type::Integer || o.type == MethodOption::Type::Number;
  CSHAPES_REQUIRE(!o.name.empty() && o.get && o.set && (!numeric || o.limit) &&
                      (o.type != MethodOption::Type::Choice || !o.choices.empty()),
                  "method ", method, ": option '", o.name,
                  "' needs a name, get and set, a limit (a number) or choices (a choice)");
}

// Two declarations of one option name must be the same option (a shared one is one declaration).
void require_same_option(const MethodOption& a, const MethodOption& b, const std::string& method) {
  CSHAPES_REQUIRE(a.type == b.type && a.flag == b.flag && a.help == b.help && a.choices == b.choices &&
                      a.fields == b.fields,
                  "method ", method, ": option '", b.name, "' differs from another method's option of that name");
}

// The outside methods of the runs in progress, each with its count of users: a list, so that a pointer
// find_canonical_form_method gave stays valid while other runs register theirs.
struct OutsideEntry {
  CanonicalFormMethod method;
  int users = 0;
};
std::mutex& outside_mutex() {
  static std::mutex m;
  return m;
}
std::list<OutsideEntry>& outside_methods() {
  static std::list<OutsideEntry> methods;
  return methods;
}

const CanonicalFormMethod* find_builtin(const std::string& name) {
  for (const CanonicalFormMethod& m : registry())
    if (m.name == name) return &m;
  return nullptr;
}

}  // namespace

void register_outside_canonical_form_method(CanonicalFormMethod method) {
  CSHAPES_REQUIRE(!method.name.empty() && method.compute, "a canonical-form method needs a name and compute");
  if (find_builtin(method.name))
    fail("method '", method.name, "' is cshapes's own; give your method another name (known: ",
         canonical_form_method_list(), ")");
  std::lock_guard<std::mutex> lock(outside_mutex());
  for (OutsideEntry& e : outside_methods())
    if (e.method.name == method.name) {
      if (e.method.key_text != method.key_text || e.method.door != method.door)
        fail("method '", method.name, "' is in use by another run with another ", e.method.door,
             " door; give this one another name");
      ++e.users;
      return;
    }
  outside_methods().push_back({std::move(method), 1});
}

void unregister_outside_canonical_form_method(const std::string& name) {
  std::lock_guard<std::mutex> lock(outside_mutex());
  for (auto it = outside_methods().begin(); it != outside_methods().end(); ++it)
    if (it->method.name == name) {
      if (--it->users == 0) outside_methods().erase(it);
      return;
    }
}

std::vector<const CanonicalFormMethod*> outside_canonical_form_methods() {
  std::lock_guard<std::mutex> lock(outside_mutex());
  std::vector<const CanonicalFormMethod*> out;
  for (const OutsideEntry& e : outside_methods()) out.push_back(&e.method);
  return out;
}

const std::vector<CanonicalFormMethod>& canonical_form_method_registry() {
  return registry();
}

bool register_canonical_form_method(CanonicalFormMethod method) {
  CSHAPES_REQUIRE(!method.name.empty() && method.compute, "a canonical-form method needs a name and compute");
  CSHAPES_REQUIRE(!find_canonical_form_method(method.name), "canonical-form method '", method.name,
                  "' is registered twice");
  for (const MethodOption& option : method.options) require_declared(option, method.name);
  for (const MethodOption& option : method.options)
    for (const MethodOption* known : all_method_options())
      if (known->name == option.name) require_same_option(*known, option, method.name);
  registry().push_back(std::move(method));
  return true;
}

const std::vector<std::string>& canonical_form_methods() {
  // Rebuilt when a method was registered since (registration happens before main).
  static std::vector<std::string> names;
  if (names.size() != registry().size()) {
    names.clear();
    for (const CanonicalFormMethod& m : registry()) names.push_back(m.name);
  }
  return names;
}

const CanonicalFormMethod* find_canonical_form_method(const std::string& name) {
  if (const CanonicalFormMethod* m = find_builtin(name)) return m;
  std::lock_guard<std::mutex> lock(outside_mutex());
  for (const OutsideEntry& e : outside_methods())
    if (e.method.name == name) return &e.method;
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

bool method_reads_field(const CanonicalFormMethod& method, const std::string& field) {
  if (field == "method" || field == "knn") return true;
  return std::find(method.reads.begin(), method.reads.end(), field) != method.reads.end();
}

bool method_reads_option(const CanonicalFormMethod& method, const std::string& name) {
  return std::any_of(method.options.begin(), method.options.end(),
                     [&name](const MethodOption& o) { return o.name == name; });
}

std::vector<const MethodOption*> all_method_options() {
  std::vector<const MethodOption*> all;
  for (const CanonicalFormMethod& m : registry())
    for (const MethodOption& option : m.options)
      if (std::none_of(all.begin(), all.end(), [&](const MethodOption* o) { return o->name == option.name; }))
        all.push_back(&option);
  return all;
}

std::vector<std::string> canonical_form_methods_where(
    const std::function<bool(const CanonicalFormMethod&)>& predicate) {
  std::vector<std::string> names;
  for (const CanonicalFormMethod& m : canonical_form_method_registry())
    if (predicate(m)) names.push_back(m.name);
  return names;
}

std::vector<std::string> canonical_form_methods_reading(const std::string& name) {
  return canonical_form_methods_where(
      [&name](const CanonicalFormMethod& m) { return method_reads_option(m, name); });
}

void refuse_options_not_read(const std::vector<std::string>& methods, const OptionFace& face) {
  const std::vector<const MethodOption*> all = all_method_options();
  std::string run;
  for (const std::string& m : methods) run += (run.empty() ? "" : ",") + m;
  for (const MethodOption* option : all) {
    if (!face.given(option->name) || (!face.cli && !option->python)) continue;
    const std::vector<std::string> readers = canonical_form_methods_reading(option->name);
    if (std::any_of(methods.begin(), methods.end(), [&](const std::string& m) {
          return std::find(readers.begin(), readers.end(), m) != readers.end();
        }))
      continue;
    const std::string quote = face.cli ? "" : "'";
    if (methods.size() == 1)
      fail(face.name(*option), " applies to ", face.cli ? "--method " : "method ", either_of(readers, quote),
           " only, not ", quote, methods.front(), quote);
    fail(face.name(*option), " applies to method ", either_of(readers, quote),
         " only, and no method run here (", run, ") is one");
  }
}

void check_method_options(const std::vector<std::string>& methods, const CanonicalFormOptions& options,
                          const OptionFace& face) {
  const std::vector<const MethodOption*> all = all_method_options();
  for (const MethodOption* option : all) check_applies_when(*option, all, options, face);
  for (const std::string& name : methods) {
    const CanonicalFormMethod& method = canonical_form_method(name);
    if (method.check) method.check(options, face);
  }
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
