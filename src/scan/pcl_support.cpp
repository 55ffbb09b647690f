#include "odometry_calibration/scan/pcl_support.h"

namespace odometry_calibration {

std::string withoutPclMessage(const std::string& what)
{
  return what +
         " needs PCL, and this build was configured without it (scripts/demo installs only what "
         "the 2D tools need): run scripts/setup, which installs PCL and builds again with it";
}

}  // namespace odometry_calibration
