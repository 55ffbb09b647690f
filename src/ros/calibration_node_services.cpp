// The live node's services: ~calibrate, ~save, ~reset, each one call into the session.
#include <tuple>

#include "odometry_calibration/eval/model_report.h"
#include "odometry_calibration/ros/calibration_node.h"
#include "odometry_calibration/ros/report_messages.h"

namespace odometry_calibration {

bool CalibrationNode::onCalibrate(Calibrate::Request& request, Calibrate::Response& response)
{
  CalibrationRequest call;
  call.model = request.model;
  call.options = request.options;
  const CalibrateOutcome outcome = session_->calibrate(call);
  response.success = outcome.success;
  response.message = outcome.message;
  if (!outcome.fit)
    return true;
  const CalibrationJobResult& job = outcome.fit->job;
  if (!outcome.fit->interval_text.empty())
    ROS_INFO("%s", outcome.fit->interval_text.c_str());
  response.report =
      ros_conversions::toReportMsg(job.report, outcome.pairs_collected, job.time_offset_s);
  report_publisher_.publish(response.report);
  const std::string summary = formatModelReport(job.report);
  if (outcome.success && job.report.warnings.empty())
    ROS_INFO("%s\n%s", response.message.c_str(), summary.c_str());
  else
    ROS_WARN("%s\n%s", response.message.c_str(), summary.c_str());
  return true;
}

bool CalibrationNode::onSave(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& response)
{
  const auto [success, message] = session_->save();
  response.success = success;
  response.message = message;
  ROS_INFO("%s", message.c_str());
  return true;
}

bool CalibrationNode::onReset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& response)
{
  std::tie(response.success, response.message) = session_->reset();
  ROS_INFO("%s", response.message.c_str());
  return true;
}

}  // namespace odometry_calibration
