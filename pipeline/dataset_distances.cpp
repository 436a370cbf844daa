#include "pipeline/dataset_distances.h"

#include <filesystem>

#include "core/dataset.h"
#include "core/error.h"
#include "core/io.h"

namespace cshapes {

DatasetDistances dataset_distances(const DatasetDistanceOptions& options) {
  auto say = [&options](const std::string& line) {
    if (options.note) options.note(line);
  };
  const Dataset data = read_dataset(options.data);
  const std::filesystem::path cache_dir(options.cache_dir);
  const DiskCache cache(options.cache_dir.empty() ? "" : (cache_dir / "forms").string());
  CanonicalFormOptions co = options.canon;
  DatasetDistances result;
  std::vector<Points> forms;
  std::vector<std::string> keys;
  for (size_t i = 0; i < data.entries.size(); ++i) {
    const DatasetEntry& e = data.entries[i];
    co.name = e.path;
    bool cached = false;
    CanonicalForm form;
    Mesh mesh;
    try {
      mesh = read_mesh(e.path);
      form = cached_canonical_form(cache, mesh, co, &cached);
    } catch (const Error& error) {
      if (co.strict) throw;
      say(std::string("skipped: ") + error.what());
      result.skipped.push_back(e.path);
      result.skipped_reasons.push_back(error.what());
      continue;
    }
    if (!form.repair_text.empty()) say(form.repair_text);
    (cached ? result.forms_cached : result.forms_computed)++;
    forms.push_back(std::move(form.X));
    keys.push_back(canonical_form_cache_key(mesh, co));
    result.names.push_back(e.name);
    result.classes.push_back(e.class_name);
    say("[" + std::to_string(i + 1) + "/" + std::to_string(data.entries.size()) + "] " + e.name +
        (cached ? " (cached)" : ""));
  }
  CSHAPES_REQUIRE(forms.size() >= 2, options.data, ": ", forms.size(), " usable shapes (",
                  result.skipped.size(), " skipped), a distance matrix needs at least 2");
  PairwiseDistanceOptions po = options.pairs;
  po.cache_dir = options.cache_dir.empty() ? "" : (cache_dir / "pairs").string();
  po.progress = options.progress;
  result.distances = pairwise_distances(forms, keys, po);
  return result;
}

}  // namespace cshapes
