// The rule that no output may be an input, as every command applies it (command.h).
#include <filesystem>

#include "cli/command.h"
#include "core/atomic_file.h"

namespace cshapes::cli {

void require_output_not_input(const std::string& output, const std::vector<std::string>& inputs,
                              const std::string& option) {
  try {
    check_output_not_input(output, inputs, option);
  } catch (const Error& e) {
    throw UsageError(e.what());
  }
}

void require_outputs_not_inputs(const std::string& folder, const std::vector<std::string>& names,
                                const std::vector<std::string>& inputs, const std::string& option) {
  for (const std::string& name : names)
    require_output_not_input((std::filesystem::path(folder) / name).string(), inputs, option);
}

}  // namespace cshapes::cli
