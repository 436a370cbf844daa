// Helpers shared by the GoogleTest files: where the shared data is, scratch directories, running the CLI.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cshapes/mesh/mesh.h"

namespace cshapes::test {

// The TOSCA data folder: $CSHAPES_DATA, else ../shared/data beside the repository. "" when absent.
std::string data_dir();
// Path of a tosca5k shape, e.g. tosca5k("cat0") -> ".../tosca5k/cat0.off". Skips the test when absent
// (use inside a TEST body via CSHAPES_REQUIRE_DATA).
std::string tosca5k(const std::string& name);

// The message of the cshapes::Error that f throws ("" when it throws none; any other exception passes).
std::string error_of(const std::function<void()>& f);

// A fresh empty directory under the build's temp area, unique per call.
std::string scratch_dir(const std::string& tag);

struct CliResult {
  int exit_code = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};
// Runs build/cshapes (or $CSHAPES_CLI when set) with the given argument string (shell-quoted by the caller).
CliResult run_cli(const std::string& arguments);

// Mean of |d - exact| / exact over the entries whose exact value exceeds min_distance (the error measure of the
// geodesics tests: near the source relative errors are meaningless). Fails the test when no entry qualifies.
double mean_relative_error(const Eigen::VectorXd& d, const Eigen::VectorXd& exact, double min_distance);

// A flat grid of nx × ny vertices in the unit-wide strip, rows shifted by half a spacing and squashed
// vertically: every triangle has an obtuse angle of about 127°, so the cotangent Laplacian has negative weights
// and fast marching needs its unfolding step.
Mesh obtuse_grid(int nx, int ny);

// A closed sausage (an icosphere stretched along a circle of radius 3, 1 thick) bent so that its two ends
// almost touch, end_gap_angle radians apart: one place with a small Euclidean and a large geodesic distance,
// and nowhere else. Remeshed to about 2,000 isotropic triangles' vertices.
Mesh bent_sausage(double end_gap_angle);

// Signed volume enclosed by the triangles, Σ v0·(v1 × v2) / 6: positive when the faces are counter-clockwise
// seen from outside; unchanged by any refinement that keeps the surface and its orientation.
double signed_volume(const Mesh& m);

// A generated articulated dataset written without the CLI (data/articulated.h): `classes` classes ×
// `poses` clean poses of about `vertices` vertices each (no noisy poses), CLASSk.off and manifest.csv in dir;
// returns the manifest's path. Deterministic (seed 0), as `cshapes generate dataset` writes it.
std::string generated_dataset(const std::string& dir, int classes, int poses, long vertices);

// Writes text to a file (creating parent directories).
void write_text(const std::string& path, const std::string& text);

// The failures of a run's JSON report (`--json`: "failures") that left their shape out. Every other failure
// must be a form kept and named "not converged" (a test's short --coulomb-max-iterations): checked here.
std::vector<nlohmann::json> left_out_failures(const nlohmann::json& report);

}  // namespace cshapes::test

// Skips the current test with a message when the shared TOSCA data is not available.
#define CSHAPES_REQUIRE_DATA()                                                                 \
  do {                                                                                          \
    if (::cshapes::test::data_dir().empty()) GTEST_SKIP() << "../shared/data not found (set CSHAPES_DATA)"; \
  } while (0)
