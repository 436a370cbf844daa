#include "core/atomic_file.h"

#include <unistd.h>

#include <atomic>
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
    if (ec) fail(path, ": cannot create directory ", target.parent_path().string(), ": ", ec.message());
  }
  std::string tmp = detail::concat(path, ".tmp.", ::getpid(), ".", counter++);
  try {
    std::ofstream out(tmp, binary ? std::ios::out | std::ios::binary | std::ios::trunc
                                  : std::ios::out | std::ios::trunc);
    if (!out) fail(path, ": cannot open for writing: ", std::strerror(errno));
    write(out);
    out.flush();
    if (!out) fail(path, ": write failed (disk full?)");
    out.close();
    if (std::rename(tmp.c_str(), path.c_str()) != 0) fail(path, ": cannot rename temporary file: ", std::strerror(errno));
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
}

std::string read_file(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) fail(path, ": no such file");
  if (fs::is_directory(path, ec)) fail(path, ": is a directory, expected a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, ": cannot open for reading: ", std::strerror(errno));
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) fail(path, ": read error");
  return buffer.str();
}

}  // namespace cshapes
