#include "cshapes/experiments/outside_methods_report.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "cshapes/pipeline/outside_methods.h"
#include "cshapes/support/atomic_file.h"

namespace fs = std::filesystem;

namespace cshapes {

std::vector<std::string> experiment_kept_folders() {
  return {"cache", kMethodLogsFolder};
}

void start_outside_methods(const std::string& out) {
  set_outside_method_logs((fs::path(out) / kMethodLogsFolder).string());
}

void finish_outside_methods(const std::vector<std::string>& methods, const std::string& out, const NoteFn& note,
                            const std::string& report_name) {
  const nlohmann::json doors = outside_methods_json(methods);
  if (doors.empty()) return;
  for (const std::string& file : write_forms_needed(methods, out))
    if (fs::path(file).extension() == ".csv")
      say(note, "warning: shapes without a form from " + fs::path(file).stem().string() + " are listed in " +
                    file + " with their meshes: compute them into the folder and rerun");
  write_file_atomically((fs::path(out) / "outside-methods.json").string(),
                        [&](std::ostream& o) { o << doors.dump(2) << "\n"; });
  const fs::path report = fs::path(out) / report_name;
  if (!fs::exists(report)) return;
  std::ostringstream text;
  {
    std::ifstream in(report);
    text << in.rdbuf();
  }
  text << "\n## Methods from outside\n\nEach under exactly the protocol of the built-in methods (the same ICP, "
          "distances and measures); its form is checked against the form contract before use "
          "(docs/outside-methods.md).\n\n"
       << outside_methods_markdown(methods);
  write_file_atomically(report.string(), [&](std::ostream& o) { o << text.str(); });
}

}  // namespace cshapes
