#include "cshapes/data/dataset.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <sstream>
#include <vector>

#include "cshapes/support/atomic_file.h"
#include "cshapes/data/classification.h"
#include "cshapes/support/error.h"
#include "cshapes/mesh/io.h"

namespace cshapes {
namespace fs = std::filesystem;

namespace {

bool is_mesh_extension(const std::string& ext) {
  return ext == "off" || ext == "ply" || ext == "obj" || ext == "stl" || ext == "vert";
}

std::string trim(const std::string& s) {
  size_t b = s.find_first_not_of(" \t\r"), e = s.find_last_not_of(" \t\r");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  std::string cell;
  while (std::getline(in, cell, ',')) cells.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') cells.push_back("");
  return cells;
}

// What a folder entry named like a mesh is when it is not a regular file (links followed); "" for a regular
// file. Asked with error codes: a loop of links is an answer, not a raw filesystem_error.
std::string not_a_mesh_file(const fs::directory_entry& item) {
  std::error_code ec;
  const fs::file_status status = fs::status(item.path(), ec);
  if (ec && ec.value() == ELOOP) return "a loop of symbolic links";
  if (ec || status.type() == fs::file_type::not_found)
    return fs::is_symlink(fs::symlink_status(item.path(), ec)) ? "a symbolic link to nothing (dangling)"
                                                               : "unreadable (" + ec.message() + ")";
  switch (status.type()) {
    case fs::file_type::regular:
      return "";
    case fs::file_type::directory:
      return "a folder";
    case fs::file_type::fifo:
      return "a FIFO (named pipe)";
    case fs::file_type::socket:
      return "a socket";
    case fs::file_type::character:
    case fs::file_type::block:
      return "a device";
    default:
      return "not a regular file";
  }
}

Dataset read_folder(const fs::path& folder) {
  Dataset d;
  d.source = folder.string();
  std::error_code ec;
  fs::directory_iterator items(folder, ec);
  CSHAPES_REQUIRE(!ec, folder.string(), ": cannot list the folder: ", ec.message());
  // Every entry named like a mesh is a shape, or it is left out with its reason (never skipped without a
  // word, never the end of the run).
  std::vector<fs::path> paths;
  for (const auto& item : items) {
    if (!is_mesh_extension(file_extension(item.path().string()))) continue;
    const std::string problem = not_a_mesh_file(item);
    if (!problem.empty()) {
      d.left_out.push_back({item.path().string(), item.path().filename().string(),
                            "is " + problem + ", expected a mesh file; remove or rename it"});
      continue;
    }
    paths.push_back(item.path());
  }
  // Shapes are named by their file's stem (reports, matrices, labels): of x.off beside x.ply, which
  // `evaluate` would refuse as two shapes of one name, the first path in byte order is the shape.
  std::sort(paths.begin(), paths.end());
  std::map<std::string, std::string> by_name;
  for (const fs::path& path : paths) {
    DatasetEntry e;
    e.path = path.string();
    e.name = path.stem().string();
    const auto [it, inserted] = by_name.emplace(e.name, e.path);
    if (!inserted) {
      d.left_out.push_back({e.path, path.filename().string(),  // the file's name: its stem is the shape's
                            "is a second file of shape '" + e.name + "' (" + it->second +
                                " is that shape: shapes are named by their file name without extension); "
                                "rename it, or list the shapes in a manifest.csv"});
      continue;
    }
    e.class_name = class_from_name(e.name);
    e.pose = pose_from_name(e.name);
    d.entries.push_back(e);
  }
  std::sort(d.left_out.begin(), d.left_out.end(),
            [](const DatasetLeftOut& a, const DatasetLeftOut& b) { return a.path < b.path; });
  CSHAPES_REQUIRE(!d.entries.empty(), folder.string(), ": no mesh files (.off .ply .obj .stl .vert) in this folder",
                  d.left_out.empty() ? "" : " (" + std::to_string(d.left_out.size()) +
                                                " entries named like one are not: the first " +
                                                d.left_out.front().path + " " + d.left_out.front().reason + ")");
  std::sort(d.entries.begin(), d.entries.end(), [](const DatasetEntry& a, const DatasetEntry& b) {
    if (a.class_name != b.class_name) return a.class_name < b.class_name;
    if (a.pose != b.pose) return a.pose < b.pose;
    return a.name < b.name;
  });
  return d;
}

// Where `file` (a manifest's or .cla's entry) really is, links followed, when that lies inside `folder` (the
// dataset's); "" when it lies outside.
std::string real_path_inside(const fs::path& file, const fs::path& folder) {
  std::error_code ec;
  const fs::path real = fs::weakly_canonical(file, ec), root = fs::weakly_canonical(folder.empty() ? "." : folder, ec);
  if (ec) return "";
  auto r = real.begin(), f = root.begin();
  for (; f != root.end(); ++f, ++r)
    if (r == real.end() || *r != *f) return "";
  return real.string();
}

// The refusal of an entry outside the dataset's folder: names the entry as written and where it leads, never
// anything read from it.
[[noreturn]] void refuse_outside(const std::string& where, const std::string& entry, const fs::path& file,
                                 const fs::path& folder) {
  std::error_code ec;
  fail(where, ": '", entry, "' leads to ", fs::weakly_canonical(file, ec).string(),
       ", outside the dataset's folder ", fs::weakly_canonical(folder.empty() ? "." : folder, ec).string(),
       " (a dataset is its folder; pass --allow-outside to read files elsewhere)");
}

Dataset read_manifest(const fs::path& manifest, bool allow_outside) {
  Dataset d;
  d.source = manifest.string();
  const std::string where = manifest.string();
  std::stringstream text(read_text_file(where));
  std::string line;
  int line_number = 0;
  std::vector<std::string> columns;
  int col_file = -1, col_class = -1, col_pose = -1, col_noisy = -1;
  while (std::getline(text, line)) {
    ++line_number;
    if (trim(line).empty()) continue;
    std::vector<std::string> cells = split_csv_line(line);
    if (columns.empty()) {
      columns = cells;
      for (size_t c = 0; c < columns.size(); ++c) {
        const std::string& name = columns[c];
        int* slot = name == "file"    ? &col_file
                    : name == "class" ? &col_class
                    : name == "pose"  ? &col_pose
                    : name == "noisy" ? &col_noisy
                                      : nullptr;
        CSHAPES_REQUIRE(slot, where, ":", line_number, ": unknown column '", name,
                        "' (known: file, class, pose, noisy)");
        CSHAPES_REQUIRE(*slot < 0, where, ":", line_number, ": column '", name, "' appears twice");
        *slot = static_cast<int>(c);
      }
      CSHAPES_REQUIRE(col_file >= 0, where, ":", line_number, ": the header has no 'file' column");
      CSHAPES_REQUIRE(col_class >= 0, where, ":", line_number, ": the header has no 'class' column");
      continue;
    }
    CSHAPES_REQUIRE(cells.size() == columns.size(), where, ":", line_number, ": ", cells.size(),
                    " fields, the header has ", columns.size());
    DatasetEntry e;
    fs::path file = cells[col_file];
    CSHAPES_REQUIRE(!file.empty(), where, ":", line_number, ": empty 'file'");
    if (file.is_relative()) file = manifest.parent_path() / file;
    e.path = file.string();
    if (!allow_outside && real_path_inside(file, manifest.parent_path()).empty())
      refuse_outside(where + ":" + std::to_string(line_number), cells[col_file], file, manifest.parent_path());
    CSHAPES_REQUIRE(fs::is_regular_file(file), where, ":", line_number, ": file '", cells[col_file],
                    "' not found (looked for ", e.path, ")");
    e.name = file.stem().string();
    e.class_name = cells[col_class];
    CSHAPES_REQUIRE(!e.class_name.empty(), where, ":", line_number, ": empty 'class' for ", cells[col_file]);
    e.pose = pose_from_name(e.name);
    if (col_pose >= 0 && !cells[col_pose].empty()) {  // an empty cell: not given
      const std::string& v = cells[col_pose];
      size_t used = 0;
      try {
        e.pose = std::stoi(v, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      CSHAPES_REQUIRE(!v.empty() && used == v.size(), where, ":", line_number,
                      ": 'pose' must be an integer, got '", v, "'");
      CSHAPES_REQUIRE(e.pose >= 0, where, ":", line_number, ": 'pose' must be 0 or more, got ", e.pose);
    }
    if (col_noisy >= 0) {
      const std::string& v = cells[col_noisy];
      CSHAPES_REQUIRE(v == "0" || v == "1" || v == "true" || v == "false", where, ":", line_number,
                      ": 'noisy' must be 0, 1, true or false, got '", v, "'");
      e.noisy = v == "1" || v == "true";
    }
    d.entries.push_back(e);
  }
  CSHAPES_REQUIRE(!columns.empty(), where,
                  ": empty manifest (expected a header line: file,class[,pose,noisy])");
  CSHAPES_REQUIRE(!d.entries.empty(), where, ": the manifest lists no shapes");
  // Poses not given and not in the name: rank within the class.
  std::map<std::string, int> rank;
  for (auto& e : d.entries) {
    int r = rank[e.class_name]++;
    if (e.pose < 0) e.pose = r;
  }
  return d;
}

// A .cla file: its models' files by classification_model_file, in file order; pose = rank in the class.
Dataset read_classification_dataset(const fs::path& cla, bool allow_outside) {
  Dataset d;
  d.source = cla.string();
  const Classification c = read_classification(cla.string());
  const std::string folder = cla.parent_path().empty() ? "." : cla.parent_path().string();
  for (const ClassificationClass& cls : c.classes)
    for (size_t k = 0; k < cls.models.size(); ++k) {
      const std::string& id = cls.models[k];
      DatasetEntry e;
      e.path = classification_model_file(folder, id);
      CSHAPES_REQUIRE(!e.path.empty(), d.source, ":", cls.model_lines[k], ": model '", id, "' of class '",
                      cls.name, "': no file ", id, ".off (or .ply .obj .stl .vert, or m", id,
                      ".off …) in ", folder);
      if (!allow_outside && real_path_inside(e.path, folder).empty())
        refuse_outside(d.source + ":" + std::to_string(cls.model_lines[k]), id, e.path, folder);
      e.name = fs::path(e.path).stem().string();
      e.class_name = cls.name;
      e.pose = static_cast<int>(k);
      d.entries.push_back(e);
    }
  CSHAPES_REQUIRE(!d.entries.empty(), d.source, ": the classification lists no models");
  return d;
}

}  // namespace

std::string class_from_name(const std::string& stem) {
  size_t end = stem.size();
  while (end > 0 && std::isdigit(static_cast<unsigned char>(stem[end - 1]))) --end;
  if (end == 0) return stem;
  // A separator before the pose number is not part of the class ("horse_7" -> "horse").
  while (end > 1 &&
         (stem[end - 1] == '_' || stem[end - 1] == '-' || stem[end - 1] == '.' || stem[end - 1] == ' '))
    --end;
  return stem.substr(0, end);
}

int pose_from_name(const std::string& stem) {
  size_t end = stem.size();
  while (end > 0 && std::isdigit(static_cast<unsigned char>(stem[end - 1]))) --end;
  if (end == 0 || end == stem.size() || stem.size() - end > 9) return -1;
  return std::stoi(stem.substr(end));
}

std::vector<int> Dataset::labels() const {
  std::vector<int> out;
  out.reserve(entries.size());
  for (const auto& e : entries)
    out.push_back(
        static_cast<int>(std::find(classes.begin(), classes.end(), e.class_name) - classes.begin()));
  return out;
}

namespace {

// A file listed twice would be compared with itself (distance 0) and count as a retrieval hit: refused,
// naming both entries, when the two paths name one file (links and "./" included). Two files of the same
// bytes under different names are two entries of the collection (a public benchmark holds such pairs): kept,
// and recorded in d.same_content for the drivers to say. Cost: one stat per file (and same_content_pairs).
void refuse_files_listed_twice(Dataset& d) {
  std::map<std::string, size_t> by_path;
  for (size_t k = 0; k < d.entries.size(); ++k) {
    const std::string& file = d.entries[k].path;
    std::error_code ec;
    const fs::path real = fs::weakly_canonical(file, ec);
    const auto [it, inserted] = by_path.emplace(ec ? file : real.string(), k);
    if (!inserted)
      fail(d.source, ": ", d.entries[it->second].path, " and ", file,
           " are the same file, listed twice (each shape must appear once)");
  }
  d.same_content = same_content_pairs(d.entries);
}

// Two files of one shape name (biped0.off and sub/biped0.off in a manifest) would be two rows of one name in
// every distance matrix and labels file, one class lost where names are matched: refused before any work,
// naming both files. Renaming a file is the user's choice; a name made up here would be a third spelling.
void refuse_shape_names_twice(const Dataset& d) {
  std::map<std::string, size_t> by_name;
  for (size_t k = 0; k < d.entries.size(); ++k) {
    const auto [it, inserted] = by_name.emplace(d.entries[k].name, k);
    if (!inserted)
      fail(d.source, ": ", d.entries[it->second].path, " and ", d.entries[k].path, " are both shape '",
           d.entries[k].name,
           "' (a shape's name is its file name without folder and extension): each shape needs its own name, "
           "its row and column in the distance matrix");
  }
}

}  // namespace

std::vector<std::pair<size_t, size_t>> same_content_pairs(const std::vector<DatasetEntry>& entries) {
  // Only files whose size another file shares are read, one at a time beside those of the same hash.
  std::map<std::uintmax_t, std::vector<size_t>> by_size;
  for (size_t k = 0; k < entries.size(); ++k) {
    std::error_code ec;
    const std::uintmax_t size = fs::file_size(entries[k].path, ec);
    if (!ec) by_size[size].push_back(k);
  }
  std::vector<std::pair<size_t, size_t>> pairs;
  for (const auto& [size, same_size] : by_size) {
    if (same_size.size() < 2) continue;
    std::map<size_t, std::vector<size_t>> by_hash;
    for (size_t k : same_size) {
      const std::string content = read_file(entries[k].path);
      std::vector<size_t>& alike = by_hash[std::hash<std::string>{}(content)];
      for (size_t other : alike)
        if (read_file(entries[other].path) == content) pairs.emplace_back(other, k);
      alike.push_back(k);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

Dataset read_dataset(const std::string& path, bool allow_outside) {
  fs::path p(path);
  CSHAPES_REQUIRE(fs::exists(p), path,
                  ": no such file or folder (expected a folder of meshes or a manifest.csv)");
  Dataset d;
  if (fs::is_directory(p)) {
    d = fs::is_regular_file(p / "manifest.csv") ? read_manifest(p / "manifest.csv", allow_outside)
                                                : read_folder(p);
  } else if (file_extension(path) == "cla") {
    d = read_classification_dataset(p, allow_outside);
  } else {
    CSHAPES_REQUIRE(file_extension(path) == "csv", path,
                    ": expected a folder of meshes, a manifest .csv or a classification .cla file");
    d = read_manifest(p, allow_outside);
  }
  for (const auto& e : d.entries)
    if (std::find(d.classes.begin(), d.classes.end(), e.class_name) == d.classes.end())
      d.classes.push_back(e.class_name);
  refuse_files_listed_twice(d);
  refuse_shape_names_twice(d);
  return d;
}

std::vector<std::string> same_content_notes(const Dataset& d) {
  std::vector<std::string> notes;
  for (const auto& [first, second] : d.same_content)
    notes.push_back(d.entries[first].name + " and " + d.entries[second].name + " (" + d.entries[first].path +
                    ", " + d.entries[second].path +
                    ") have the same content: two entries of the collection, both kept as queries");
  return notes;
}

std::vector<std::string> dataset_description_files(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    const fs::path manifest = fs::path(path) / "manifest.csv";
    if (fs::exists(manifest, ec)) return {manifest.string()};
    return {};
  }
  return {path};
}

std::string dataset_name(const std::string& path) {
  fs::path p = fs::path(path).lexically_normal();
  if (!p.has_filename()) p = p.parent_path();  // "tosca5k/"
  if (p.filename() == "." || p.empty()) p = fs::absolute(p).lexically_normal();
  if (!p.has_filename()) p = p.parent_path();
  std::error_code ec;
  if (fs::is_directory(p, ec)) return p.filename().string();
  if (p.filename() == "manifest.csv") {
    const fs::path folder = fs::absolute(p).lexically_normal().parent_path();
    if (!folder.filename().empty()) return folder.filename().string();
  }
  return p.stem().string();
}

void write_manifest(const std::string& manifest_path, const std::vector<DatasetEntry>& entries) {
  const fs::path folder = fs::path(manifest_path).parent_path();
  write_file_atomically(manifest_path, [&](std::ostream& out) {
    out << "file,class,pose,noisy\n";
    for (const auto& e : entries) {
      fs::path file(e.path);
      std::string shown = e.path;
      if (!folder.empty()) {
        fs::path rel = file.lexically_relative(folder);
        if (!rel.empty() && *rel.begin() != "..") shown = rel.string();
      } else if (file.is_relative()) {
        shown = file.string();
      }
      CSHAPES_REQUIRE(shown.find(',') == std::string::npos && e.class_name.find(',') == std::string::npos,
                      "write_manifest: commas are not allowed in file or class names: ", shown);
      out << shown << ',' << e.class_name << ',' << (e.pose >= 0 ? std::to_string(e.pose) : "") << ','
          << (e.noisy ? 1 : 0) << '\n';
    }
  });
}

void write_off_fixed(const std::string& path, const Mesh& mesh, int decimals) {
  CSHAPES_REQUIRE(decimals >= 0 && decimals <= 17, "write_off_fixed: decimals must be in 0..17, got ",
                  decimals);
  write_file_atomically(path, [&](std::ostream& out) {
    out << "OFF\n" << mesh.num_vertices() << ' ' << mesh.num_faces() << " 0\n";
    char buffer[128];
    for (Index i = 0; i < mesh.num_vertices(); ++i) {
      for (int k = 0; k < 3; ++k) {
        double v = mesh.V(i, k);
        // No "-0.000000": a coordinate rounding to zero is written as zero whatever its sign.
        if (std::abs(v) < 0.5 * std::pow(10.0, -decimals)) v = 0;
        std::snprintf(buffer, sizeof buffer, k < 2 ? "%.*f " : "%.*f\n", decimals, v);
        out << buffer;
      }
    }
    for (Index f = 0; f < mesh.num_faces(); ++f)
      out << "3 " << mesh.F(f, 0) << ' ' << mesh.F(f, 1) << ' ' << mesh.F(f, 2) << '\n';
  });
}

}  // namespace cshapes
