#include "cshapes/pipeline/shape_failures.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <utility>

#include "cshapes/support/error.h"
#include "cshapes/mesh/unit_scale.h"
#include "cshapes/matching/shape_distance.h"

namespace cshapes {

std::string describe(const ShapeFailure& f) {
  if (!f.left_out())
    return f.name + ": " + (f.method.empty() ? "" : f.method + ": ") + f.fallback + " (kept)";
  if (f.stage == "read") return f.name + " left out: " + f.path + " cannot be used: " + f.reason;
  return f.name + " left out: the " + f.method + " canonical form failed: " + f.reason;
}

int count_left_out(const std::vector<ShapeFailure>& failures) {
  // Shapes, not records: one shape that failed for three methods of a run is one shape left out.
  std::set<std::pair<std::string, std::string>> shapes;
  for (const ShapeFailure& f : failures)
    if (f.left_out()) shapes.emplace(f.name, f.path);
  return static_cast<int>(shapes.size());
}

nlohmann::json shape_failures_json(const std::vector<ShapeFailure>& failures) {
  nlohmann::json out = nlohmann::json::array();
  for (const ShapeFailure& f : failures)
    out.push_back({{"name", f.name},
                   {"path", f.path},
                   {"method", f.method},
                   {"stage", f.stage},
                   {"reason", f.reason},
                   {"left_out", f.left_out()},
                   {"fallback", f.left_out() ? nlohmann::json(nullptr) : nlohmann::json(f.fallback)}});
  return out;
}

namespace {
// A table cell: one line, no column separators.
std::string cell(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '|') c = c == '|' ? '/' : ' ';
  return text;
}
}  // namespace

std::string shape_failures_markdown(const std::vector<ShapeFailure>& failures, LeftOutScope scope) {
  if (failures.empty()) return "";
  std::ostringstream md;
  const int left_out = count_left_out(failures);
  md << "## Shapes left out and fallbacks\n\n";
  const long forms_left_out =
      std::count_if(failures.begin(), failures.end(), [](const ShapeFailure& f) { return f.left_out(); });
  if (scope == LeftOutScope::Form && forms_left_out > 0)
    md << forms_left_out << (forms_left_out == 1 ? " form" : " forms") << " could not be computed and "
       << (forms_left_out == 1 ? "was" : "were")
       << " left out, each named below by its shape, case and method; every other form was measured. The run "
          "went on and ends with exit code 3 (partial result). `--strict` stops at the first failure "
          "instead.\n\n";
  else if (left_out > 0)
    md << left_out << (left_out == 1 ? " shape was" : " shapes were")
       << " left out of every measurement, by every method (so that the methods are compared on the same "
          "shapes); the run went on with the others and ends with exit code 3 (partial result). `--strict` "
          "stops at the first failure instead.\n\n";
  int fallbacks = 0, poor_forms = 0, same_content = 0, not_resampled = 0;
  for (const ShapeFailure& f : failures) {
    fallbacks += !f.left_out() && f.stage == "geodesics";
    poor_forms += !f.left_out() && f.stage == "form quality";
    same_content += !f.left_out() && f.stage == "dataset";
    not_resampled += !f.left_out() && f.stage == "resample";
  }
  if (same_content > 0)
    md << same_content << (same_content == 1 ? " entry holds" : " entries hold")
       << " the same bytes as another entry under a different name; both are kept as two entries of the "
          "collection (a public benchmark may hold such pairs): in a retrieval each finds the other at "
          "distance 0.\n\n";
  if (not_resampled > 0)
    md << not_resampled << (not_resampled == 1 ? " shape" : " shapes")
       << " could not be remeshed by `--resample` and " << (not_resampled == 1 ? "was" : "were")
       << " kept at " << (not_resampled == 1 ? "its" : "their")
       << " own resolution (the reason in the table).\n\n";
  if (fallbacks > 0)
    md << "A geodesic method that failed on a shape fell back to the next (heat → fast marching); those "
          "shapes were kept.\n\n";
  if (poor_forms > 0)
    md << poor_forms << (poor_forms == 1 ? " canonical form fails" : " canonical forms fail")
       << " its own quality check (vertices on edges stretched beyond 5× their length, far from the form "
          "or detached: canon/form_quality.h); such a form is kept and measured as it is, and listed here so "
          "that no figure rests on it unsaid.\n\n";
  md << "| shape | file | method | stage | what happened |\n| --- | --- | --- | --- | --- |\n";
  for (const ShapeFailure& f : failures)
    md << "| " << cell(f.name) << " | `" << cell(f.path) << "` | " << (f.method.empty() ? "all" : f.method)
       << " | " << f.stage << " | " << cell(f.left_out() ? "left out: " + f.reason : f.fallback) << " |\n";
  md << "\n";
  return md.str();
}

namespace {
std::vector<ShapeFailure> records_of_pairs(const std::vector<DatasetEntry>& entries,
                                           const std::vector<std::pair<size_t, size_t>>& pairs,
                                           const std::string& kept_as) {
  std::vector<ShapeFailure> records;
  for (const auto& [first, second] : pairs) {
    const DatasetEntry& a = entries[first];
    const DatasetEntry& b = entries[second];
    records.push_back({b.name, b.path, "", "dataset", "the same content as " + a.name + " (" + a.path + ")",
                       "the same content as " + a.name + " (" + a.path +
                           "): two entries of the collection, both kept as " + kept_as});
  }
  return records;
}
}  // namespace

std::vector<ShapeFailure> same_content_records(const Dataset& data) {
  return records_of_pairs(data.entries, data.same_content, "queries");
}

std::vector<ShapeFailure> same_content_records(const std::vector<DatasetEntry>& entries,
                                               const std::string& kept_as) {
  return records_of_pairs(entries, same_content_pairs(entries), kept_as);
}

std::vector<ShapeFailure> left_out_records(const std::vector<DatasetLeftOut>& left_out, bool strict) {
  std::vector<ShapeFailure> records;
  for (const DatasetLeftOut& entry : left_out) {
    CSHAPES_REQUIRE(!strict, entry.path, ": ", entry.reason,
                    " (--strict: a dataset entry that is no shape stops the run)");
    records.push_back({entry.name, entry.path, "", "read", entry.reason, ""});
  }
  return records;
}

void add_records(std::vector<ShapeFailure>& failures, const std::vector<ShapeFailure>& records,
                 const NoteFn& note) {
  for (const ShapeFailure& record : records) {
    say(note, describe(record));
    failures.push_back(record);
  }
}

ShapeFailure read_failure(const std::string& name, const std::string& path, const Error& error) {
  return {name, path, "", "read", error.what(), ""};
}

std::optional<std::vector<CachedForm>> shape_canonical_forms(const DiskCache& cache, const Mesh& mesh,
                                                             const std::vector<CanonicalFormOptions>& options,
                                                             const std::string& name,
                                                             std::vector<ShapeFailure>& failures) {
  std::vector<CachedForm> forms;
  size_t at = 0;  // the method being computed when an error is thrown
  try {
    forms = cached_canonical_forms(cache, mesh, options, &at);
  } catch (const IoError&) {
    throw;
  } catch (const FileError&) {
    throw;
  } catch (const Error& error) {
    bool strict = false;
    for (const CanonicalFormOptions& o : options) strict = strict || o.strict;
    if (strict) throw;
    const std::string method = at < options.size() ? options[at].method : "";
    failures.push_back(
        {name, options.empty() ? name : options.front().name, method, "canonical form", error.what(), ""});
    return std::nullopt;
  }
  // A form ICP cannot take at any size (too few points, points on a line or at one point) leaves the shape
  // out, named, here, before any alignment: in the pairs it ended the whole run (exit 1). Its size is no
  // reason: the pairs are aligned at unit size (eval/pairwise_distances.h).
  for (size_t k = 0; k < forms.size(); ++k) {
    const std::string refusal = icp_points_refusal(finite_rows(forms[k].form.X));
    if (refusal.empty()) continue;
    if (options[k].strict) fail(name, ": its form cannot be aligned: ", refusal);
    failures.push_back(
        {name, options[k].name, options[k].method, "alignment", "its form cannot be aligned: " + refusal, ""});
    return std::nullopt;
  }
  for (size_t k = 0; k < forms.size(); ++k) {
    const std::string& text = forms[k].form.geodesics_fallback;
    if (text.empty()) continue;
    bool recorded = false;
    for (const ShapeFailure& f : failures) recorded = recorded || (f.name == name && f.fallback == text);
    if (!recorded) failures.push_back({name, options[k].name, options[k].method, "geodesics", text, text});
  }
  // A form that fails its own quality check (canon/form_quality.h) is kept and measured, and said.
  for (size_t k = 0; k < forms.size(); ++k) {
    const std::optional<FormQuality>& quality = forms[k].form.quality;
    if (!quality || quality->ok) continue;
    const std::string& description = quality->description;
    failures.push_back({name, options[k].name, options[k].method, "form quality", description,
                        "form quality " + description + "; the form is kept and measured as it is"});
  }
  return forms;
}

std::vector<size_t> forms_of_incomparable_size(const std::vector<const Points*>& forms) {
  std::vector<double> sizes(forms.size(), std::numeric_limits<double>::quiet_NaN());
  std::vector<double> known;
  for (size_t k = 0; k < forms.size(); ++k) {
    if (!forms[k] || forms[k]->rows() == 0) continue;
    const Points points = finite_rows(*forms[k]);
    if (points.rows() == 0) continue;
    // Measured at unit size (a power of two: exact), so neither an overflow nor an underflow decides.
    const double scale = power_of_two_unit_scale(points);
    const Eigen::RowVector3d centre = (points * scale).colwise().mean();
    sizes[k] = std::sqrt(((points * scale).rowwise() - centre).rowwise().squaredNorm().maxCoeff()) / scale;
    if (std::isfinite(sizes[k]) && sizes[k] > 0) known.push_back(sizes[k]);
  }
  std::vector<size_t> out;
  if (known.empty()) return out;
  std::nth_element(known.begin(), known.begin() + static_cast<long>(known.size() / 2), known.end());
  const double median = known[known.size() / 2];
  for (size_t k = 0; k < forms.size(); ++k)
    if (sizes[k] > 0 && std::isfinite(sizes[k]) &&
        (sizes[k] / median > kIncomparableSizeRatio || median / sizes[k] > kIncomparableSizeRatio))
      out.push_back(k);
  return out;
}

std::string incomparable_size_reason() {
  return "its form is more than 1e70 times smaller or larger than the median form of the set: ICP cannot align "
         "it with the others at one scale (squared distances of both do not fit in a double)";
}

}  // namespace cshapes
