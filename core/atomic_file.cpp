#include "core/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sstream>

#include "core/error.h"

namespace cshapes {

namespace fs = std::filesystem;

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write,
                           bool binary) {
  static std::atomic<int> counter{0};
  fs::path target(path);
  if (target.has_parent_path()) {
    std::error_code ec;
    fs::create_directories(target.parent_path(), ec);
    if (ec) fail_file(path, ": cannot create directory ", target.parent_path().string(), ": ", ec.message());
  }
  // Host, process and a counter: unique among the threads and processes (MPI ranks on several nodes
  // included) that may write the same path at once on a shared file system.
  static const std::string host = [] {
    char name[256] = {};
    if (::gethostname(name, sizeof name - 1) != 0) return std::string("host");
    return std::string(name);
  }();
  std::string tmp = detail::concat(path, ".tmp.", host, ".", ::getpid(), ".", counter++);
  try {
    std::ofstream out(
        tmp, binary ? std::ios::out | std::ios::binary | std::ios::trunc : std::ios::out | std::ios::trunc);
    if (!out) fail_file(path, ": cannot open for writing: ", std::strerror(errno));
    write(out);
    out.flush();
    if (!out) fail_file(path, ": write failed (disk full?)");
    out.close();
    if (std::rename(tmp.c_str(), path.c_str()) != 0)
      fail_file(path, ": cannot rename temporary file: ", std::strerror(errno));
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
}

namespace {

// The folder that would hold a new entry at `path`, and whether it must be created first.
// Throws when an ancestor is not a folder or the path is a folder.
void check_folder_takes_files(const std::string& path, const fs::path& folder) {
  fs::path existing = folder.empty() ? fs::path(".") : folder;
  std::error_code ec;
  while (!fs::exists(existing, ec)) {
    if (!existing.has_parent_path() || existing.parent_path() == existing) {
      existing = ".";
      break;
    }
    existing = existing.parent_path();
  }
  if (!fs::is_directory(existing, ec))
    fail(path, ": cannot write here: ", existing.string(), " is not a folder");
  // A probe is the only test that holds for root, ACLs and read-only mounts alike.
  std::string probe = detail::concat((existing / ".cshapes-probe.").string(), ::getpid());
  int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
  if (fd < 0 && errno == EEXIST) {
    ::unlink(probe.c_str());
    fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
  }
  if (fd < 0) fail_file(path, ": cannot write in ", existing.string(), ": ", std::strerror(errno));
  ::close(fd);
  ::unlink(probe.c_str());
}

std::string lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

}  // namespace

void check_output_path(const std::string& path, const std::vector<std::string>& extensions) {
  if (path.empty()) fail("output path is empty");
  const fs::path target(path);
  std::error_code ec;
  if (fs::is_directory(target, ec) || path.back() == '/') fail(path, ": is a folder, expected a file name");
  if (!extensions.empty()) {
    const std::string ext = lower(target.extension().string());
    std::string known;
    for (const std::string& e : extensions) known += (known.empty() ? "." : ", .") + e;
    if (ext.size() < 2) fail(path, ": no file extension; expected ", known);
    if (std::find(extensions.begin(), extensions.end(), ext.substr(1)) == extensions.end())
      fail(path, ": cannot write '", ext, "' files; expected ", known);
  }
  check_folder_takes_files(path, target.parent_path());
}

void check_output_directory(const std::string& path) {
  if (path.empty()) fail("output folder is empty");
  std::error_code ec;
  if (fs::exists(path, ec) && !fs::is_directory(path, ec)) fail(path, ": exists and is not a folder");
  check_folder_takes_files(path, fs::path(path));
}

std::string read_file(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) fail_file(path, ": no such file");
  if (fs::is_directory(path, ec)) fail_file(path, ": is a directory, expected a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail_file(path, ": cannot open for reading: ", std::strerror(errno));
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) fail_file(path, ": read error");
  return buffer.str();
}

void write_csv(const std::string& path, const std::vector<std::string>& columns,
               const std::vector<std::vector<double>>& rows) {
  write_file_atomically(path, [&](std::ostream& out) {
    for (size_t c = 0; c < columns.size(); ++c) out << (c ? "," : "") << columns[c];
    out << '\n';
    out.precision(10);
    for (const auto& row : rows) {
      for (size_t c = 0; c < row.size(); ++c) out << (c ? "," : "") << row[c];
      out << '\n';
    }
  });
}

}  // namespace cshapes
