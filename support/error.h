// Errors: the library throws cshapes::Error with a message a user can act on (which file, which element,
// what was expected); it never prints or exits. The CLI catches, prints one line and exits non-zero.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

namespace cshapes {

namespace detail {
// A message as it can be printed whole: a NUL byte or another control character quoted from a file (a CSV
// field, a header token) would cut it short or garble the terminal; each becomes \xHH. Lines and tabs stay.
inline std::string printable_message(const std::string& message) {
  static const char digits[] = "0123456789abcdef";
  std::string out;
  out.reserve(message.size());
  for (const char c : message) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 32 && c != '\n' && c != '\t') {
      out += "\\x";
      out += digits[u >> 4];
      out += digits[u & 15];
    } else if (u == 127) {
      out += "\\x7f";
    } else {
      out += c;
    }
  }
  return out;
}
}  // namespace detail

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(detail::printable_message(message)) {}
};

// A file that cannot be found, opened, created or written (the file system's refusal, not its content):
// front ends that tell the two apart (the Python module raises OSError for it, ValueError for Error).
class FileError : public Error {
 public:
  explicit FileError(const std::string& message) : Error(message) {}
};

// A failed read or write of the run's own files (cache entries, outputs): the run's failure, never one
// shape's, so drivers that leave a failing shape out rethrow it (pipeline/shape_failures.h).
struct IoError : Error {
  using Error::Error;
};

// An output or cache file that cannot be written: a full disk, a read-only file system, a folder that is a
// file, a failed rename. Its message names the path and the system's reason (strerror). It is never a fault
// of one shape: a loop that skips a failing shape and goes on must rethrow it, so that the run stops before
// more work is lost:  catch (const WriteError&) { throw; }  before its  catch (const Error&).
class WriteError : public FileError {
 public:
  explicit WriteError(const std::string& message) : FileError(message) {}
};

namespace detail {
template <typename... Args>
std::string concat(const Args&... args) {
  std::ostringstream out;
  (out << ... << args);
  return out.str();
}
}  // namespace detail

// Throws cshapes::Error whose message is the concatenation of the arguments.
template <typename... Args>
[[noreturn]] void fail(const Args&... args) {
  throw Error(detail::concat(args...));
}

// Throws cshapes::FileError whose message is the concatenation of the arguments.
template <typename... Args>
[[noreturn]] void fail_file(const Args&... args) {
  throw FileError(detail::concat(args...));
}

// Throws cshapes::WriteError whose message is the concatenation of the arguments.
template <typename... Args>
[[noreturn]] void fail_write(const Args&... args) {
  throw WriteError(detail::concat(args...));
}

}  // namespace cshapes

// Checks a precondition in every build type (unlike assert):
// CSHAPES_REQUIRE(n > 0, "mesh ", name, " is empty").
#define CSHAPES_REQUIRE(cond, ...)             \
  do {                                         \
    if (!(cond)) ::cshapes::fail(__VA_ARGS__); \
  } while (0)
