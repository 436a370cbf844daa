#include "cshapes/eval/distance_csv.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>

#include "cshapes/support/atomic_file.h"
#include "cshapes/data/dataset.h"
#include "cshapes/support/error.h"

namespace cshapes {

namespace {

std::string trim(const std::string& s) {
  size_t a = s.find_first_not_of(" \t\r\n"), b = s.find_last_not_of(" \t\r\n");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

// Splits on commas, semicolons or tabs when present, else on runs of spaces.
std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> fields;
  bool delimited = line.find_first_of(",;\t") != std::string::npos;
  if (delimited) {
    std::string field;
    for (char c : line) {
      if (c == ',' || c == ';' || c == '\t') {
        fields.push_back(trim(field));
        field.clear();
      } else {
        field += c;
      }
    }
    fields.push_back(trim(field));
  } else {
    std::istringstream in(line);
    std::string field;
    while (in >> field) fields.push_back(field);
  }
  return fields;
}

bool parse_number(const std::string& text, double& value) {
  if (text.empty()) return false;
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  // The whole field: strtod stops at a NUL byte inside it ("5\0448" was read as 5).
  return end == text.c_str() + text.size();
}

std::vector<std::vector<std::string>> read_rows(const std::string& path, std::vector<int>& line_numbers) {
  std::istringstream in(read_text_file(path));
  std::vector<std::vector<std::string>> rows;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    rows.push_back(split_fields(t));
    line_numbers.push_back(number);
  }
  return rows;
}

std::string stem(const std::string& name) {
  return std::filesystem::path(name).stem().string();
}

}  // namespace

NamedDistances read_distance_csv(const std::string& path) {
  std::vector<int> line_of;
  std::vector<std::vector<std::string>> rows = read_rows(path, line_of);
  CSHAPES_REQUIRE(!rows.empty(), path, ": no distance matrix (the file is empty)");
  auto all_numbers = [](const std::vector<std::string>& fields, size_t from) {
    double v;
    for (size_t k = from; k < fields.size(); ++k)
      if (!parse_number(fields[k], v)) return false;
    return true;
  };
  NamedDistances result;
  size_t first_row = 0;
  // No header but a name column: every row "name,d_1,…,d_N" with N the number of rows.
  bool names_only_in_rows =
      rows[0].size() == rows.size() + 1 && !all_numbers(rows[0], 0) && all_numbers(rows[0], 1);
  bool header = !names_only_in_rows && !all_numbers(rows[0], 0);
  size_t n = header ? rows.size() - 1 : rows.size();
  // A name column: data rows with N+1 fields whose first is not a number (or a header with N+1 cells).
  bool name_column = false;
  if (header) {
    first_row = 1;
    std::vector<std::string> names = rows[0];
    double v;
    bool rows_named = rows.size() > 1 && !parse_number(rows[1][0], v);
    if (names.size() == n + 1 && rows_named) {
      name_column = true;
      names.erase(names.begin());
    }
    result.names = names;
  }
  if (!name_column && rows.size() > first_row && rows[first_row].size() == n + 1 &&
      !all_numbers(rows[first_row], 0))
    name_column = true;
  if (!header)
    for (size_t i = 0; i < n; ++i) result.names.push_back(name_column ? rows[i][0] : std::to_string(i));
  CSHAPES_REQUIRE(result.names.size() == n, path, ": the header names ", result.names.size(),
                  " shapes but there are ", n, " rows (expected a square matrix)");
  result.D.resize(static_cast<Index>(n), static_cast<Index>(n));
  for (size_t i = 0; i < n; ++i) {
    const std::vector<std::string>& fields = rows[first_row + i];
    const size_t offset = name_column ? 1 : 0;
    CSHAPES_REQUIRE(fields.size() == n + offset, path, ":", line_of[first_row + i], ": expected ", n + offset,
                    " fields, found ", fields.size());
    for (size_t j = 0; j < n; ++j) {
      double v;
      if (!parse_number(fields[j + offset], v))
        fail(path, ":", line_of[first_row + i], ": field ", j + offset + 1, " '", fields[j + offset],
             "' is not a number");
      result.D(static_cast<Index>(i), static_cast<Index>(j)) = v;
    }
  }
  return result;
}

void write_distance_csv(const std::string& path, const std::vector<std::string>& names,
                        const Eigen::MatrixXd& D) {
  CSHAPES_REQUIRE(D.rows() == D.cols() && static_cast<Index>(names.size()) == D.rows(), path, ": ",
                  names.size(), " names for a ", D.rows(), "x", D.cols(), " matrix");
  for (const std::string& name : names)
    CSHAPES_REQUIRE(name.find_first_of(",;\t\n") == std::string::npos && !name.empty(), path,
                    ": shape name '", name, "' is empty or contains a separator");
  write_file_atomically(path, [&](std::ostream& out) {
    for (size_t k = 0; k < names.size(); ++k) out << (k ? "," : "") << names[k];
    out << '\n';
    char buffer[32];
    for (Index i = 0; i < D.rows(); ++i) {
      for (Index j = 0; j < D.cols(); ++j) {
        std::snprintf(buffer, sizeof buffer, "%.9g", D(i, j));
        out << (j ? "," : "") << buffer;
      }
      out << '\n';
    }
  });
}

void write_dissimilarity_text(const std::string& path, const Eigen::MatrixXd& D) {
  CSHAPES_REQUIRE(D.rows() == D.cols(), path, ": a ", D.rows(), "x", D.cols(), " matrix is not square");
  write_file_atomically(path, [&](std::ostream& out) {
    char buffer[32];
    for (Index i = 0; i < D.rows(); ++i) {
      for (Index j = 0; j < D.cols(); ++j) {
        std::snprintf(buffer, sizeof buffer, "%.9g", D(i, j));
        out << (j ? " " : "") << buffer;
      }
      out << '\n';
    }
  });
}

void write_psb_matrix(const std::string& path, const Eigen::MatrixXd& D) {
  CSHAPES_REQUIRE(D.rows() == D.cols(), path, ": a ", D.rows(), "x", D.cols(), " matrix is not square");
  write_file_atomically(path, [&](std::ostream& out) {
    for (Index i = 0; i < D.rows(); ++i)
      for (Index j = 0; j < D.cols(); ++j) {
        const float value = static_cast<float>(D(i, j));
        std::uint32_t bits;
        std::memcpy(&bits, &value, sizeof bits);
        // Little-endian whatever the host's order: the file means the same everywhere.
        const char bytes[4] = {static_cast<char>(bits & 0xff), static_cast<char>((bits >> 8) & 0xff),
                               static_cast<char>((bits >> 16) & 0xff), static_cast<char>(bits >> 24)};
        out.write(bytes, 4);
      }
  }, /*binary=*/true);
}

std::string class_of_shape_name(const std::string& name) {
  return class_from_name(stem(name));
}

std::vector<std::string> read_labels_csv(const std::string& path, const std::vector<std::string>& names) {
  std::vector<int> line_of;
  std::vector<std::vector<std::string>> rows = read_rows(path, line_of);
  if (!rows.empty() && rows[0].size() == 2 && rows[0][0] == "name" && rows[0][1] == "class") {
    rows.erase(rows.begin());
    line_of.erase(line_of.begin());
  }
  std::vector<std::string> classes;
  if (!rows.empty() && rows[0].size() == 1) {
    CSHAPES_REQUIRE(rows.size() == names.size(), path, ": ", rows.size(), " class lines for ", names.size(),
                    " shapes (one class per line, in the matrix's order)");
    for (size_t i = 0; i < rows.size(); ++i) {
      CSHAPES_REQUIRE(rows[i].size() == 1, path, ":", line_of[i], ": expected one class name");
      CSHAPES_REQUIRE(!rows[i][0].empty(), path, ":", line_of[i], ": empty class name");
      classes.push_back(rows[i][0]);
    }
    return classes;
  }
  std::map<std::string, std::string> by_name;
  std::map<std::string, size_t> row_of;  // where each name got its class
  for (size_t i = 0; i < rows.size(); ++i) {
    CSHAPES_REQUIRE(rows[i].size() == 2, path, ":", line_of[i], ": expected 'name,class', found ",
                    rows[i].size(), " fields");
    // An empty class would put every such shape in class '' (all queries hits: mAP 1.0).
    CSHAPES_REQUIRE(!rows[i][0].empty() && !rows[i][1].empty(), path, ":", line_of[i], ": empty ",
                    rows[i][0].empty() ? "shape name" : "class name", ", expected 'name,class'");
    const auto [first, inserted] = row_of.emplace(rows[i][0], i);
    CSHAPES_REQUIRE(inserted || rows[first->second][1] == rows[i][1], path, ":", line_of[i], ": shape '",
                    rows[i][0], "' has class '", rows[i][1], "' here and '", rows[first->second][1],
                    "' on line ", line_of[first->second]);
    by_name[rows[i][0]] = rows[i][1];
    by_name.emplace(stem(rows[i][0]), rows[i][1]);
  }
  for (const std::string& name : names) {
    auto it = by_name.find(name);
    if (it == by_name.end()) it = by_name.find(stem(name));
    CSHAPES_REQUIRE(it != by_name.end(), path, ": no class given for shape '", name, "'");
    classes.push_back(it->second);
  }
  return classes;
}

std::string labels_path_for(const std::string& matrix_path) {
  std::filesystem::path path(matrix_path);
  return path.replace_extension(".labels.csv").string();
}

namespace {

// The description's fields with their names in the labels file, in the order they are written.
std::vector<std::pair<const char*, std::string*>> description_fields(MatrixDescription& d) {
  return {{"method", &d.method}, {"distance", &d.distance}, {"data", &d.data}};
}

}  // namespace

MatrixDescription read_matrix_description(const std::string& labels_path) {
  MatrixDescription description;
  std::istringstream in(read_text_file(labels_path));
  std::string line;
  while (std::getline(in, line)) {
    const std::string t = trim(line);
    if (t.empty() || t[0] != '#') continue;
    const std::string comment = trim(t.substr(1));
    const size_t colon = comment.find(':');
    if (colon == std::string::npos) continue;
    for (const auto& [name, field] : description_fields(description))
      if (comment.compare(0, colon, name) == 0 && std::string(name).size() == colon)
        *field = trim(comment.substr(colon + 1));
  }
  return description;
}

std::string matrix_description_text(const MatrixDescription& description) {
  std::string text;
  const auto add = [&](const std::string& part) {
    if (!part.empty()) text += (text.empty() ? "" : ", ") + part;
  };
  add(description.method);
  add(description.distance.empty() ? "" : description.distance + " distance");
  add(description.data);
  return text;
}

void write_labels_csv(const std::string& path, const std::vector<std::string>& names,
                      const std::vector<std::string>& classes, const MatrixDescription& description) {
  MatrixDescription recorded = description;
  for (const auto& [name, field] : description_fields(recorded))
    CSHAPES_REQUIRE(field->find_first_of("\r\n") == std::string::npos, path, ": the matrix's ", name, " '",
                    *field, "' holds a line break");
  CSHAPES_REQUIRE(names.size() == classes.size(), path, ": ", names.size(), " names but ", classes.size(),
                  " classes");
  for (size_t i = 0; i < names.size(); ++i)
    for (const std::string* text : {&names[i], &classes[i]})
      CSHAPES_REQUIRE(!text->empty() && text->find_first_of(",;\t\n") == std::string::npos, path, ": ",
                      text == &names[i] ? "shape name" : "class", " '", *text, "' of shape ", i + 1,
                      " is empty or contains a separator");
  write_file_atomically(path, [&](std::ostream& out) {
    for (const auto& [name, field] : description_fields(recorded))
      if (!field->empty()) out << "# " << name << ": " << *field << '\n';
    out << "name,class\n";
    for (size_t i = 0; i < names.size(); ++i) out << names[i] << ',' << classes[i] << '\n';
  });
}

const char* const kDistanceMatrixRules =
    "refused: two shapes of one name, a NaN or a negative distance; warned: an asymmetric matrix (each query "
    "ranks its own row, as given) and a non-zero diagonal (unused: a query is never ranked against itself)";

std::vector<std::string> check_distance_matrix(const NamedDistances& input, const std::string& source) {
  const Eigen::MatrixXd& D = input.D;
  const Index n = D.rows();
  CSHAPES_REQUIRE(D.cols() == n && static_cast<Index>(input.names.size()) == n, source, ": ", n, "x",
                  D.cols(), " matrix with ", input.names.size(), " names");
  std::map<std::string, size_t> first_of;
  for (size_t i = 0; i < input.names.size(); ++i) {
    const auto [it, inserted] = first_of.emplace(input.names[i], i);
    CSHAPES_REQUIRE(inserted, source, ": shape name '", input.names[i], "' appears twice (rows ",
                    it->second + 1, " and ", i + 1, "): each shape must appear once");
  }
  double largest = 0;
  for (Index i = 0; i < n; ++i)
    for (Index j = 0; j < n; ++j) {
      const double d = D(i, j);
      CSHAPES_REQUIRE(!std::isnan(d), source, ": distance from '", input.names[i], "' to '", input.names[j],
                      "' is NaN");
      CSHAPES_REQUIRE(d >= 0, source, ": distance from '", input.names[i], "' to '", input.names[j], "' is ",
                      d, ", expected >= 0");
      if (std::isfinite(d)) largest = std::max(largest, d);
    }
  std::vector<std::string> warnings;
  const double tolerance = 1e-9 * largest;
  long asymmetric = 0, diagonal = 0;
  Index worst_i = 0, worst_j = 0, worst_k = 0;
  double worst = 0, worst_diagonal = 0;
  for (Index i = 0; i < n; ++i) {
    if (D(i, i) > tolerance) {
      ++diagonal;
      if (D(i, i) > worst_diagonal) worst_diagonal = D(i, i), worst_k = i;
    }
    for (Index j = i + 1; j < n; ++j) {
      const double gap = D(i, j) == D(j, i) ? 0 : std::abs(D(i, j) - D(j, i));
      if (!(gap > tolerance)) continue;
      ++asymmetric;
      if (!(gap <= worst)) worst = gap, worst_i = i, worst_j = j;
    }
  }
  auto name = [&](Index i) { return "'" + input.names[static_cast<size_t>(i)] + "'"; };
  if (asymmetric > 0)
    warnings.push_back(detail::concat(source, ": not symmetric: ", asymmetric, " pairs differ, most ",
                                      name(worst_i), " and ", name(worst_j), " (", D(worst_i, worst_j),
                                      " vs ", D(worst_j, worst_i), "); each query ranks its own row"));
  if (diagonal > 0)
    warnings.push_back(detail::concat(source, ": ", diagonal, " non-zero diagonal entries, largest ",
                                      name(worst_k), " (", worst_diagonal,
                                      "); unused: a query is never ranked against itself"));
  return warnings;
}

}  // namespace cshapes
