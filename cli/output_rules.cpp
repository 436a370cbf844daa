// The rule that no output may be an input, as every command applies it (command.h).
#include <filesystem>

#include "cli/command.h"
#include "cshapes/support/atomic_file.h"

namespace cshapes::cli {

void require_output_not_input(const std::string& output, const std::vector<std::string>& inputs,
                              const std::string& option) {
  try {
    check_output_not_input(output, inputs, option);
  } catch (const Error& e) {
    throw UsageError(e.what());
  }
}

void require_output_folder_apart(const std::string& out, const std::string& data) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (out.empty() || data.empty() || !fs::is_directory(out, ec)) return;
  const fs::path folder = fs::is_directory(data, ec) ? fs::path(data) : fs::path(data).parent_path();
  std::error_code same_ec;
  if (fs::equivalent(out, folder.empty() ? fs::path(".") : folder, same_ec) && !same_ec)
    usage_fail("--out ", out, ": is the folder of the dataset ", data,
               "; an output never replaces an input: write the run to another folder");
}

void require_outputs_not_inputs(const std::string& folder, const std::vector<std::string>& names,
                                const std::vector<std::string>& inputs, const std::string& option) {
  for (const std::string& name : names)
    require_output_not_input((std::filesystem::path(folder) / name).string(), inputs, option);
}

}  // namespace cshapes::cli
