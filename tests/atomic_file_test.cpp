// Writing outputs (support/atomic_file.h): a failed write is a WriteError naming the path and the system's
// reason, nothing partial is left, and a symbolic link is written through.
#include "cshapes/support/atomic_file.h"

#include <gtest/gtest.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "cshapes/support/error.h"
#include "tests/test_support.h"

namespace cshapes {
namespace atomic_file_test {

namespace fs = std::filesystem;

void write_text_atomically(const std::string& path, const std::string& text) {
  write_file_atomically(path, [&](std::ostream& out) { out << text; });
}

// The WriteError message of writing `path`, failing the test when there is none.
std::string write_error(const std::string& path) {
  try {
    write_text_atomically(path, std::string(200000, 'x'));
  } catch (const WriteError& e) {
    return e.what();
  }
  ADD_FAILURE() << path << ": written";
  return "";
}

TEST(AtomicFile, AFullDiskIsAWriteErrorAndLeavesNothing) {
  const std::string dir = test::scratch_dir("atomic-full");
  write_text_atomically(dir + "/old.txt", "old");
  fail_file_writes_for_testing(2, ENOSPC);
  write_text_atomically(dir + "/first.txt", "fits");
  std::string message = write_error(dir + "/old.txt");
  fail_file_writes_for_testing(0);
  EXPECT_EQ(message.rfind(dir + "/old.txt: ", 0), 0u) << message;
  EXPECT_NE(message.find(std::strerror(ENOSPC)), std::string::npos) << message;
  EXPECT_EQ(read_file(dir + "/old.txt"), "old");  // untouched
  EXPECT_EQ(read_file(dir + "/first.txt"), "fits");
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();
  // Another reason, as the system gives it.
  fail_file_writes_for_testing(1, EROFS);
  message = write_error(dir + "/x.txt");
  fail_file_writes_for_testing(0);
  EXPECT_NE(message.find(std::strerror(EROFS)), std::string::npos) << message;
  fs::remove_all(dir);
}

TEST(AtomicFile, AFolderThatIsAFileIsAWriteErrorWithTheReason) {
  const std::string dir = test::scratch_dir("atomic-not-folder");
  test::write_text(dir + "/file", "x");
  const std::string message = write_error(dir + "/file/sub/out.txt");
  EXPECT_EQ(message.rfind(dir + "/file/sub/out.txt: ", 0), 0u) << message;
  EXPECT_NE(message.find(std::strerror(ENOTDIR)), std::string::npos) << message;
  EXPECT_THROW(check_output_directory(dir + "/file"), WriteError);
  fs::remove_all(dir);
}

TEST(AtomicFile, ASymbolicLinkIsWrittenThrough) {
  // Issue 22: an output that was a symbolic link was replaced by a file.
  const std::string dir = test::scratch_dir("atomic-link");
  fs::create_directories(dir + "/real");
  test::write_text(dir + "/real/target.csv", "old");
  fs::create_symlink("real/target.csv", dir + "/link.csv");  // relative, as `ln -s` makes them
  write_text_atomically(dir + "/link.csv", "new");
  EXPECT_TRUE(fs::is_symlink(dir + "/link.csv"));
  EXPECT_EQ(read_file(dir + "/real/target.csv"), "new");
  // A link to a file not there yet: the file is made where the link points.
  fs::create_symlink(dir + "/real/later.csv", dir + "/dangling.csv");
  write_text_atomically(dir + "/dangling.csv", "made");
  EXPECT_TRUE(fs::is_symlink(dir + "/dangling.csv"));
  EXPECT_EQ(read_file(dir + "/real/later.csv"), "made");
  fs::remove_all(dir);
}

}  // namespace atomic_file_test
}  // namespace cshapes
