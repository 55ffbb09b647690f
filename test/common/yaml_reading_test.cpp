#include "odometry_calibration/common/yaml_reading.h"

#include <chrono>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "support/alias_bomb.h"

namespace odometry_calibration {
namespace {

using test::aliasBomb;

/// The message of what `load` throws ("" when it does not).
template <typename Load>
std::string thrown(Load load)
{
  try {
    load();
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  return "";
}

TEST(YamlReading, RefusesAnAliasBombAtOnceNamingTheSource)
{
  const auto start = std::chrono::steady_clock::now();
  const std::string message = thrown([] { loadYamlDocument(aliasBomb(9), "bomb.yaml"); });
  const double elapsed_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(message.rfind("bomb.yaml: YAML aliases expand to more than 100000 nodes", 0), 0u)
      << message;
  EXPECT_LT(elapsed_s, 2.0);
}

TEST(YamlReading, KeepsDocumentsWithinTheBoundAliasesIncluded)
{
  // Four levels: 10^4 nodes expanded, under the bound; a small document with an alias too.
  const YAML::Node four = loadYamlDocument(aliasBomb(4), "four.yaml");
  EXPECT_EQ(four["a3"].size(), 10u);
  const YAML::Node small =
      loadYamlDocument("pose: &p [0.1, 0, 0]\nsame: *p\nname: x\n", "small.yaml");
  EXPECT_EQ(small["same"][0].as<double>(), 0.1);
  // The bound is the caller's: the same four levels refused below 10^4.
  EXPECT_NE(thrown([] {
              loadYamlDocument(aliasBomb(4), "four.yaml", 5000);
            }).find("YAML aliases expand to more than 5000 nodes"),
            std::string::npos);
}

TEST(YamlReading, SaysWhenADocumentWithoutAliasesIsTooLarge)
{
  std::string list = "[";
  for (int i = 0; i < 200; ++i)
    list += (i > 0 ? ", " : "") + std::to_string(i);
  list += "]";
  const std::string message = thrown([&] { loadYamlDocument(list, "long.yaml", 100); });
  EXPECT_EQ(message.rfind("long.yaml: the document holds more than 100 nodes", 0), 0u) << message;
}

TEST(YamlReading, NamesTheSourceOfASyntaxError)
{
  const std::string message = thrown([] { loadYamlDocument("a: [1, 2\n", "broken.yaml"); });
  EXPECT_EQ(message.rfind("broken.yaml: ", 0), 0u) << message;
}

}  // namespace
}  // namespace odometry_calibration
