#include "cshapes/pipeline/experiment_kit.h"

#include <algorithm>
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

nlohmann::json stage_times_json(const std::vector<StageTime>& profile) {
  nlohmann::json stages = nlohmann::json::array();
  for (const StageTime& t : profile)
    stages.push_back({{"stage", t.stage},
                      {"method", t.method},
                      {"wall_seconds", t.wall_seconds},
                      {"cpu_seconds", t.cpu_seconds}});
  return stages;
}

std::string stage_times_markdown(const std::vector<StageTime>& profile, int cores) {
  double wall = 0, cpu = 0;
  for (const StageTime& t : profile) {
    wall += t.wall_seconds;
    cpu += t.cpu_seconds;
  }
  std::string out =
      "| stage | method | wall s | CPU s | cores busy | idle |\n|---|---|---:|---:|---:|---:|\n";
  auto row = [&](const std::string& stage, const std::string& method, double w, double c) {
    const double busy = w > 0 ? c / w : NAN;
    out += "| " + stage + " | " + method + " | " + fixed(w, 1) + " | " + fixed(c, 1) + " | " + fixed(busy, 2) +
           " | " + percent(std::isfinite(busy) ? std::max(0.0, 1 - busy / std::max(1, cores)) : NAN, 0) +
           " |\n";
  };
  double small_wall = 0, small_cpu = 0;
  int small = 0;
  for (const StageTime& t : profile) {
    if (t.wall_seconds < 0.01 * wall) {
      small_wall += t.wall_seconds;
      small_cpu += t.cpu_seconds;
      ++small;
      continue;
    }
    row(t.stage, t.method.empty() ? "—" : t.method, t.wall_seconds, t.cpu_seconds);
  }
  if (small > 0) row(std::to_string(small) + " short stages", "—", small_wall, small_cpu);
  row("**total**", "", wall, cpu);
  return out;
}

}  // namespace cshapes
