// AtomicFile / write_file_atomic (hrpp/util/atomic_file.h): the output appears under its name only
// when complete; every failure removes the temporary file and names the file and the reason.
#include "hrpp/util/atomic_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "test_util.h"

namespace hrpp {
namespace {

namespace fs = std::filesystem;
using test::temp_dir;

std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

TEST(AtomicFile, AppearsUnderItsNameOnlyAtCommit) {
  const std::string dir = temp_dir("atomic_file_commit");
  const std::string path = dir + "/out.bin";
  {
    AtomicFile f(path);
    EXPECT_EQ(f.tmp_path(), path + ".tmp");
    f.write("abc");
    EXPECT_GE(std::fputs("def", f.stream()), 0);
    EXPECT_FALSE(fs::exists(path));
    EXPECT_TRUE(fs::exists(path + ".tmp"));
    f.commit();
  }
  EXPECT_EQ(read_text(path), "abcdef");
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  write_file_atomic(path, std::string_view("x\0y", 3));
  EXPECT_EQ(read_text(path), std::string("x\0y", 3));
}

TEST(AtomicFile, WithoutCommitLeavesTheTargetAsItWas) {
  const std::string dir = temp_dir("atomic_file_abandon");
  const std::string path = dir + "/out.json";
  write_file_atomic(path, "old");
  {
    AtomicFile f(path);
    f.write("new, half written");
  }
  EXPECT_EQ(read_text(path), "old");
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  AtomicFile g(path);
  EXPECT_THROW(g.fail("disk full"), AtomicFileError);
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  EXPECT_EQ(read_text(path), "old");
}

TEST(AtomicFile, ErrorsNameTheFileAndTheReason) {
  const std::string dir = temp_dir("atomic_file_errors");
  try {
    write_file_atomic(dir + "/no/such/dir/out.json", "x");
    FAIL() << "no error";
  } catch (const AtomicFileError& e) {
    EXPECT_STREQ(e.what(), (dir + "/no/such/dir/out.json.tmp: cannot open for writing: No such "
                                  "file or directory")
                               .c_str());
  }
  // A non-empty directory cannot be replaced by a file: the rename fails.
  const std::string target = dir + "/taken";
  fs::create_directories(target + "/inside");
  try {
    write_file_atomic(target, "x");
    FAIL() << "no error";
  } catch (const AtomicFileError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(target + ": cannot rename " + target + ".tmp to it: ", 0),
              0u)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(target + ".tmp"));
  AtomicFile f(dir + "/twice");
  f.commit();
  EXPECT_THROW(f.commit(), AtomicFileError);
  EXPECT_THROW(f.write("late"), AtomicFileError);
}

}  // namespace
}  // namespace hrpp
