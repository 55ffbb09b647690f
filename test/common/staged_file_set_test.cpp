// A set of files replaced whole or not at all (issue 32): the old set stays when a rename fails
// half-way (every entry put back) or when the new set is abandoned before commit.
#include "odometry_calibration/common/staged_file_set.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "support/files.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;

void write(const std::string& path, const std::string& text)
{
  std::ofstream(path) << text;
}

class FileSet : public ::testing::Test
{
protected:
  void SetUp() override
  {
    char pattern[] = "/tmp/staged_file_set_test.XXXXXX";
    directory_ = mkdtemp(pattern);
    write(directory_ + "/a.txt", "old a");
    write(directory_ + "/b.txt", "old b");
    write(directory_ + "/keep.txt", "not in the set");
    fs::create_directory(directory_ + "/plots");
    write(directory_ + "/plots/p.dat", "old plot");
  }
  void TearDown() override { fs::remove_all(directory_); }

  /// The new set staged: a.txt, plots/ (b.txt is removed by it).
  void stage(StagedFileSet& set)
  {
    write(set.stagedPath("a.txt"), "new a");
    fs::create_directory(set.stagedPath("plots"));
    write(set.stagedPath("plots") + "/p.dat", "new plot");
  }
  /// The folder's entries (staging folders included).
  std::size_t entries() const
  {
    return static_cast<std::size_t>(std::distance(fs::directory_iterator(directory_), {}));
  }
  std::string read(const std::string& name) const
  {
    return test_support::readFile(directory_ + "/" + name);
  }

  std::string directory_;
};

TEST_F(FileSet, ReplacesTheSetAndKeepsOtherFiles)
{
  {
    StagedFileSet set(directory_);
    stage(set);
    set.commit({"a.txt", "plots"}, {"b.txt"});
  }
  EXPECT_EQ(read("a.txt"), "new a");
  EXPECT_EQ(read("plots/p.dat"), "new plot");
  EXPECT_FALSE(fs::exists(directory_ + "/b.txt"));
  EXPECT_EQ(read("keep.txt"), "not in the set");
  EXPECT_EQ(entries(), 3u);  // a.txt, plots, keep.txt: no staging folder left
}

TEST_F(FileSet, AFailedRenamePutsTheOldSetBack)
{
  int renames = 0;
  {
    // The fourth rename fails: b.txt and a.txt and plots were moved aside, the new a.txt was in.
    StagedFileSet set(directory_, [&](const std::string& from, const std::string& to) {
      if (++renames == 5) {
        errno = ENOSPC;
        return -1;
      }
      return std::rename(from.c_str(), to.c_str());
    });
    stage(set);
    try {
      set.commit({"a.txt", "plots"}, {"b.txt"});
      FAIL() << "the injected rename failure was not reported";
    } catch (const std::runtime_error& error) {
      EXPECT_NE(std::string(error.what()).find("No space left on device"), std::string::npos)
          << error.what();
      EXPECT_NE(std::string(error.what()).find("previous files are kept"), std::string::npos);
    }
  }
  EXPECT_EQ(renames, 5);
  EXPECT_EQ(read("a.txt"), "old a");
  EXPECT_EQ(read("b.txt"), "old b");
  EXPECT_EQ(read("plots/p.dat"), "old plot");
  EXPECT_EQ(entries(), 4u);  // the old set and keep.txt, nothing new
}

TEST_F(FileSet, EntriesInSubfoldersAreOneSet)
{
  // A set spread over the folder and a subfolder (a joint session's source_<k>/ files).
  fs::create_directory(directory_ + "/source_0");
  write(directory_ + "/source_0/a.txt", "old source a");
  int renames = 0;
  {
    StagedFileSet set(directory_, [&](const std::string& from, const std::string& to) {
      if (++renames == 4) {  // a.txt and source_0/a.txt aside, source_0/a.txt in, a.txt fails
        errno = EIO;
        return -1;
      }
      return std::rename(from.c_str(), to.c_str());
    });
    write(set.stagedPath("source_0/a.txt"), "new source a");
    write(set.stagedPath("a.txt"), "new a");
    EXPECT_THROW(set.commit({"source_0/a.txt", "a.txt"}), std::runtime_error);
  }
  EXPECT_EQ(read("source_0/a.txt"), "old source a");
  EXPECT_EQ(read("a.txt"), "old a");
  {
    StagedFileSet set(directory_);
    write(set.stagedPath("source_0/a.txt"), "new source a");
    write(set.stagedPath("a.txt"), "new a");
    set.commit({"source_0/a.txt", "a.txt"});
  }
  EXPECT_EQ(read("source_0/a.txt"), "new source a");
  EXPECT_EQ(read("a.txt"), "new a");
  EXPECT_EQ(entries(), 5u);  // a.txt, b.txt, keep.txt, plots, source_0: no staging folder
}

TEST_F(FileSet, AnAbandonedSetLeavesNothing)
{
  {
    StagedFileSet set(directory_);
    stage(set);
  }
  EXPECT_EQ(read("a.txt"), "old a");
  EXPECT_EQ(entries(), 4u);
}

}  // namespace
}  // namespace odometry_calibration
