// The numbers of one row of the tools' score table (calibrate_bag --test, score_calibration,
// compare_models): ATE, RPE, RMSE x, y, theta after the model's name.
#pragma once

#include <sstream>
#include <string>
#include <vector>

namespace odometry_calibration {
namespace test_support {

/// The five numbers of `model`'s row of `table` (a line starting with the name and a blank);
/// empty when there is no such row.
inline std::vector<double> scoreTableRow(const std::string& table, const std::string& model)
{
  const std::size_t at = table.find("\n" + model + " ");
  if (at == std::string::npos)
    return {};
  std::istringstream line(table.substr(at + 1 + model.size()));
  std::vector<double> values(5);
  for (double& value : values)
    line >> value;
  return values;
}

}  // namespace test_support
}  // namespace odometry_calibration
