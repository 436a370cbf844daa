#include "cshapes/support/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <streambuf>
#include <vector>

#include "cshapes/support/error.h"

namespace cshapes {

namespace fs = std::filesystem;

namespace {

// The write fault of the test hook: from the `countdown`-th file on, every write fails with `error`.
std::atomic<long> g_fault_countdown{0};
std::atomic<int> g_fault_error{0};
std::atomic<bool> g_fault_active{false};

// Whether this file's bytes must be refused (the test hook), counting it.
bool write_fault_for_this_file() {
  if (g_fault_active) return true;
  long left = g_fault_countdown.load();
  while (left > 0 && !g_fault_countdown.compare_exchange_weak(left, left - 1)) {
  }
  if (left == 1) g_fault_active = true;
  return g_fault_active;
}

// An output stream buffer over a file descriptor that keeps the system's reason (errno) of the first failed
// write, so that the message can say "No space left on device" rather than "write failed".
class FileDescriptorBuffer : public std::streambuf {
 public:
  FileDescriptorBuffer(int fd, int injected_error)
      : fd_(fd), injected_error_(injected_error), buffer_(1 << 16) {
    setp(buffer_.data(), buffer_.data() + buffer_.size());
  }
  int error() const { return error_; }

 protected:
  int_type overflow(int_type ch) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(ch, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(ch);
      pbump(1);
    }
    return traits_type::not_eof(ch);
  }
  std::streamsize xsputn(const char* data, std::streamsize size) override {
    if (size <= epptr() - pptr()) {
      std::memcpy(pptr(), data, static_cast<size_t>(size));
      pbump(static_cast<int>(size));
      return size;
    }
    if (!drain() || !write_all(data, static_cast<size_t>(size))) return 0;
    return size;
  }
  int sync() override { return drain() ? 0 : -1; }

 private:
  bool drain() {
    const size_t size = static_cast<size_t>(pptr() - pbase());
    setp(buffer_.data(), buffer_.data() + buffer_.size());
    return write_all(buffer_.data(), size);
  }
  bool write_all(const char* data, size_t size) {
    if (error_) return false;
    if (size > 0 && injected_error_) {
      error_ = injected_error_;
      return false;
    }
    while (size > 0) {
      const ssize_t written = ::write(fd_, data, size);
      if (written < 0) {
        if (errno == EINTR) continue;
        error_ = errno;
        return false;
      }
      data += written;
      size -= static_cast<size_t>(written);
    }
    return true;
  }
  int fd_;
  int injected_error_;
  std::vector<char> buffer_;
  int error_ = 0;
};

// Where a write to `path` lands: the file itself, or the file a symbolic link at `path` points to (followed
// through every link), so that an output that is a link is written through, not replaced by a file.
std::string write_target(const std::string& path) {
  std::error_code ec;
  fs::path target(path);
  for (int hops = 0; fs::is_symlink(fs::symlink_status(target, ec)); ++hops) {
    if (hops == 40) fail_write(path, ": cannot write: too many levels of symbolic links");
    const fs::path link = fs::read_symlink(target, ec);
    if (ec) fail_write(path, ": cannot read the symbolic link: ", ec.message());
    target = link.is_absolute() ? link : target.parent_path() / link;
  }
  return target.string();
}

}  // namespace

void fail_file_writes_for_testing(long nth, int error_number) {
  g_fault_active = false;
  g_fault_error = error_number;
  g_fault_countdown = nth > 0 ? nth : 0;
}

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write,
                           bool binary) {
  (void)binary;  // POSIX writes bytes as they are
  static std::atomic<int> counter{0};
  const std::string target_path = write_target(path);
  fs::path target(target_path);
  if (target.has_parent_path()) {
    std::error_code ec;
    fs::create_directories(target.parent_path(), ec);
    if (ec) fail_write(path, ": cannot create folder ", target.parent_path().string(), ": ", ec.message());
  }
  // Host, process and a counter: unique among the threads and processes (MPI ranks on several nodes
  // included) that may write the same path at once on a shared file system.
  static const std::string host = [] {
    char name[256] = {};
    if (::gethostname(name, sizeof name - 1) != 0) return std::string("host");
    return std::string(name);
  }();
  const std::string tmp = detail::concat(target_path, ".tmp.", host, ".", ::getpid(), ".", counter++);
  const int injected = write_fault_for_this_file() ? g_fault_error.load() : 0;
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) fail_write(path, ": cannot create a file in its folder: ", std::strerror(errno));
  bool open = true;
  try {
    FileDescriptorBuffer buffer(fd, injected);
    std::ostream out(&buffer);
    write(out);
    out.flush();
    if (buffer.error()) fail_write(path, ": cannot write: ", std::strerror(buffer.error()));
    if (!out) fail_write(path, ": cannot write (the stream failed)");
    open = false;
    if (::close(fd) != 0) fail_write(path, ": cannot write: ", std::strerror(errno));
    if (std::rename(tmp.c_str(), target_path.c_str()) != 0)
      fail_write(path, ": cannot rename the temporary file into place: ", std::strerror(errno));
  } catch (...) {
    if (open) ::close(fd);
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
    fail_write(path, ": cannot write here: ", existing.string(), " is not a folder");
  // A probe is the only test that holds for root, ACLs and read-only mounts alike.
  std::string probe = detail::concat((existing / ".cshapes-probe.").string(), ::getpid());
  int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
  if (fd < 0 && errno == EEXIST) {
    ::unlink(probe.c_str());
    fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
  }
  if (fd < 0) fail_write(path, ": cannot write in ", existing.string(), ": ", std::strerror(errno));
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
  // A file goes into a folder that exists (as cp and a compiler's -o do): a mistyped folder is not created.
  if (target.has_parent_path() && !fs::is_directory(target.parent_path(), ec))
    fail_write(path, ": the folder ", target.parent_path().string(),
               fs::exists(target.parent_path(), ec) ? " is not a folder" : " does not exist (create it first)");
  check_folder_takes_files(path, target.parent_path());
}

void check_output_directory(const std::string& path) {
  if (path.empty()) fail("output folder is empty");
  std::error_code ec;
  if (fs::exists(path, ec) && !fs::is_directory(path, ec)) fail_write(path, ": exists and is not a folder");
  check_folder_takes_files(path, fs::path(path));
}

void check_output_not_input(const std::string& output, const std::vector<std::string>& inputs,
                            const std::string& option) {
  std::error_code ec;
  if (output.empty() || !fs::exists(output, ec)) return;
  const std::string named = option.empty() ? output : option + " " + output;
  for (const std::string& input : inputs) {
    if (input.empty()) continue;
    std::error_code same_ec;
    if (!fs::equivalent(output, input, same_ec) || same_ec) continue;
    fail(named, ": is the input ", input, input == output ? "" : " (the same file)",
         "; an output never replaces an input: write it to another path");
  }
}

std::string read_file(const std::string& path) {
  // What the path is, decided before anything is opened: a FIFO would block, a device (/dev/zero) never
  // ends, a folder is no file.
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    const int error = errno;
    if (error == ENOENT) fail_file(path, ": no such file");
    if (error == ELOOP) fail_file(path, ": a loop of symbolic links, no file at the end");
    fail_file(path, ": cannot read: ", std::strerror(error));
  }
  if (S_ISDIR(info.st_mode)) fail_file(path, ": is a directory, expected a file");
  if (!S_ISREG(info.st_mode))
    fail_file(path, ": is ",
              S_ISFIFO(info.st_mode)   ? "a FIFO (named pipe)"
              : S_ISCHR(info.st_mode)  ? "a character device"
              : S_ISBLK(info.st_mode)  ? "a block device"
              : S_ISSOCK(info.st_mode) ? "a socket"
                                       : "not a regular file",
              ", expected a regular file");
  // O_NONBLOCK: should the path have become a FIFO since the check, opening it does not wait for a writer.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) fail_file(path, ": cannot open for reading: ", std::strerror(errno));
  struct stat opened {};
  if (::fstat(fd, &opened) != 0 || !S_ISREG(opened.st_mode)) {
    ::close(fd);
    fail_file(path, ": changed while being opened, expected a regular file");
  }
  // At most the size the file had when opened: a file that keeps growing is read as it was.
  std::string bytes(static_cast<size_t>(opened.st_size), '\0');
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t got = ::read(fd, &bytes[done], bytes.size() - done);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) {
      const int error = errno;
      ::close(fd);
      fail_file(path, ": read error: ", std::strerror(error));
    }
    if (got == 0) break;  // shrank meanwhile
    done += static_cast<size_t>(got);
  }
  ::close(fd);
  bytes.resize(done);
  return bytes;
}

bool starts_with_utf8_bom(std::string_view bytes) {
  return bytes.size() >= 3 && bytes.substr(0, 3) == "\xEF\xBB\xBF";
}

std::string read_text_file(const std::string& path) {
  std::string text = read_file(path);
  if (starts_with_utf8_bom(text)) text.erase(0, 3);
  return text;
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
