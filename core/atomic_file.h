// Writing files so that a failure never leaves a partial output: write to a temporary name beside the target,
// then rename over it (atomic on POSIX within one file system).
#pragma once

#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace cshapes {

// Calls write(stream) on a temporary file next to `path` and renames it to `path` when write returns.
// If write throws (or the stream fails), the temporary file is removed and the error propagates;
// `path` is then untouched. Creates missing parent directories. binary: open in binary mode.
// Several threads or processes (MPI ranks on other nodes of a shared file system too) may write the same path
// at once: each writes its own temporary file (host, process id and a counter in its name) and the last
// rename wins whole.
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write,
                           bool binary = false);

// A CSV of numbers (header + rows, 10 significant digits), written atomically.
void write_csv(const std::string& path, const std::vector<std::string>& columns,
               const std::vector<std::vector<double>>& rows);

// Checks, before any work, that an output file can later be written at `path`: its lower-cased extension is
// one of `extensions` (without the dot, e.g. {"off", "ply"}; empty: any), the path is not a folder, and its
// folder exists and takes a new file, or can be created (a probe file is created and removed there, so the
// answer holds for root and read-only mounts too; nothing else is left behind). Throws cshapes::Error naming
// the path and what is wrong.
void check_output_path(const std::string& path, const std::vector<std::string>& extensions);
// The same for an output folder: it is a writable folder, or can be created.
void check_output_directory(const std::string& path);

// Reads a whole file into a string; throws naming the file when it cannot be read.
std::string read_file(const std::string& path);

}  // namespace cshapes
