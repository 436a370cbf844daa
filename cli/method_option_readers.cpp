// Which method reads which option of the shared groups, derived from the method registry's own table
// (CanonicalFormMethod::options_not_read, through pipeline's reads_any_option, the helpers Python's
// canonical_form() uses too): an option given to a single method that reads none of the fields it sets is
// refused (command.h: check_options_read_by).
#include <utility>

#include "cli/command.h"
#include "cshapes/pipeline/canonical_form_methods.h"

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
      {"--fold-overstretch", {"mds_solver.fold_overstretch"}},
      {"--eigenpairs", {"lbo", "diffusion"}},
      {"--laplacian", {"lbo", "diffusion", "spectral_mds"}},
      {"--near-multiple-gap", {"lbo", "diffusion", "spectral_mds"}},
  };
  return table;
}

}  // namespace

void check_options_read_by(const std::string& method_name, bool history_given) {
  const CanonicalFormMethod& method = canonical_form_method(method_name);
  for (const auto& [option, fields] : shared_option_fields())
    if (canon_option_given(option) && !reads_any_option(method, fields))
      usage_fail(option, " applies to --method ", either_of(canonical_form_methods_reading(fields)),
                 " only, not ", method_name);
  if (history_given && !method.has_history)
    usage_fail(
        "--history applies to --method ",
        either_of(canonical_form_methods_where([](const CanonicalFormMethod& m) { return m.has_history; })),
        " only (", method_name, " has no iterations)");
}

}  // namespace cshapes::cli
