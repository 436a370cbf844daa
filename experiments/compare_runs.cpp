#include "cshapes/experiments/compare_runs.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

#include "cshapes/data/dataset_checksums.h"
#include "cshapes/experiments/figures.h"
#include "cshapes/experiments/retrieval_experiment.h"
#include "cshapes/pipeline/experiment_kit.h"
#include "cshapes/support/format.h"
#include "cshapes/support/atomic_file.h"
#include "cshapes/support/error.h"
#include "cshapes/support/output_folder.h"

namespace cshapes {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kSupported = "experiment retrieval";
// The other experiments, whose outputs are recognised and refused by name (not merged yet).
const std::set<std::string> kNotYet = {"experiment paper", "experiment noise", "experiment pose",
                                       "experiment topkids"};
// Retrieval measures that agree to this are one result (the JSON's doubles round-trip exactly; the slack
// only forgives a run written by another printer of the same numbers).
constexpr double kSameResult = 1e-12;

// The six measures: their names in retrieval.json, and in the tables and messages.
const char* const kMeasureNames[] = {"nn", "ft", "st", "e", "dcg", "map"};
const char* const kMeasureTitles[] = {"NN", "FT", "ST", "E", "DCG", "mAP"};

// A member of a JSON object that must be there, with a message naming the file and the member.
const json& member(const json& object, const std::string& key, const std::string& file,
                   const std::string& where = "") {
  if (!object.is_object() || !object.contains(key))
    fail(file, ": expected \"", key, "\"", where.empty() ? "" : " in " + where,
         " (a retrieval.json written by `cshapes experiment retrieval`)");
  return object.at(key);
}

RetrievalScores scores_of(const json& entry, const std::string& file, const std::string& where) {
  RetrievalScores s;
  double* fields[] = {&s.nn, &s.ft, &s.st, &s.e, &s.dcg, &s.ap};
  for (size_t k = 0; k < 6; ++k) {
    const json& value = member(entry, kMeasureNames[k], file, where);
    if (!value.is_number()) fail(file, ": \"", kMeasureNames[k], "\" in ", where, ": expected a number");
    *fields[k] = value.get<double>();
  }
  return s;
}

double score(const RetrievalScores& s, size_t k) {
  const double fields[] = {s.nn, s.ft, s.st, s.e, s.dcg, s.ap};
  return fields[k];
}

// The folder's record must say: a complete run of experiment retrieval.
void require_retrieval_run(const std::string& folder) {
  std::error_code ec;
  if (!fs::exists(folder, ec))
    fail(folder, ": no such folder (expected the output folder of a `cshapes ", kSupported, "` run)");
  if (!fs::is_directory(folder, ec))
    fail(folder, ": not a folder (expected the output folder of a `cshapes ", kSupported, "` run)");
  const OutputFolderOwner owner = output_folder_owner(folder);
  if (owner.command.empty())
    fail(folder, ": not a cshapes output folder (no ", kOutputRecordName,
         " record); expected the output folder of a `cshapes ", kSupported, "` run");
  if (kNotYet.count(owner.command))
    fail(folder, ": holds the outputs of `cshapes ", owner.command, "`; compare merges `cshapes ", kSupported,
         "` runs only (", owner.command, " outputs are not supported yet)");
  if (owner.command != kSupported)
    fail(folder, ": holds the outputs of `cshapes ", owner.command, "`; compare merges `cshapes ", kSupported,
         "` runs only");
  if (!owner.complete)
    fail(folder, ": its `cshapes ", kSupported,
         "` run did not complete (still running, or killed); rerun it (its cache resumes) and compare again");
}

json read_json_file(const std::string& path) {
  const std::string text = read_text_file(path);
  json j = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded())
    fail(path, ": not valid JSON (expected the retrieval.json of `cshapes ", kSupported, "`)");
  return j;
}

// The first difference between two runs' inputs, for the refusal: a shape only in one, another class, another
// file. a, b: the runs' "inputs"."shapes"; name_a, name_b: their folders.
std::string first_input_difference(const json& a, const json& b, const std::string& name_a,
                                   const std::string& name_b) {
  std::map<std::string, std::pair<std::string, std::string>> shapes_a, shapes_b;  // name -> (class, sha256)
  for (const json& s : a) shapes_a[s.value("name", "")] = {s.value("class", ""), s.value("sha256", "")};
  for (const json& s : b) shapes_b[s.value("name", "")] = {s.value("class", ""), s.value("sha256", "")};
  for (const auto& [name, value] : shapes_a) {
    auto it = shapes_b.find(name);
    if (it == shapes_b.end()) return "shape " + name + " is in " + name_a + " only";
    if (value.first != it->second.first)
      return "shape " + name + " has class " + value.first + " in " + name_a + ", " + it->second.first +
             " in " + name_b;
    if (value.second != it->second.second)
      return "shape " + name + "'s file differs (SHA-256 " + value.second.substr(0, 12) + "… in " + name_a +
             ", " + it->second.second.substr(0, 12) + "… in " + name_b + ")";
  }
  for (const auto& [name, value] : shapes_b)
    if (!shapes_a.count(name)) return "shape " + name + " is in " + name_b + " only";
  return "the same shapes, yet the digests differ";
}

struct RunFile {
  std::string folder, path;
  json content;
  json outside;  // its outside-methods.json (an array of {name, door, text}); empty when it has none
};

RunFile read_run(const std::string& folder) {
  require_retrieval_run(folder);
  RunFile run{folder, (fs::path(folder) / "retrieval.json").string(), json(), json()};
  std::error_code ec;
  if (!fs::is_regular_file(run.path, ec))
    fail(run.path, ": missing (expected the retrieval.json of a complete `cshapes ", kSupported, "` run)");
  run.content = read_json_file(run.path);
  const json& j = run.content;
  if (!j.is_object()) fail(run.path, ": expected a JSON object");
  if (!j.contains("inputs"))
    fail(run.path,
         ": records no checksums of its inputs (written by a cshapes older than `cshapes compare`), so "
         "compare cannot tell whether it ran on the same data; rerun `cshapes ",
         kSupported, " --data ", j.value("data", std::string("DATA")), " --out ", folder,
         "` with its options (its cache makes the rerun cheap) and compare again");
  const json& inputs = j.at("inputs");
  const json& digest = member(inputs, "digest", run.path, "\"inputs\"");
  const json& shapes = member(inputs, "shapes", run.path, "\"inputs\"");
  if (!digest.is_string() || !shapes.is_array())
    fail(run.path, ": \"inputs\": expected a \"digest\" string and a \"shapes\" array");
  std::vector<ShapeChecksum> checksums;
  for (const json& s : shapes) {
    if (!s.is_object()) fail(run.path, ": \"inputs\".\"shapes\": expected objects {name, class, sha256}");
    checksums.push_back({s.value("name", ""), s.value("class", ""), s.value("sha256", "")});
  }
  // The digest is the checksums': a file edited by hand, or cut short, is not taken for the data it names.
  if (dataset_digest(checksums) != digest.get<std::string>())
    fail(run.path,
         ": \"inputs\": its digest is not the digest of its shapes' checksums (the file was edited or "
         "damaged); rerun `cshapes ",
         kSupported, "` into ", folder);
  const std::string outside = (fs::path(folder) / "outside-methods.json").string();
  if (fs::is_regular_file(outside, ec)) {
    run.outside = read_json_file(outside);
    if (!run.outside.is_array()) fail(outside, ": expected an array of {name, door, text}");
  }
  member(j, "protocol", run.path);
  if (!member(j, "methods", run.path).is_array()) fail(run.path, ": \"methods\": expected an array");
  if (!member(j, "distances", run.path).is_array()) fail(run.path, ": \"distances\": expected an array");
  return run;
}

std::string canonical_or_absolute(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  return (ec ? fs::absolute(path) : p).lexically_normal().string();
}

bool is_inside_or_same(const std::string& inner, const std::string& outer) {
  const fs::path a = canonical_or_absolute(inner), b = canonical_or_absolute(outer);
  auto ia = a.begin(), ib = b.begin();
  for (; ib != b.end(); ++ia, ++ib) {
    if (ib->empty()) continue;  // a trailing separator
    if (ia == a.end() || *ia != *ib) return false;
  }
  return true;
}

// The first measure where two results of one method differ, "" when none does.
std::string first_result_difference(const ComparedMethod& a, const ComparedMethod& b) {
  if (a.shapes != b.shapes) return std::to_string(a.shapes) + " shapes vs " + std::to_string(b.shapes);
  for (const auto& [kind, scores] : a.scores) {
    auto it = b.scores.find(kind);
    if (it == b.scores.end()) return retrieval_distance_title(kind) + " in the first only";
    for (size_t k = 0; k < 6; ++k)
      if (std::abs(score(scores, k) - score(it->second, k)) > kSameResult)
        return retrieval_distance_title(kind) + " " + kMeasureTitles[k] + " " + fixed(score(scores, k), 6) +
               " vs " + fixed(score(it->second, k), 6);
  }
  for (const auto& [kind, scores] : b.scores)
    if (!a.scores.count(kind)) return retrieval_distance_title(kind) + " in the second only";
  return "";
}

ComparedMethod method_of(const json& m, size_t run, const std::string& file, const json& outside) {
  ComparedMethod method;
  const json& name = member(m, "method", file, "\"methods\"");
  if (!name.is_string() || name.get<std::string>().empty())
    fail(file, ": \"methods\": expected each method's name as a non-empty string");
  method.method = name.get<std::string>();
  method.title = m.value("title", method.method);
  method.run = run;
  method.shapes = m.value("shapes", 0);
  for (const json& door : outside)
    if (door.is_object() && door.value("name", "") == method.method) {
      method.door = door.value("door", "");
      method.door_text = door.value("text", "");
    }
  const std::string where = "method " + method.method;
  for (const auto& [kind, entry] : member(m, "distances", file, where).items()) {
    method.scores[kind] = scores_of(entry, file, where + ", distance " + kind);
    method.entries[kind] = entry;
  }
  return method;
}

}  // namespace

CompareRunsResult read_compared_runs(const std::vector<std::string>& folders) {
  CSHAPES_REQUIRE(folders.size() >= 2, "compare: expected two or more run folders, got ", folders.size());
  for (size_t a = 0; a < folders.size(); ++a)
    for (size_t b = 0; b < a; ++b)
      if (canonical_or_absolute(folders[a]) == canonical_or_absolute(folders[b]))
        fail(folders[a], ": given twice (as ", folders[b], " and ", folders[a], "); expected distinct runs");
  std::vector<RunFile> files;
  for (const std::string& folder : folders) files.push_back(read_run(folder));
  CompareRunsResult r;
  r.experiment = "retrieval";
  const json& first = files[0].content;
  r.inputs_digest = first.at("inputs").at("digest").get<std::string>();
  r.protocol = first.at("protocol");
  r.shapes = first.value("shapes", 0);
  r.classes = first.value("classes", std::vector<std::string>());
  for (size_t k = 0; k < files.size(); ++k) {
    const RunFile& f = files[k];
    const json& j = f.content;
    if (k > 0) {
      const std::string digest = j.at("inputs").at("digest").get<std::string>();
      if (digest != r.inputs_digest)
        fail(f.folder, ": not run on the same data as ", files[0].folder, ": ",
             first_input_difference(first.at("inputs").at("shapes"), j.at("inputs").at("shapes"),
                                    files[0].folder, f.folder),
             "; inputs' digests ", r.inputs_digest.substr(0, 12), "… and ", digest.substr(0, 12),
             "…; compare merges runs on the same shapes with the same classes only");
      for (const auto& [key, value] : r.protocol.items())
        if (!j.at("protocol").contains(key) || j.at("protocol").at(key) != value)
          fail(f.folder, ": run with ", key, " = ", j.at("protocol").value(key, json()).dump(), ", ",
               files[0].folder, " with ", value.dump(),
               "; compare merges runs of one protocol only (rerun one with the other's "
               "setting)");
      for (const auto& [key, value] : j.at("protocol").items())
        if (!r.protocol.contains(key))
          fail(f.folder, ": its protocol has ", key, ", which ", files[0].folder,
               "'s has not (runs by different versions of cshapes); rerun the older one");
    }
    ComparedRun run;
    run.folder = f.folder;
    run.data = j.value("data", std::string());
    run.build = j.value("build", json::object());
    for (const json& kind : j.at("distances"))
      if (kind.is_string() &&
          std::find(r.distances.begin(), r.distances.end(), kind.get<std::string>()) == r.distances.end())
        r.distances.push_back(kind.get<std::string>());
    for (const json& m : j.at("methods")) {
      ComparedMethod method = method_of(m, k, f.path, f.outside);
      run.methods.push_back(method.method);
      auto same = std::find_if(r.methods.begin(), r.methods.end(),
                               [&](const ComparedMethod& other) { return other.method == method.method; });
      if (same == r.methods.end()) {
        r.methods.push_back(std::move(method));
        continue;
      }
      if (same->run == k) fail(f.path, ": method ", method.method, " is listed twice");
      const std::string difference = first_result_difference(*same, method);
      if (!difference.empty())
        fail("method ", method.method, " is in ", files[same->run].folder, " and in ", f.folder,
             " with different results (", difference,
             "): one name, two results; compare one of those runs, or run the method again under another "
             "name");
      same->also_in.push_back(k);
    }
    r.runs.push_back(std::move(run));
  }
  return r;
}

void write_compare_json(const CompareRunsResult& r, const std::string& folder) {
  json runs = json::array();
  for (const ComparedRun& run : r.runs)
    runs.push_back(
        {{"folder", run.folder}, {"data", run.data}, {"build", run.build}, {"methods", run.methods}});
  json methods = json::array();
  for (const ComparedMethod& m : r.methods) {
    json also = json::array();
    for (size_t k : m.also_in) also.push_back(r.runs[k].folder);
    json distances = json::object();
    for (const auto& [kind, entry] : m.entries) distances[kind] = entry;
    methods.push_back({{"method", m.method},
                       {"title", m.title},
                       {"run", r.runs[m.run].folder},
                       {"also_in", also},
                       {"shapes", m.shapes},
                       {"door", m.door.empty() ? json(nullptr) : json(m.door)},
                       {"door_text", m.door_text.empty() ? json(nullptr) : json(m.door_text)},
                       {"distances", distances}});
  }
  ExperimentFolder(folder).write_json("compare.json", {{"experiment", r.experiment},
                                                       {"inputs", {{"digest", r.inputs_digest}}},
                                                       {"protocol", r.protocol},
                                                       {"shapes", r.shapes},
                                                       {"classes", r.classes},
                                                       {"distances", r.distances},
                                                       {"runs", runs},
                                                       {"methods", methods},
                                                       {"build", build_json()}});
}

void draw_compare_figure(CompareRunsResult& r, const std::string& folder, FigureFormat format) {
  const FigureRun drawn =
      draw_figure("compare_figure.py", {folder}, (fs::path(folder) / "pr").string(), format);
  r.figures.clear();
  if (!drawn.drawn) {
    r.figures_note = drawn.problem;
    return;
  }
  r.figures_note.clear();
  r.figures.push_back(figure_file_name("pr", format));
}

void write_compare_report(const CompareRunsResult& r, const std::string& folder) {
  std::ostringstream out;
  out << "# Comparison of " << r.runs.size() << " `cshapes experiment " << r.experiment << "` runs\n\n"
      << build_sentence() << "\n\n"
      << "The same data in every run: " << r.shapes << " shapes in " << r.classes.size()
      << " classes, inputs' digest `" << r.inputs_digest
      << "` (SHA-256 over each shape's name, class and file SHA-256, as each run's retrieval.json records "
         "it). "
         "The same protocol: ";
  bool first = true;
  for (const auto& [key, value] : r.protocol.items()) {
    out << (first ? "" : ", ") << key << " " << value.dump();
    first = false;
  }
  out << ". Every number is the run's own; nothing was recomputed.\n\n## Runs\n\n| run | data | cshapes | "
         "methods |\n"
         "|---|---|---|---|\n";
  for (const ComparedRun& run : r.runs) {
    out << "| `" << run.folder << "` | `" << run.data << "` | "
        << run.build.value("version", std::string("?")) << " (" << run.build.value("build", std::string("?"))
        << ", " << run.build.value("simd", std::string("?")) << ") | ";
    for (size_t k = 0; k < run.methods.size(); ++k) out << (k ? ", " : "") << run.methods[k];
    out << " |\n";
  }
  out << "\n## Overall\n\nEvery shape a query against all the others; micro averages over the queries.\n\n"
      << "| method | distance | shapes" << kRetrievalMeasuresHeader << " run |\n|---|---|---:|"
      << kRetrievalMeasuresRule << "---|\n";
  bool fewer = false;
  for (const ComparedMethod& m : r.methods)
    for (const std::string& kind : r.distances) {
      auto it = m.scores.find(kind);
      if (it == m.scores.end()) continue;
      std::string run = "`" + r.runs[m.run].folder + "`";
      for (size_t k : m.also_in) run += " (also `" + r.runs[k].folder + "`)";
      out << "| " << m.title << " | " << retrieval_distance_title(kind) << " | " << m.shapes
          << retrieval_measures_cells(it->second) << ' ' << run << " |\n";
      fewer = fewer || m.shapes < r.shapes;
    }
  out << '\n';
  if (fewer)
    out << "A method with fewer shapes than the collection's " << r.shapes
        << " left some out in its run: its run's report names them and why.\n\n";
  bool outside = false;
  for (const ComparedMethod& m : r.methods) outside = outside || !m.door.empty();
  if (outside) {
    out << "## Methods from outside\n\nAs their runs name them (outside-methods.json); each ran under the "
           "protocol of the built-in methods.\n\n";
    for (const ComparedMethod& m : r.methods)
      if (!m.door.empty())
        out << "- **" << m.method << "** (`" << r.runs[m.run].folder << "`): by the " << m.door << " door, `"
            << m.door_text << "`\n";
    out << '\n';
  }
  out << "## Figure\n\n";
  if (r.figures.empty()) out << "Not drawn: " << r.figures_note << "\n\n";
  for (const std::string& f : r.figures) out << figure_markdown(f, f) << "\n\n";
  out << "## Files\n\n"
         "- `compare.json`: the table above with each method's PR curves and per-class measures, the runs\n"
         "- `pr.png` (`pr.pdf`, `pr.svg` with `--figure-format`): the PR curves, one panel per distance, "
         "every method; `methods.json`: the methods' titles the figure uses\n"
         "- each run's own folder holds its matrices, per-class tables, confusion matrices and failures\n";
  ExperimentFolder(folder).write_text("report.md", out.str());
}

CompareRunsResult compare_runs(const CompareRunsOptions& o) {
  CSHAPES_REQUIRE(!o.out.empty(), "compare: an output folder is required");
  for (const std::string& run : o.runs)
    if (is_inside_or_same(o.out, run) || is_inside_or_same(run, o.out))
      fail(o.out, ": the output folder may not be a run's folder, inside one or hold one (", run,
           "); expected a folder of its own");
  // Everything is read and checked before the output folder is claimed: a refusal writes nothing.
  CompareRunsResult r = read_compared_runs(o.runs);
  for (const ComparedRun& run : r.runs)
    say(o.note, run.folder + ": " + counted(static_cast<long long>(run.methods.size()), "method"));
  OutputRun output(o.out, "compare", {}, o.force);
  write_compare_json(r, o.out);
  if (o.figures) {
    draw_compare_figure(r, o.out, o.figure_format);
    if (!r.figures_note.empty()) say(o.note, "no figure: " + r.figures_note);
  } else {
    r.figures_note = "not requested (--no-draw)";
  }
  write_compare_report(r, o.out);
  output.commit();
  return r;
}

}  // namespace cshapes
