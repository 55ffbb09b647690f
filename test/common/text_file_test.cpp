#include "odometry_calibration/common/text_file.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

namespace odometry_calibration {
namespace {

class TextFileTest : public ::testing::Test
{
protected:
  void SetUp() override
  {
    char pattern[] = "/tmp/text_file_test.XXXXXX";
    ASSERT_NE(mkdtemp(pattern), nullptr);
    dir_ = pattern;
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  /// The message readTextFile throws for `path` ("" when it reads the file).
  static std::string refusal(const std::string& path)
  {
    try {
      readTextFile(path, "the configuration");
    } catch (const std::runtime_error& error) {
      return error.what();
    }
    return "";
  }

  std::string dir_;
};

TEST_F(TextFileTest, ReadsAFile)
{
  std::ofstream(dir_ + "/config.yaml") << "model: diff_drive\n";
  EXPECT_EQ(readTextFile(dir_ + "/config.yaml", "the configuration"), "model: diff_drive\n");
}

TEST_F(TextFileTest, GivesEachReasonItsOwnMessage)
{
  EXPECT_EQ(refusal(dir_), dir_ + " is a directory, not a configuration file");
  EXPECT_EQ(refusal(dir_ + "/missing.yaml"),
            dir_ + "/missing.yaml does not exist: give the path of the configuration file");
  std::ofstream(dir_ + "/empty.yaml").close();
  EXPECT_EQ(refusal(dir_ + "/empty.yaml"),
            dir_ + "/empty.yaml is empty: the configuration file holds nothing to read");
}

TEST_F(TextFileTest, RefusesWhatIsNotARegularFileWithoutWaiting)
{
  // A named pipe would block the read until someone writes into it.
  const std::string pipe = dir_ + "/pipe.yaml";
  ASSERT_EQ(mkfifo(pipe.c_str(), 0600), 0);
  EXPECT_EQ(refusal(pipe), pipe +
                               " is a named pipe, not a configuration file: give the path of the "
                               "file itself");
  EXPECT_EQ(refusal("/dev/zero"),
            "/dev/zero is a device, not a configuration file: give the path of the file itself");
}

TEST_F(TextFileTest, SaysWhyAnUnreadableFileCannotBeRead)
{
  const std::string path = dir_ + "/locked.yaml";
  std::ofstream(path) << "model: diff_drive\n";
  ASSERT_EQ(chmod(path.c_str(), 0), 0);
  if (geteuid() == 0)
    GTEST_SKIP() << "root reads a file without permissions";
  EXPECT_EQ(refusal(path), "cannot read the configuration " + path + ": Permission denied");
}

}  // namespace
}  // namespace odometry_calibration
