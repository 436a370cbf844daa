#include "cshapes/support/option_declaration.h"

#include <algorithm>
#include <utility>

namespace cshapes {

std::string keyword_flag(const std::string& keyword) {
  std::string flag = "--" + keyword;
  std::replace(flag.begin() + 2, flag.end(), '_', '-');
  return flag;
}

OptionDeclaration negated_option(std::string keyword, std::string flag, std::string help) {
  OptionDeclaration option(std::move(keyword), std::move(flag), std::move(help));
  option.negated = true;
  return option;
}

std::string option_help(const OptionDeclaration& option, OptionSkin skin) {
  std::string out = option.negated && skin == OptionSkin::Cli ? "do not " : "";
  const std::string& text = option.help;
  for (size_t k = 0; k < text.size();) {
    const size_t open = text.find('{', k);
    const size_t close = open == std::string::npos ? std::string::npos : text.find('}', open);
    if (close == std::string::npos) {
      out += text.substr(k);
      break;
    }
    const std::string name = text.substr(open + 1, close - open - 1);
    const bool keyword = !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
      return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
    });
    out += text.substr(k, open - k);
    out +=
        keyword ? (skin == OptionSkin::Cli ? keyword_flag(name) : name) : text.substr(open, close - open + 1);
    k = close + 1;
  }
  return out;
}

}  // namespace cshapes
