#include "cshapes/data/dataset_checksums.h"

#include <algorithm>

#include "cshapes/support/error.h"
#include "cshapes/support/sha256.h"

namespace cshapes {

DatasetChecksums dataset_checksums(const Dataset& data) {
  DatasetChecksums checksums;
  for (const DatasetEntry& e : data.entries) {
    std::string sha256;
    try {
      sha256 = file_content_hash(e.path);
    } catch (const Error&) {
      // Unreadable now: the drivers leave such a shape out and say why; its line keeps its name in the
      // digest.
    }
    checksums.shapes.push_back({e.name, e.class_name, sha256});
  }
  checksums.digest = dataset_digest(checksums.shapes);
  return checksums;
}

std::string dataset_digest(const std::vector<ShapeChecksum>& shapes) {
  std::vector<std::string> lines;
  lines.reserve(shapes.size());
  for (const ShapeChecksum& s : shapes)
    lines.push_back(s.name + '\t' + s.class_name + '\t' + s.sha256 + '\n');
  std::sort(lines.begin(), lines.end());
  std::string all;
  for (const std::string& line : lines) all += line;
  return sha256_hex(all);
}

}  // namespace cshapes
