#include "cshapes/data/classification.h"

#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"

namespace cshapes {
namespace fs = std::filesystem;

namespace {

struct Token {
  std::string text;
  int line = 0;
};

// Whitespace-separated tokens with their line numbers: the format allows any whitespace between tokens.
std::vector<Token> tokenize(const std::string& text) {
  std::vector<Token> tokens;
  std::stringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    std::stringstream words(line);
    std::string word;
    while (words >> word) tokens.push_back({word, number});
  }
  return tokens;
}

// A non-negative count, strictly ("12", not "12a" or "-1").
long parse_count(const Token& t, const std::string& where, const char* what) {
  bool digits = !t.text.empty() && t.text.size() <= 9;
  for (char c : t.text) digits = digits && c >= '0' && c <= '9';
  CSHAPES_REQUIRE(digits, where, ":", t.line, ": expected ", what, " (a count >= 0), got '", t.text, "'");
  return std::stol(t.text);
}

bool has_whitespace(const std::string& s) {
  return s.find_first_of(" \t\r\n\f\v") != std::string::npos;
}

}  // namespace

std::vector<std::string> Classification::models() const {
  std::vector<std::string> all;
  for (const ClassificationClass& c : classes) all.insert(all.end(), c.models.begin(), c.models.end());
  return all;
}

Classification parse_classification(const std::string& text, const std::string& where) {
  const std::vector<Token> tokens = tokenize(text);
  size_t at = 0;
  // The next token, or an error saying what was expected at the end of the file.
  auto next = [&](const std::string& what) -> const Token& {
    CSHAPES_REQUIRE(at < tokens.size(), where, ":", tokens.empty() ? 1 : tokens.back().line,
                    ": the file ends where ", what, " was expected");
    return tokens[at++];
  };
  const Token& magic = next("the header 'PSB 1'");
  CSHAPES_REQUIRE(magic.text == "PSB", where, ":", magic.line,
                  ": not a classification file (expected the header 'PSB 1', got '", magic.text, "')");
  const Token& version = next("the format version");
  CSHAPES_REQUIRE(version.text == "1", where, ":", version.line, ": format version '", version.text,
                  "' (only version 1 is known)");
  const Token& class_count_token = next("the number of classes");
  const long class_count = parse_count(class_count_token, where, "the number of classes");
  const Token& model_count_token = next("the number of models");
  const long model_count = parse_count(model_count_token, where, "the number of models");
  Classification c;
  std::set<std::string> names;
  std::map<std::string, int> model_line;
  for (long k = 0; k < class_count; ++k) {
    const std::string which = "class " + std::to_string(k + 1) + " of " + std::to_string(class_count);
    ClassificationClass cls;
    const Token& name = next("the name of " + which);
    cls.name = name.text;
    const Token& parent = next("the parent class of '" + cls.name + "'");
    cls.parent = parent.text;
    CSHAPES_REQUIRE(names.insert(cls.name).second, where, ":", name.line, ": class '", cls.name,
                    "' appears twice (class names must be unique)");
    CSHAPES_REQUIRE(cls.parent == "0" || (names.count(cls.parent) && cls.parent != cls.name), where, ":",
                    parent.line, ": class '", cls.name, "' has parent '", cls.parent,
                    "', which is not defined before it (parents come first; 0: the root)");
    const Token& count_token = next("the model count of class '" + cls.name + "'");
    const long count = parse_count(count_token, where, "the model count of its class");
    for (long m = 0; m < count; ++m) {
      CSHAPES_REQUIRE(at < tokens.size(), where, ":", count_token.line, ": class '", cls.name, "' says ",
                      count, " models, the file ends after ", m);
      const Token& id = tokens[at++];
      const auto [it, fresh] = model_line.emplace(id.text, id.line);
      CSHAPES_REQUIRE(fresh, where, ":", id.line, ": model '", id.text, "' is listed twice (first on line ",
                      it->second, "); each model belongs to one class");
      cls.models.push_back(id.text);
      cls.model_lines.push_back(id.line);
    }
    c.classes.push_back(std::move(cls));
  }
  CSHAPES_REQUIRE(at == tokens.size(), where, ":", at < tokens.size() ? tokens[at].line : 0, ": '",
                  at < tokens.size() ? tokens[at].text : "", "' after the last of the ", class_count,
                  " classes the header announces (a model count too small, or numClasses too small?)");
  CSHAPES_REQUIRE(static_cast<long>(model_line.size()) == model_count, where, ":", model_count_token.line,
                  ": the header announces ", model_count, " models, the classes list ", model_line.size());
  return c;
}

Classification read_classification(const std::string& path) {
  return parse_classification(read_text_file(path), path);
}

void write_classification(const std::string& path, const Classification& c) {
  std::set<std::string> names, models;
  for (const ClassificationClass& cls : c.classes) {
    CSHAPES_REQUIRE(!cls.name.empty() && !has_whitespace(cls.name) && cls.name != "0", path,
                    ": class name '", cls.name, "' cannot be written (empty, '0' or with whitespace)");
    CSHAPES_REQUIRE(names.insert(cls.name).second, path, ": class '", cls.name, "' twice");
    CSHAPES_REQUIRE(cls.parent == "0" || (names.count(cls.parent) && cls.parent != cls.name), path,
                    ": the parent '", cls.parent, "' of class '", cls.name, "' is not defined before it");
    for (const std::string& id : cls.models) {
      CSHAPES_REQUIRE(!id.empty() && !has_whitespace(id), path, ": model id '", id,
                      "' cannot be written (empty or with whitespace)");
      CSHAPES_REQUIRE(models.insert(id).second, path, ": model '", id, "' listed twice");
    }
  }
  write_file_atomically(path, [&](std::ostream& out) {
    out << "PSB 1\n" << c.classes.size() << ' ' << models.size() << '\n';
    for (const ClassificationClass& cls : c.classes) {
      out << '\n' << cls.name << ' ' << cls.parent << ' ' << cls.models.size() << '\n';
      for (const std::string& id : cls.models) out << id << '\n';
    }
  });
}

Classification classification_from_labels(const std::vector<std::string>& ids,
                                          const std::vector<std::string>& classes) {
  CSHAPES_REQUIRE(ids.size() == classes.size(), "classification_from_labels: ", ids.size(), " ids and ",
                  classes.size(), " classes");
  Classification c;
  std::map<std::string, size_t> index;
  for (size_t i = 0; i < ids.size(); ++i) {
    auto [it, fresh] = index.emplace(classes[i], c.classes.size());
    if (fresh) c.classes.push_back({classes[i], "0", {}, {}});
    c.classes[it->second].models.push_back(ids[i]);
  }
  return c;
}

std::string classification_model_file(const std::string& folder, const std::string& id) {
  for (const char* prefix : {"", "m"})
    for (const char* ext : {".off", ".ply", ".obj", ".stl", ".vert"}) {
      const fs::path file = fs::path(folder) / (prefix + id + ext);
      if (fs::is_regular_file(file)) return file.string();
    }
  return "";
}

}  // namespace cshapes
