#include "cshapes/pipeline/renamed_options.h"

namespace cshapes {

const std::vector<RenamedOption>& renamed_options() {
  static const std::vector<RenamedOption> table = {
      // A method's own option names its method; an iteration cap is `*_max_iterations` in every command.
      {"method options", "iters", "smacof_max_iterations"},
      {"method options", "tolerance", "smacof_tolerance"},
      {"method options", "window", "smacof_window"},
      {"method options", "landmarks", "mds_landmarks"},
      {"method options", "start_landmarks", "coulomb_start_landmarks"},
      // ICP's stopping rule, beside SMACOF's and Coulomb's.
      {"align", "tolerance", "icp_tolerance"},
      {"remesh", "tolerance", "vertex_tolerance", false},
      // Counts: vertices of a mesh, points of a cloud; SMACOF's settings as the method option names them.
      {"bench coulomb", "n", "points", false},
      {"bench coulomb-iteration", "n", "vertices", false},
      {"bench form", "n", "vertices", false},
      {"bench geodesics", "n", "vertices", false},
      {"bench icp", "n", "points", false},
      {"bench smacof", "n", "points", false},
      {"bench smacof", "iters", "iterations", false},
      {"bench smacof", "max_iters", "smacof_max_iterations", false},
      {"bench smacof", "tolerance", "smacof_tolerance", false},
      {"bench smacof", "window", "smacof_window", false},
      {"experiment coulomb-params", "max_iterations", "coulomb_max_iterations", false},
      {"experiment paper", "timing_repeats", "table1_repeats"},
      {"experiment paper", "fig5_iterations", "fig5_max_iterations", false},
      // `--methods` is canonical-form methods in every command; geodesic methods say so.
      {"stress", "canon_methods", "methods", false},
  };
  return table;
}

std::vector<RenamedOption> renamed_options_in(const std::string& scope) {
  std::vector<RenamedOption> found;
  for (const RenamedOption& r : renamed_options())
    if (r.scope == scope) found.push_back(r);
  return found;
}

}  // namespace cshapes
