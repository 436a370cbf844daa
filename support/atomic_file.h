// Writing files so that a failure never leaves a partial output: write to a temporary name beside the target,
// then rename over it (atomic on POSIX within one file system).
#pragma once

#include <cerrno>
#include <fstream>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace cshapes {

// Calls write(stream) on a temporary file next to `path` and renames it to `path` when write returns.
// If write throws (or the stream fails), the temporary file is removed and the error propagates;
// `path` is then untouched. Creates missing parent directories. binary: open in binary mode.
// Several threads or processes (MPI ranks on other nodes of a shared file system too) may write the same path
// at once: each writes its own temporary file (host, process id and a counter in its name) and the last
// rename wins whole.
// A path that is a symbolic link is written through: the file it points to is replaced, the link stays.
// Every failure of the file system (a folder that cannot be created, a file that cannot be created, written,
// closed or renamed: a full disk, a read-only mount) throws cshapes::WriteError naming `path` and the
// system's reason.
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write,
                           bool binary = false);

// Test hook (fault injection, no mounts needed): from the nth file written by write_file_atomically on
// (1: the next one; counted over all threads), every write fails with errno `error_number`, as on a disk
// that filled up; 0 disarms it. Not for use outside tests.
void fail_file_writes_for_testing(long nth, int error_number = ENOSPC);

// A CSV of numbers (header + rows, 10 significant digits), written atomically.
void write_csv(const std::string& path, const std::vector<std::string>& columns,
               const std::vector<std::vector<double>>& rows);

// Checks, before any work, that an output file can later be written at `path`: its lower-cased extension is
// one of `extensions` (without the dot, e.g. {"off", "ply"}; empty: any), the path is not a folder, and its
// folder exists (a missing one is refused, never created: a mistyped path is not made) and takes a new file
// (a probe file is created and removed there, so the answer holds for root and read-only mounts too; nothing
// else is left behind). Throws cshapes::Error naming the path and what is wrong. Output folders of runs
// (check_output_directory) are created when missing, with their parents.
void check_output_path(const std::string& path, const std::vector<std::string>& extensions);
// The same for an output folder: it is a writable folder, or can be created.
void check_output_directory(const std::string& path);
// The rule that no output may be an input, checked before any work: throws cshapes::Error naming both when
// `output` already exists and is the same file as one of `inputs` (std::filesystem::equivalent: "./X", a
// symbolic link to X and a hard link of X are all X). An output that does not exist yet is no input; empty
// paths in `inputs` are ignored. `option` names the output in the message (e.g. "-o", "--history").
void check_output_not_input(const std::string& output, const std::vector<std::string>& inputs,
                            const std::string& option = "");

// Reads a whole file into a string; throws cshapes::FileError naming the file when it cannot be read. Only a
// regular file is read (symbolic links followed): a folder, a FIFO, a device (/dev/zero) or a socket is
// refused by name before it is opened, and a loop of links is named as such; at most the size the file had
// when opened is read.
std::string read_file(const std::string& path);
// Whether bytes start with a UTF-8 byte-order mark (EF BB BF), which some editors put before text.
bool starts_with_utf8_bom(std::string_view bytes);
// read_file for a text format: a leading UTF-8 byte-order mark is dropped.
std::string read_text_file(const std::string& path);

}  // namespace cshapes
