// The output folder of a command that writes a set of files (every experiment, `evaluate`, `generate`): a run
// never replaces what a user had, never leaves a mix of two runs' files, and leaves nothing of a previous run
// it no longer writes.
//
// A folder that cshapes owns holds a record, FOLDER/.cshapes-outputs, naming the command that owns it and the
// files (paths relative to FOLDER) its last complete run wrote. An OutputRun, made before any work:
//   - claims the folder: a missing or empty folder, or one whose record names the same command, is taken;
//     anything else (files cshapes did not write, or another command's outputs: a dataset's folder given as an
//     experiment's output) is refused with an Error naming one such file, unless `force` (then those files are
//     left where they are, replaced only where the run writes the same name);
//   - moves the previous run's files aside into FOLDER/.cshapes-previous, so that the run writes into a folder
//     holding only what it keeps between runs (`kept`: subfolders such as a cache, which make reruns resume)
//     and the user's files;
//   - commit(): the run completed; the previous run's files are deleted and the record lists the new set;
//   - destroyed without commit() (an exception, a full disk, Ctrl-C): the files this run wrote are removed and
//     the previous run's are moved back, so the folder holds the previous complete set again.
// A run killed outright (kill -9) leaves the record marked "running"; the next claim of the folder finds the
// process gone and restores the previous set first. Two live processes writing one folder: the second is refused.
#pragma once

#include <set>
#include <string>
#include <vector>
#include "cshapes/support/option_declaration.h"

namespace cshapes {

// `--force` and force=: the option a user sets to write where files cshapes did not write are (declared once,
// support/option_declaration.h).
// `--out DIR` and out= of every run over a dataset (the experiments).
inline const OptionDeclaration kOutFolderOption{
    "out", "--out",
    "output folder, created when missing (its cache/ makes reruns, and a killed run restarted, resume); a "
    "folder holding files cshapes did not write is refused, and a rerun removes the outputs of the previous "
    "one"};
inline const OptionDeclaration kForceOption{
    "force", "--force",
    "write although the outputs' place holds files cshapes did not write (they are left as they are, unless "
    "this run writes the same name)"};

class Communicator;

// The record's name inside an output folder.
inline constexpr const char* kOutputRecordName = ".cshapes-outputs";

class OutputRun {
 public:
  // folder: the output folder (created with its parents when missing). command: who owns it ("experiment
  // paper", "evaluate"). kept: top-level entries of folder that stay in place between runs (e.g. "cache").
  // With a communicator of several ranks, rank 0 does the file work and every rank throws the same Error.
  OutputRun(std::string folder, std::string command, std::vector<std::string> kept = {}, bool force = false,
            const Communicator* communicator = nullptr);
  ~OutputRun();
  OutputRun(const OutputRun&) = delete;
  OutputRun& operator=(const OutputRun&) = delete;

  // The run completed: rank 0 deletes the previous set and writes the record (a no-op on the other ranks).
  void commit();
  const std::string& folder() const { return folder_; }

 private:
  void claim();
  void roll_back() noexcept;

  std::string folder_, command_;
  std::vector<std::string> kept_;
  bool force_ = false;
  const Communicator* communicator_ = nullptr;
  bool committed_ = false;
  bool claimed_ = false;
  std::set<std::string> present_at_claim_;  // files that were there before the run (the user's, under force)
  std::set<std::string> previous_;          // the previous complete run's files, now in .cshapes-previous
};

// Who owns an output folder by its record: the command ("experiment retrieval"; "" when the folder has no
// record, or is missing) and whether its last run completed (false while a run writes it, or after one was
// killed: its files may then be a mix). For a command that reads another's outputs (`cshapes compare`).
struct OutputFolderOwner {
  std::string command;
  bool complete = false;
};
// Throws an Error naming the record when the folder holds a record cshapes cannot read.
OutputFolderOwner output_folder_owner(const std::string& folder);

// Moves every file under `staging` (a folder the caller wrote a result set into) to the same relative path under
// `target`, after checking that none of them would replace an existing file there (unless `force`): an Error
// naming the first such file otherwise, and `target` untouched. `staging` is removed in both cases. Returns the
// relative paths moved, in order.
std::vector<std::string> publish_staged_files(const std::string& staging, const std::string& target, bool force);

// A fresh, empty folder for a result set, inside `parent` (created when missing): parent/.cshapes-staging-<id>.
std::string make_staging_folder(const std::string& parent);

}  // namespace cshapes
