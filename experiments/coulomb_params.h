// The parameter study behind the Coulomb defaults (`cshapes experiment coulomb-params`).
//
// For every shape and every configuration (the defaults with one choice changed: k, step rule, L1/L2,
// tearing time/fraction, scheme, ...), it canonizes the clean shape and a glued version of it — the same
// vertices with K bridge edges between vertex pairs that are close in space but far along the surface (the
// paper's topological noise) — and records the violation, the energy, iterations, time, how many bridges
// were torn, and the RMS distance between the glued and the clean canonical forms after rigid alignment
// (same vertex order), relative to the clean form's bounding-box diagonal. With partners, it also canonizes
// another pose of the same class and measures pose invariance: the RMS distance between ground-truth
// corresponding samples (corres/*.vts) of the two canonical forms after rigid alignment, beside the same for
// the two input poses.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cshapes/canon/coulomb.h"

namespace cshapes {

// One configuration of the study: a name and how it changes the default options.
struct CoulombParamsConfig {
  std::string name;
  std::function<void(CoulombCanonOptions&)> apply;
};
// Every configuration, "default" first.
const std::vector<CoulombParamsConfig>& coulomb_params_configs();

struct CoulombParamsOptions {
  std::string data;  // folder of NAME.off shapes (and corres/NAME.vts)
  std::vector<std::string> shapes = {"cat0", "michael0"};
  std::vector<std::string> partners = {"cat1", "michael1"};  // one per shape, or none
  std::vector<std::string> configs;              // names from coulomb_params_configs(); empty: all
  int bridges = 8;                               // bridge edges glued per shape
  int max_iterations = 600;                      // iteration cap per run
  std::function<void(const std::string&)> note;  // one line per shape and per run
};

struct CoulombParamsRow {
  std::string shape, config;
  int iterations = 0;
  double seconds = 0;
  bool converged = false;
  double energy = 0, mean_violation = 0, max_violation = 0;
  int glued_iterations = 0;
  double glued_seconds = 0;
  int bridges = 0, bridges_torn = 0;
  double glued_rms_to_clean = 0;  // / the clean form's bbox diagonal
  double pose_rms = -1;           // −1: no partner
  double input_pose_rms = -1;
};

std::vector<CoulombParamsRow> run_coulomb_params(const CoulombParamsOptions& options);

// OUT/coulomb_params.csv and OUT/coulomb_params.md (written atomically); returns the Markdown table.
std::string write_coulomb_params(const std::string& out, const std::vector<CoulombParamsRow>& rows);

// The rows as JSON (what `experiment coulomb-params --json` prints): every column of coulomb_params.csv at full
// precision, pose distances null where a shape has no partner.
nlohmann::json coulomb_params_json(const std::vector<CoulombParamsRow>& rows);

}  // namespace cshapes
