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

#include "cshapes/support/types.h"

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

// The forms the evaluation tools read, without names (rows and columns in the order of the collection's .cla
// file, data/classification.h), each written atomically:
//   text  N lines of N numbers (%.9g) separated by one space: the plain dissimilarity matrix that the SHREC
//         non-rigid retrieval tracks' evaluation code reads (and read_distance_csv, as its "plain" format).
//   PSB   N×N 32-bit IEEE floats, row-major (entry i·N + j is D(i, j)), little-endian, no header: the
//         Princeton Shape Benchmark's .matrix, which its psbTable and psbPRCurve read with a .cla file.
void write_dissimilarity_text(const std::string& path, const Eigen::MatrixXd& D);
void write_psb_matrix(const std::string& path, const Eigen::MatrixXd& D);

// What a distance matrix must be before retrieval is measured on it, by rule (the text below is also
// `cshapes evaluate --help`'s). Refused (throws cshapes::Error naming the file and the shapes): two shapes
// of one name, a NaN or a negative distance. Warned (one line each, returned): an asymmetric matrix (beyond
// 1e-9 of its largest finite entry; each query ranks its own row, as given) and a non-zero diagonal (a query
// is never ranked against itself, so its diagonal entry is unused).
extern const char* const kDistanceMatrixRules;
std::vector<std::string> check_distance_matrix(const NamedDistances& input, const std::string& source);

// The class of a shape from its name, by the datasets' rule (data/dataset.h class_from_name) after
// dropping any directory and extension: "cat0" → "cat", "dir/victoria10.off" → "victoria".
std::string class_of_shape_name(const std::string& name);

// Classes from a labels file for the given shape names. Accepted:
//   "name,class" lines (an optional header "name,class"), matched by name (as given, or without directory
//   and extension), every shape needing a line; or one class per line, in the matrix's order. A name given
//   twice with two classes is refused, naming both lines.
std::vector<std::string> read_labels_csv(const std::string& path, const std::vector<std::string>& names);

// The labels file that goes with a distance matrix: its path with the extension replaced, D.csv →
// D.labels.csv. `cshapes distmat` writes it beside every matrix, and `cshapes evaluate` reads it when no
// --labels is given, so the classes of a manifest reach the measures whatever the file names.
std::string labels_path_for(const std::string& matrix_path);
// What a distance matrix measures, in words for figures and reports: `cshapes distmat` records it in the
// labels file it writes beside the matrix, as comment lines above the header that every reader of the file
// skips
//   # method: Coulomb
//   # distance: Hausdorff
//   # data: tosca5k
// and `cshapes evaluate` names it in its figures' titles. An empty field: not recorded.
struct MatrixDescription {
  std::string method;    // the method's title ("Coulomb", "classical MDS")
  std::string distance;  // the distance between shapes ("Hausdorff")
  std::string data;      // the collection ("tosca5k")
};
// The description in a labels file's comment lines (the fields above, each on a line "# FIELD: VALUE");
// empty fields for a file without them. Throws naming the file when it cannot be read.
MatrixDescription read_matrix_description(const std::string& labels_path);
// "Coulomb, Hausdorff distance, tosca5k": the fields recorded, in that order; "" when none is.
std::string matrix_description_text(const MatrixDescription& description);

// Writes "name,class" lines under the header "name,class" (what read_labels_csv reads), atomically, with the
// description's recorded fields as comment lines above them. Throws naming the file on a name or class that
// is empty or holds a separator, or a description field that holds a line break.
void write_labels_csv(const std::string& path, const std::vector<std::string>& names,
                      const std::vector<std::string>& classes, const MatrixDescription& description = {});

}  // namespace cshapes
