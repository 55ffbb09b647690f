#include "odometry_calibration/common/atomic_file.h"

#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/file_size_limit.h"

namespace odometry_calibration {
namespace {

class AtomicFileTest : public ::testing::Test
{
protected:
  void SetUp() override
  {
    char pattern[] = "/tmp/atomic_file_test.XXXXXX";
    ASSERT_NE(mkdtemp(pattern), nullptr);
    dir_ = pattern;
  }

  void TearDown() override
  {
    for (const std::string& name : entries()) {
      const std::string full = dir_ + "/" + name;
      if (::unlink(full.c_str()) != 0) {
        ::rmdir(full.c_str());
      }
    }
    ::rmdir(dir_.c_str());
  }

  std::vector<std::string> entries() const
  {
    std::vector<std::string> names;
    DIR* dir = ::opendir(dir_.c_str());
    if (dir == nullptr)
      return names;
    while (const dirent* entry = ::readdir(dir)) {
      const std::string name = entry->d_name;
      if (name != "." && name != "..")
        names.push_back(name);
    }
    ::closedir(dir);
    return names;
  }

  static std::string readAll(const std::string& path)
  {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream content;
    content << in.rdbuf();
    return content.str();
  }

  std::string dir_;
};

TEST_F(AtomicFileTest, WritesContentThatReadsBack)
{
  const std::string path = dir_ + "/result.yaml";
  const std::string content = std::string("calibration:\n  b: 0.512\n") + '\0' + "tail\n";
  writeFileAtomically(path, content);
  EXPECT_EQ(readAll(path), content);
}

TEST_F(AtomicFileTest, WritesEmptyContent)
{
  const std::string path = dir_ + "/empty.txt";
  writeFileAtomically(path, "");
  struct stat info
  {
  };
  ASSERT_EQ(::stat(path.c_str(), &info), 0);
  EXPECT_EQ(info.st_size, 0);
}

TEST_F(AtomicFileTest, OverwriteReplacesWholeOldContent)
{
  const std::string path = dir_ + "/result.txt";
  writeFileAtomically(path, "a much longer old content that must disappear entirely\n");
  writeFileAtomically(path, "new\n");
  EXPECT_EQ(readAll(path), "new\n");
}

TEST_F(AtomicFileTest, LeavesNoTemporaryFilesAfterSuccess)
{
  writeFileAtomically(dir_ + "/a.txt", "first");
  writeFileAtomically(dir_ + "/a.txt", "second");
  writeFileAtomically(dir_ + "/b.txt", "third");
  const std::vector<std::string> names = entries();
  ASSERT_EQ(names.size(), 2u);
  for (const std::string& name : names) {
    EXPECT_EQ(name.find(".tmp."), std::string::npos) << name;
  }
}

TEST_F(AtomicFileTest, MissingDirectoryThrowsNamingThePath)
{
  const std::string path = dir_ + "/no_such_dir/result.txt";
  try {
    writeFileAtomically(path, "content");
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
  }
  EXPECT_TRUE(entries().empty());
}

TEST_F(AtomicFileTest, FailedRenameRemovesTemporaryFile)
{
  // Renaming a regular file over a directory fails (EISDIR).
  const std::string path = dir_ + "/occupied";
  ASSERT_EQ(::mkdir(path.c_str(), 0755), 0);
  try {
    writeFileAtomically(path, "content");
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
  }
  const std::vector<std::string> names = entries();
  ASSERT_EQ(names.size(), 1u);
  EXPECT_EQ(names[0], "occupied");
}

TEST_F(AtomicFileTest, WrittenFileHasMode0644EvenUnderRestrictiveUmask)
{
  const std::string path = dir_ + "/shared.txt";
  const mode_t old_umask = ::umask(077);
  writeFileAtomically(path, "content");
  ::umask(old_umask);
  struct stat info
  {
  };
  ASSERT_EQ(::stat(path.c_str(), &info), 0);
  EXPECT_EQ(info.st_mode & 07777, static_cast<mode_t>(0644));
}

TEST_F(AtomicFileTest, AFullDiskLeavesThePreviousFileIntact)
{
  const std::string path = dir_ + "/result.yaml";
  const std::string previous = "model: diff_drive\nradius: 0.0765\n";
  writeFileAtomically(path, previous);
  {
    const test::FileSizeLimit full_disk(100);  // the new content does not fit
    try {
      writeFileAtomically(path, std::string(10000, 'x'));
      ADD_FAILURE() << "a write beyond the limit succeeded";
    } catch (const std::runtime_error& error) {
      EXPECT_NE(std::string(error.what()).find("result.yaml"), std::string::npos) << error.what();
    }
  }
  EXPECT_EQ(readAll(path), previous);
  EXPECT_EQ(entries(), std::vector<std::string>{"result.yaml"});  // no temporary left behind
  writeFileAtomically(path, "retried\n");  // room again: the next write works
  EXPECT_EQ(readAll(path), "retried\n");
}

}  // namespace
}  // namespace odometry_calibration
