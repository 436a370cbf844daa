// Datasets for every multi-shape command: a folder of meshes, or a manifest.csv listing them.
//
// Folder: every mesh file in it (extensions .off .ply .obj .stl .vert, not recursive); the class is the file
// name without extension and trailing digits (TOSCA's convention: cat3.off -> class "cat", pose 3; victoria10
// -> "victoria", 10). Entries are sorted by class name, then pose number, then file name. A folder holding a
// manifest.csv is read through its manifest.
//
// manifest.csv: a header line naming the columns, then one line per shape; comma-separated, no quoting.
//   file   (required) path of the mesh, relative to the manifest's folder (or absolute), inside that folder
//          (see read_dataset's allow_outside)
//   class  (required) class label
//   pose   (optional) integer pose number, 0 or more (a negative one is refused; an empty cell is "not
//          given"); default: the file name's trailing digits, else the line's rank in its class
//   noisy  (optional) 0/1 (or false/true): whether the shape carries topological noise
// Any other column, a missing required column, a missing file, or an unreadable value is refused with a
// message naming the manifest, the line and the column or file. Manifest order is kept.
// FILE.cla: a Princeton Shape Benchmark classification (data/classification.h), each model id mapped to the
// file ID.off (.ply .obj .stl .vert) or mID.off … in the .cla's folder, the first that exists; classes as the
// file says, file order kept, pose = rank within the class. A missing file is refused naming the .cla line.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "cshapes/mesh/mesh.h"
#include "cshapes/support/option_declaration.h"

namespace cshapes {

// `--allow-outside` and allow_outside=: a dataset's manifest or .cla may list files outside its folder
// (declared once, support/option_declaration.h).
inline const OptionDeclaration kAllowOutsideOption{
    "allow_outside", "--allow-outside",
    "read manifest or .cla entries that lead outside the dataset's folder (refused by default)"};
// `--data` and data=: a dataset as every command that reads one takes it (an experiment that needs more of it
// says so in its own declaration, after this text).
inline const OptionDeclaration kDataOption{
    "data", "--data", "folder of meshes (class = name without trailing digits), manifest.csv or a .cla file"};
// `--shapes` and shapes=: a run restricted to some shapes of the dataset, by name.
inline const OptionDeclaration kShapesOption{
    "shapes", "--shapes", "only these shapes (names; comma-separated on the command line); default: all"};

struct DatasetEntry {
  std::string path;        // path to the mesh file (as found, or resolved against the manifest's folder)
  std::string name;        // file name without folder and extension ("cat3")
  std::string class_name;  // "cat"
  int pose = -1;           // pose number within the class
  bool noisy = false;      // topological noise (manifest column "noisy")
};

// A folder entry named like a mesh that is not a shape of the dataset: a loop of links, a dangling link, a
// FIFO, a folder, or a second file of one shape name (x.ply beside x.off: the first path in byte order is
// kept). The drivers leave it out and say so (pipeline/shape_failures.h: left_out_records; exit 3), the
// rest of the folder is read.
struct DatasetLeftOut {
  std::string path;
  std::string name;  // the file's name with its extension (x.ply: its stem may be a shape's name)
  std::string reason;
};

struct Dataset {
  std::string source;                 // the folder or manifest read
  std::vector<DatasetEntry> entries;  // see the ordering above
  std::vector<DatasetLeftOut> left_out;  // folder entries that are no shape of it, with the reason
  std::vector<std::string> classes;   // distinct class names, in order of first appearance
  // Pairs of entries (indices, first < second) whose files hold the same bytes under different names: both
  // kept (two queries of a benchmark), and said by the drivers (same_content_notes).
  std::vector<std::pair<size_t, size_t>> same_content;
  // Class index (into `classes`) of each entry.
  std::vector<int> labels() const;
};

// Reads a folder, a manifest.csv or a .cla file (by path). Throws cshapes::Error naming the problem: a file
// listed twice (two paths of one file), two files of one shape name in a manifest or .cla (biped0.off and
// sub/biped0.off: both files named), a folder without a mesh file. In a folder, entries named like a mesh
// that are no shape (see DatasetLeftOut) go to left_out.
// A dataset is its folder: a manifest's or .cla's entry that leads outside the folder of the manifest or .cla
// (a "../" path, an absolute path, a symbolic link; links are followed) is refused naming the line, unless
// allow_outside (the CLI's --allow-outside; drivers pass it for manifests they wrote themselves).
Dataset read_dataset(const std::string& path, bool allow_outside = false);

// The pairs of entries (indices, first < second) whose files hold the same bytes (what read_dataset records in
// Dataset::same_content), in index order: for drivers that gather their shapes without read_dataset (a
// TOPKIDS or TOSCA folder with its truth files) or choose some of a dataset's. Reads only the files whose
// size another file shares; a file that cannot be read throws cshapes::Error.
std::vector<std::pair<size_t, size_t>> same_content_pairs(const std::vector<DatasetEntry>& entries);

// One line per pair of Dataset::same_content ("bird02 and bird10 (paths) have the same content: ...").
std::vector<std::string> same_content_notes(const Dataset& d);

// The files that describe the dataset at `path` (what read_dataset reads besides the meshes): the manifest
// .csv or the .cla file itself, or a folder's manifest.csv when it has one; empty for a plain folder of
// meshes. No file is read: for checks before any work (check_output_not_input).
std::vector<std::string> dataset_description_files(const std::string& path);

// The name of the dataset at `path` in titles and reports: a folder's name ("tosca5k"), the folder's name of
// a manifest.csv, the stem of any other file (a .cla file: "test"). Trailing slashes and "." are resolved
// lexically; no file is read.
std::string dataset_name(const std::string& path);

// The class of a file name: the stem without trailing digits and a separator before them ("michael12" ->
// "michael", "horse_7" -> "horse"); the whole stem when it has no non-digit character.
std::string class_from_name(const std::string& stem);
// The trailing digits of a stem as a number, -1 when there are none.
int pose_from_name(const std::string& stem);

// Writes manifest.csv (columns file,class,pose,noisy) with paths relative to the manifest's folder when the
// files lie inside it. Atomic.
void write_manifest(const std::string& manifest_path, const std::vector<DatasetEntry>& entries);

// Writes an OFF file with a fixed number of decimals (e.g. "12.345678"), so that generated data is
// byte-identical across runs and platforms whose last-bit rounding differs. Atomic.
void write_off_fixed(const std::string& path, const Mesh& mesh, int decimals = 6);

}  // namespace cshapes
