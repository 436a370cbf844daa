// What a dataset holds, by content: each shape's file SHA-256 and one digest of the whole collection, so that
// two runs can tell whether they read the same shapes with the same classes (`cshapes compare`,
// experiments/compare_runs.h) wherever the files lay and whatever they were called on disk.
#pragma once

#include <string>
#include <vector>

#include "cshapes/data/dataset.h"

namespace cshapes {

struct ShapeChecksum {
  std::string name;        // the dataset's name of the shape ("cat3")
  std::string class_name;  // its class
  std::string sha256;      // SHA-256 of its file's bytes (64 lowercase hex digits); "" when it cannot be read
};

struct DatasetChecksums {
  std::vector<ShapeChecksum> shapes;  // in the dataset's order
  // SHA-256 of the lines "NAME\tCLASS\tSHA256\n" of every shape, sorted by name: the same for the same shapes
  // and classes in any listing order, folder or manifest; different when a byte of a mesh, a class or a name
  // differs.
  std::string digest;
};

// Reads every entry's file once (cost: the dataset's size in bytes). A file that cannot be read gets an empty
// sha256 (the drivers leave its shape out and name it), never an exception.
DatasetChecksums dataset_checksums(const Dataset& data);

// The digest rule above, for checksums recorded elsewhere (a run's JSON).
std::string dataset_digest(const std::vector<ShapeChecksum>& shapes);

}  // namespace cshapes
