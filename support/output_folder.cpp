#include "cshapes/support/output_folder.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "cshapes/support/atomic_file.h"
#include "cshapes/support/communicator.h"
#include "cshapes/support/error.h"

namespace cshapes {

namespace fs = std::filesystem;

namespace {

constexpr const char* kPreviousName = ".cshapes-previous";
constexpr const char* kStagingPrefix = ".cshapes-staging-";
constexpr const char* kRecordHeader = "cshapes output folder 1";

struct OutputRecord {
  bool present = false;
  std::string command;
  bool running = false;
  long pid = 0;
  std::string host;
  std::set<std::string> files;    // the last complete run's files
  std::set<std::string> foreign;  // files that were there before (kept, never removed)
};

std::string host_name() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "";
  return name;
}

bool process_alive(long pid) {
  if (pid <= 0) return false;
  if (!(::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM)) return false;
  // A process killed outright stays a zombie until its parent reaps it (never, under an init that does not):
  // it writes nothing more, so it is not alive here (Linux's /proc/PID/stat: "PID (comm) STATE ...").
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (std::getline(stat, line)) {
    const size_t paren = line.rfind(')');
    if (paren != std::string::npos && paren + 2 < line.size() && (line[paren + 2] == 'Z' || line[paren + 2] == 'X'))
      return false;
  }
  return true;
}

// The record: a header line, then "key value" lines; file names are the rest of their line.
OutputRecord read_record(const fs::path& folder) {
  OutputRecord r;
  const fs::path path = folder / kOutputRecordName;
  std::error_code ec;
  if (!fs::exists(path, ec)) return r;
  std::istringstream in(read_text_file(path.string()));
  std::string line;
  if (!std::getline(in, line) || line != kRecordHeader)
    fail(path.string(), ": not a cshapes output record (expected its first line '", kRecordHeader,
         "'); remove it if the folder is yours");
  r.present = true;
  while (std::getline(in, line)) {
    const size_t space = line.find(' ');
    const std::string key = line.substr(0, space), value = space == std::string::npos ? "" : line.substr(space + 1);
    if (key == "command") r.command = value;
    else if (key == "state") r.running = value == "running";
    else if (key == "pid") r.pid = std::atol(value.c_str());
    else if (key == "host") r.host = value;
    else if (key == "file") r.files.insert(value);
    else if (key == "foreign") r.foreign.insert(value);
  }
  return r;
}

void write_record(const fs::path& folder, const OutputRecord& r) {
  write_file_atomically((folder / kOutputRecordName).string(), [&](std::ostream& out) {
    out << kRecordHeader << '\n'
        << "command " << r.command << '\n'
        << "state " << (r.running ? "running" : "complete") << '\n';
    if (r.running) out << "pid " << r.pid << '\n' << "host " << r.host << '\n';
    for (const std::string& f : r.files) out << "file " << f << '\n';
    for (const std::string& f : r.foreign) out << "foreign " << f << '\n';
  });
}

bool is_internal(const std::string& top) {
  return top == kOutputRecordName || top == kPreviousName || top.rfind(kStagingPrefix, 0) == 0;
}

// Every file (and link) under folder, relative, except the record's own entries and the kept top-level ones.
std::set<std::string> list_files(const fs::path& folder, const std::vector<std::string>& kept) {
  std::set<std::string> files;
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return files;
  for (const fs::directory_entry& top : fs::directory_iterator(folder, ec)) {
    const std::string name = top.path().filename().string();
    if (is_internal(name) || std::find(kept.begin(), kept.end(), name) != kept.end()) continue;
    if (top.is_directory(ec) && !top.is_symlink(ec)) {
      for (auto it = fs::recursive_directory_iterator(top.path(), ec); it != fs::recursive_directory_iterator();
           it.increment(ec)) {
        if (ec) break;
        if (!it->is_directory(ec) || it->is_symlink(ec))
          files.insert(fs::relative(it->path(), folder, ec).generic_string());
      }
    } else {
      files.insert(name);
    }
  }
  return files;
}

// Removes the empty folders on the way from folder/relative's parent up to folder (exclusive).
void remove_empty_parents(const fs::path& folder, const std::string& relative) {
  std::error_code ec;
  for (fs::path p = fs::path(relative).parent_path(); !p.empty(); p = p.parent_path()) {
    if (!fs::is_empty(folder / p, ec) || ec) return;
    fs::remove(folder / p, ec);
  }
}

void move_file(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  fs::create_directories(to.parent_path(), ec);
  fs::rename(from, to, ec);
  if (ec) fail_write("cannot move ", from.string(), " to ", to.string(), ": ", ec.message());
}

// The previous set of files (in .cshapes-previous) back in place; files not in `keep` removed first.
void restore(const fs::path& folder, const std::vector<std::string>& kept, const std::set<std::string>& keep) {
  for (const std::string& f : list_files(folder, kept))
    if (!keep.count(f)) {
      std::error_code ec;
      fs::remove(folder / f, ec);
      remove_empty_parents(folder, f);
    }
  const fs::path previous = folder / kPreviousName;
  std::error_code ec;
  if (fs::is_directory(previous, ec))
    for (const std::string& f : list_files(previous, {})) move_file(previous / f, folder / f);
  fs::remove_all(previous, ec);
}

std::string refusal(const fs::path& folder, const std::string& command, const std::string& why) {
  return folder.string() + ": " + why + "; cshapes " + command +
         " writes only into a new or empty folder or one it wrote before (choose another --out, or pass "
         "--force to write into it: files of other names are left as they are)";
}

}  // namespace

OutputRun::OutputRun(std::string folder, std::string command, std::vector<std::string> kept, bool force,
                     const Communicator* communicator)
    : folder_(std::move(folder)), command_(std::move(command)), kept_(std::move(kept)), force_(force),
      communicator_(communicator) {
  CSHAPES_REQUIRE(!folder_.empty(), command_, ": an output folder is required");
  const Communicator& comm = communicator_ ? *communicator_ : single_process();
  std::string problem;
  bool write_error = false;
  if (comm.is_root()) {
    try {
      claim();
    } catch (const WriteError& e) {
      problem = e.what();
      write_error = true;
    } catch (const Error& e) {
      problem = e.what();
    }
  }
  if (comm.size() > 1) {
    std::string message = (write_error ? "W" : "E") + problem;
    comm.broadcast_from_root(message);
    write_error = message[0] == 'W';
    problem = message.substr(1);
  }
  if (!problem.empty()) {
    if (write_error) throw WriteError(problem);
    throw Error(problem);
  }
  claimed_ = comm.is_root();
}

void OutputRun::claim() {
  const fs::path folder(folder_);
  std::error_code ec;
  if (fs::exists(folder, ec) && !fs::is_directory(folder, ec))
    fail(folder_, ": exists and is not a folder; cshapes ", command_, " writes its outputs into a folder");
  fs::create_directories(folder, ec);
  if (ec || !fs::is_directory(folder))
    fail_write("cannot create the output folder ", folder_, ": ", ec ? ec.message() : "not a folder");
  OutputRecord record = read_record(folder);
  std::set<std::string> foreign;
  if (record.present && record.command == command_) {
    if (record.running) {
      if (record.host == host_name() && process_alive(record.pid) && record.pid != static_cast<long>(getpid()))
        fail(folder_, ": another cshapes ", command_, " (process ", record.pid,
             ") is writing into this folder; wait for it, or choose another --out");
      // A run that was killed: its partial files go, the last complete set comes back.
      std::set<std::string> keep = record.foreign;
      restore(folder, kept_, keep);
    }
    fs::remove_all(folder / kPreviousName, ec);  // a commit stopped after writing its record
    foreign = record.foreign;
    for (const std::string& f : list_files(folder, kept_))
      if (!record.files.count(f) && !foreign.count(f)) {
        if (!force_) throw Error(refusal(folder, command_, "holds '" + f + "', which cshapes did not write"));
        foreign.insert(f);
      }
    previous_ = record.files;
  } else {
    const std::set<std::string> present = list_files(folder, kept_);
    if (!force_) {
      if (record.present)
        throw Error(refusal(folder, command_, "holds the outputs of cshapes " + record.command));
      if (!present.empty())
        throw Error(refusal(folder, command_, "holds '" + *present.begin() + "', which cshapes did not write"));
      for (const std::string& k : kept_)
        if (fs::exists(folder / k, ec))
          throw Error(refusal(folder, command_, "holds '" + k + "', which cshapes did not write"));
    }
    foreign = present;
  }
  // The previous set moves aside; what remains is the user's.
  for (const std::string& f : previous_) {
    if (foreign.count(f) || !fs::exists(fs::symlink_status(folder / f, ec))) continue;
    move_file(folder / f, folder / kPreviousName / f);
    remove_empty_parents(folder, f);
  }
  present_at_claim_ = list_files(folder, kept_);
  OutputRecord running;
  running.command = command_;
  running.running = true;
  running.pid = static_cast<long>(getpid());
  running.host = host_name();
  running.files = previous_;
  running.foreign = present_at_claim_;
  write_record(folder, running);
}

void OutputRun::commit() {
  if (!claimed_ || committed_) return;
  const fs::path folder(folder_);
  OutputRecord done;
  done.command = command_;
  for (const std::string& f : list_files(folder, kept_))
    (present_at_claim_.count(f) ? done.foreign : done.files).insert(f);
  write_record(folder, done);
  std::error_code ec;
  fs::remove_all(folder / kPreviousName, ec);
  committed_ = true;
}

void OutputRun::roll_back() noexcept {
  try {
    const fs::path folder(folder_);
    restore(folder, kept_, present_at_claim_);
    OutputRecord back;
    back.command = command_;
    back.files = previous_;
    back.foreign = present_at_claim_;
    write_record(folder, back);
  } catch (...) {
    // Nothing more can be done here; the record still says "running", so the next claim restores.
  }
}

OutputRun::~OutputRun() {
  if (claimed_ && !committed_) roll_back();
}

std::string make_staging_folder(const std::string& parent) {
  std::error_code ec;
  fs::create_directories(parent, ec);
  std::random_device device;
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::ostringstream name;
    name << kStagingPrefix << getpid() << '-' << std::hex << device();
    const fs::path path = fs::path(parent) / name.str();
    if (fs::create_directory(path, ec)) return path.string();
  }
  fail_write("cannot create a staging folder in ", parent, ": ", ec ? ec.message() : "name taken");
}

OutputFolderOwner output_folder_owner(const std::string& folder) {
  const OutputRecord record = read_record(folder);
  OutputFolderOwner owner;
  if (!record.present) return owner;
  owner.command = record.command;
  owner.complete = !record.running;
  return owner;
}

std::vector<std::string> publish_staged_files(const std::string& staging, const std::string& target, bool force) {
  struct Cleanup {
    std::string path;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(path, ec);
    }
  } cleanup{staging};
  const std::set<std::string> files = list_files(staging, {});
  std::error_code ec;
  if (!force)
    for (const std::string& f : files)
      if (fs::exists(fs::symlink_status(fs::path(target) / f, ec)))
        fail((fs::path(target) / f).string(),
             ": exists; cshapes never replaces a file it was not asked to (pass --force to replace it, or "
             "choose another output)");
  std::vector<std::string> moved;
  for (const std::string& f : files) {
    move_file(fs::path(staging) / f, fs::path(target) / f);
    moved.push_back(f);
  }
  return moved;
}

}  // namespace cshapes
