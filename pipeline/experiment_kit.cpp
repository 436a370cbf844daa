#include "cshapes/pipeline/experiment_kit.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/build_info.h"
#include "cshapes/support/error.h"
#include "cshapes/support/simd.h"

namespace cshapes {

namespace fs = std::filesystem;

ExperimentFolder::ExperimentFolder(std::string root) : root_(std::move(root)) {
  CSHAPES_REQUIRE(!root_.empty(), "experiment: an output folder is required");
  std::error_code ec;
  fs::create_directories(root_, ec);
  if (ec || !fs::is_directory(root_))
    throw WriteError("cannot create the output folder " + root_ + ": " +
                     (ec ? ec.message() : "not a folder"));
}

std::string ExperimentFolder::path(const std::string& relative) const {
  return (fs::path(root_) / relative).string();
}

void ExperimentFolder::write(const std::string& relative,
                             const std::function<void(std::ostream&)>& write) const {
  write_file_atomically(path(relative), write);
}

void ExperimentFolder::write_text(const std::string& relative, const std::string& text) const {
  write(relative, [&](std::ostream& out) { out << text; });
}

void ExperimentFolder::write_json(const std::string& relative, const nlohmann::json& value) const {
  write(relative, [&](std::ostream& out) { out << value.dump(2) << '\n'; });
}

std::string ExperimentFolder::cache_directory(const std::string& name) const {
  return (fs::path(root_) / "cache" / name).string();
}

DiskCache ExperimentFolder::cache(const std::string& name) const {
  return DiskCache(cache_directory(name));
}

std::string format_number(const char* format, double value) {
  if (std::isnan(value)) return "—";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

nlohmann::json build_json() {
  return {{"version", version()}, {"build", build_description()}, {"simd", to_string(simd_target())}};
}

std::string build_sentence() {
  return "Computed by cshapes " + version() + " (" + build_description() + ") with the " +
         simd_description() + " kernels.";
}

std::string fixed(double value, int decimals) {
  if (!std::isfinite(value)) return "—";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

std::string percent(double fraction, int decimals) {
  if (!std::isfinite(fraction)) return "—";
  return fixed(100 * fraction, decimals) + "%";
}

}  // namespace cshapes
