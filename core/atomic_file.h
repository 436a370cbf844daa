// Writing files so that a failure never leaves a partial output: write to a temporary name beside the target,
// then rename over it (atomic on POSIX within one file system).
#pragma once

#include <fstream>
#include <functional>
#include <string>

namespace cshapes {

// Calls write(stream) on a temporary file next to `path` and renames it to `path` when write returns.
// If write throws (or the stream fails), the temporary file is removed and the error propagates;
// `path` is then untouched. Creates missing parent directories. binary: open in binary mode.
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write,
                           bool binary = false);

// Reads a whole file into a string; throws naming the file when it cannot be read.
std::string read_file(const std::string& path);

}  // namespace cshapes
