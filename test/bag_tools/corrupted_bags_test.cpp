// calibrate_bag on broken bags: truncated, unindexed and corrupted ones (random bytes of random
// chunks overwritten, 50 fixed seeds) end with an exit status and a message naming the bag,
// never with a signal (a crash, an abort, an uncaught exception).
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "odometry_calibration/bag_writers/sim_bag_writer.h"
#include "odometry_calibration/sim/scenario.h"

#include "support/files.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;
const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;
const std::string kTool = CALIBRATE_BAG_PROGRAM;

using test_support::readFile;

class CorruptedBags : public ::testing::Test
{
protected:
  static void SetUpTestSuite()
  {
    char pattern[] = "/tmp/corrupted_bags_test.XXXXXX";
    directory_ = mkdtemp(pattern);
    sim::Scenario scenario = sim::loadScenarioYaml(
        kConfig + "/sim/scenarios/diff_drive_office.yaml", kConfig + "/sim/worlds");
    scenario.duration_s = 6.0;
    simulateToBag(scenario, directory_ + "/clean.bag", "");
    clean_ = readFile(directory_ + "/clean.bag");
  }
  static void TearDownTestSuite() { fs::remove_all(directory_); }

  struct Outcome
  {
    bool exited = false;  ///< false: killed by a signal
    int status = -1;      ///< exit status, or the signal
    std::string error;    ///< stderr
  };

  /// Writes `bytes` as `name` and runs calibrate_bag on it.
  static Outcome run(const std::string& name, const std::string& bytes)
  {
    const std::string bag = directory_ + "/" + name;
    std::ofstream(bag, std::ios::binary) << bytes;
    const std::string command = kTool + " --config " + kConfig + "/diff_drive.yaml " + bag +
                                " --quiet --gnuplot /bin/true --output-dir " + directory_ +
                                "/out > /dev/null 2> " + directory_ + "/stderr.txt";
    const int status = std::system(command.c_str());
    Outcome outcome;
    // The shell reports a program killed by a signal as exit status 128 + signal.
    outcome.exited = WIFEXITED(status) && WEXITSTATUS(status) < 128;
    outcome.status = WIFEXITED(status) ? WEXITSTATUS(status) % 128 : WTERMSIG(status);
    outcome.error = readFile(directory_ + "/stderr.txt");
    if (outcome.exited) {
      fs::remove(bag);
    } else {  // kept for a replay
      fs::rename(bag, "/tmp/" + name);
      outcome.error += "(the bag is kept as /tmp/" + name + ")";
    }
    return outcome;
  }

  static std::string directory_;
  static std::string clean_;
};

std::string CorruptedBags::directory_;
std::string CorruptedBags::clean_;

TEST_F(CorruptedBags, TruncatedAndUnindexedBagsAreNamedAndExitOne)
{
  for (const double fraction : {0.0, 0.01, 0.3, 0.5, 0.9, 0.999}) {
    const Outcome outcome =
        run("truncated.bag", clean_.substr(0, static_cast<std::size_t>(fraction * clean_.size())));
    ASSERT_TRUE(outcome.exited) << fraction << ": signal " << outcome.status;
    EXPECT_EQ(outcome.status, 1) << fraction << ": " << outcome.error;
    EXPECT_NE(outcome.error.find("truncated.bag"), std::string::npos) << outcome.error;
  }
  // A recording that was never closed: the header's index position is zero (as in a
  // .bag.active file left by a crash).
  std::string unindexed = clean_;
  const std::size_t field = unindexed.find("index_pos=");
  ASSERT_NE(field, std::string::npos);
  for (std::size_t i = 0; i < 8; ++i)
    unindexed[field + 10 + i] = '\0';
  const Outcome outcome = run("unindexed.bag", unindexed);
  ASSERT_TRUE(outcome.exited) << "signal " << outcome.status;
  EXPECT_EQ(outcome.status, 1) << outcome.error;
  EXPECT_NE(outcome.error.find("unindexed.bag"), std::string::npos) << outcome.error;
  EXPECT_NE(outcome.error.find("reindex"), std::string::npos) << outcome.error;
}

TEST_F(CorruptedBags, RandomCorruptionsNeverCrash)
{
  // Each seed overwrites 100 random bytes of the chunks (past the 4 KiB bag header), in runs
  // of 1 to 8 bytes, so that record lengths, headers and message data are all hit.
  std::map<int, int> statuses;
  for (unsigned seed = 0; seed < 50; ++seed) {
    std::mt19937 random(seed);
    std::string bytes = clean_;
    std::uniform_int_distribution<std::size_t> where(4096 + 13, bytes.size() - 1);
    std::uniform_int_distribution<int> value(0, 255), run_length(1, 8);
    for (int corrupted = 0; corrupted < 100;) {
      const std::size_t at = where(random);
      for (int k = run_length(random); k > 0 && corrupted < 100 && at + k < bytes.size(); --k) {
        bytes[at + static_cast<std::size_t>(k)] = static_cast<char>(value(random));
        ++corrupted;
      }
    }
    const Outcome outcome = run("corrupted-" + std::to_string(seed) + ".bag", bytes);
    ASSERT_TRUE(outcome.exited) << "seed " << seed << ": killed by signal " << outcome.status
                                << "\n"
                                << outcome.error;
    // 1: the bag is unreadable (named); 0, 3, 4, 5: the damage hit only message data, which
    // gave a calibration (or one that warns); never 2 (usage) or anything else.
    EXPECT_TRUE(outcome.status == 0 || outcome.status == 1 || outcome.status == 3 ||
                outcome.status == 4 || outcome.status == 5)
        << "seed " << seed << ": exit " << outcome.status << "\n"
        << outcome.error;
    if (outcome.status == 1) {
      EXPECT_NE(outcome.error.find("corrupted-" + std::to_string(seed) + ".bag"), std::string::npos)
          << outcome.error;
      EXPECT_NE(outcome.error.find("is corrupted"), std::string::npos) << outcome.error;
    }
    ++statuses[outcome.status];
  }
  std::string summary;
  for (const auto& [status, n] : statuses)
    summary += " exit " + std::to_string(status) + ": " + std::to_string(n);
  std::cout << "50 corrupted bags:" << summary << "\n";
}

}  // namespace
}  // namespace odometry_calibration
