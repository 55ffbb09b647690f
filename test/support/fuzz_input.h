// Helpers of the libFuzzer targets (test/<layer>/*_fuzz.cpp, built by scripts/fuzz).
#pragma once

#include <unistd.h>
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>
#include <utility>

namespace odometry_calibration {
namespace test {

/// The fuzzer's bytes as a string.
inline std::string fuzzText(const std::uint8_t* data, std::size_t size)
{
  return std::string(reinterpret_cast<const char*>(data), size);
}

/// Splits `text` at the first line "---8<---": the part before and the part after (empty when
/// there is no such line). Lets one input carry two documents (a config and per-call options).
inline std::pair<std::string, std::string> splitFuzzText(const std::string& text)
{
  const std::string cut = "\n---8<---\n";
  const std::size_t at = text.find(cut);
  if (at == std::string::npos)
    return {text, ""};
  return {text.substr(0, at), text.substr(at + cut.size())};
}

/// Writes `text` to a file of this process in /tmp and returns its path (for readers that
/// take a path).
inline std::string fuzzFile(const std::string& text, const std::string& suffix)
{
  const std::string path = "/tmp/odometry_calibration_fuzz_" + std::to_string(::getpid()) + suffix;
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
  return path;
}

}  // namespace test
}  // namespace odometry_calibration
