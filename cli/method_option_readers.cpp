// Which method reads which option of the shared groups, derived from the method registry's own table
// (CanonicalFormMethod::options_not_read): an option given to a single method that reads none of the fields
// it sets is refused (command.h: check_options_read_by).
#include <algorithm>
#include <utility>

#include "cli/command.h"
#include "pipeline/canonical_form_methods.h"

namespace cshapes::cli {

namespace {

// The options of groups that several methods share, each with the CanonicalFormOptions fields it sets.
// Options of a group only its own method reads are check_canon_method_options' business.
const std::vector<std::pair<std::string, std::vector<std::string>>>& shared_option_fields() {
  static const std::vector<std::pair<std::string, std::vector<std::string>>> table = {
      {"--geodesics", {"geodesics"}},
      {"--distances", {"distances_file"}},
      {"--mds-solver", {"mds_solver"}},
      {"--landmarks", {"mds_solver"}},
      {"--fold-overstretch", {"mds_solver"}},
      {"--eigenpairs", {"lbo", "diffusion"}},
      {"--laplacian", {"lbo", "diffusion", "spectral_mds"}},
      {"--near-multiple-gap", {"lbo", "diffusion", "spectral_mds"}},
  };
  return table;
}

// "a", "a or b", "a, b or c": the methods for which `predicate` holds, in registration order.
template <class Predicate>
std::string method_names(Predicate predicate) {
  std::vector<std::string> names;
  for (const CanonicalFormMethod& m : canonical_form_method_registry())
    if (predicate(m)) names.push_back(m.name);
  std::string text;
  for (size_t k = 0; k < names.size(); ++k)
    text += (k == 0 ? "" : k + 1 == names.size() ? " or " : ", ") + names[k];
  return text;
}

bool reads_any(const CanonicalFormMethod& method, const std::vector<std::string>& fields) {
  for (const std::string& field : fields)
    if (std::find(method.options_not_read.begin(), method.options_not_read.end(), field) ==
        method.options_not_read.end())
      return true;
  return false;
}

}  // namespace

void check_options_read_by(const std::string& method_name, bool history_given) {
  const CanonicalFormMethod& method = canonical_form_method(method_name);
  for (const auto& [option, fields] : shared_option_fields()) {
    if (!canon_option_given(option) || reads_any(method, fields)) continue;
    const std::vector<std::string>& read = fields;  // a structured binding cannot be captured in C++17
    usage_fail(option, " applies to --method ",
               method_names([&read](const CanonicalFormMethod& m) { return reads_any(m, read); }),
               " only, not ", method_name);
  }
  if (history_given && !method.has_history)
    usage_fail("--history applies to --method ",
               method_names([](const CanonicalFormMethod& m) { return m.has_history; }), " only (",
               method_name, " has no iterations)");
}

}  // namespace cshapes::cli
