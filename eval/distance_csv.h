// Distance matrices between shapes as CSV, and class labels for them.
//
// Format written: a header row with the N shape names, then N rows of N numbers (%.9g), comma-separated.
// Formats read:
//   - that format;
//   - with a name column as well: header "name,<n1>,…,<nN>" (any first cell) and rows "<name_i>,d_i1,…";
//   - plain: N rows of N numbers and no header (names become "0", "1", …).
// Fields may be separated by commas, semicolons, tabs or spaces; blank lines and lines starting with '#'
// are skipped. "inf" and "nan" parse as such.
#pragma once

#include <string>
#include <vector>

#include "core/types.h"

namespace cshapes {

struct NamedDistances {
  std::vector<std::string> names;  // N
  Eigen::MatrixXd D;               // N×N
};

// Reads a matrix in any format above; throws naming the file and line on a ragged row, a non-number or a
// non-square matrix.
NamedDistances read_distance_csv(const std::string& path);
// Writes the header-row format, atomically.
void write_distance_csv(const std::string& path, const std::vector<std::string>& names,
                        const Eigen::MatrixXd& D);

// The class of a shape from its name, by the datasets' rule (core/dataset.h class_from_name) after
// dropping any directory and extension: "cat0" → "cat", "dir/victoria10.off" → "victoria".
std::string class_of_shape_name(const std::string& name);

// Classes from a labels file for the given shape names. Accepted:
//   "name,class" lines (an optional header "name,class"), matched by name (as given, or without directory
//   and extension), every shape needing a line; or one class per line, in the matrix's order.
std::vector<std::string> read_labels_csv(const std::string& path, const std::vector<std::string>& names);

}  // namespace cshapes
