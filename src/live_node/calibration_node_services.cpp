// The live node's services: ~calibrate, ~save, ~reset, each one call into the session (with
// several ego-motion sources ~calibrate is their joint fit, ~save saves every sensor).
#include <tuple>

#include "odometry_calibration/eval/model_report.h"
#include "odometry_calibration/live_node/calibration_node.h"
#include "odometry_calibration/ros/report_messages.h"

namespace odometry_calibration {

bool CalibrationNode::onCalibrate(Calibrate::Request& request, Calibrate::Response& response)
{
  CalibrationRequest call;
  call.model = request.model;
  call.options = request.options;
  call.reply_holdout_fraction = options_.holdout_fraction;
  const JointCalibrateOutcome joint = sessions_->calibrate(call);
  const CalibrateOutcome& outcome = joint.outcome;
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
  // Several sources: every sensor's table and the fits alone (the first sensor's view is the
  // reply's report); one source: its report.
  const std::string summary = joint.joint ? joint.text : formatModelReport(job.report);
  if (outcome.success && job.report.warnings.empty())
    ROS_INFO("%s\n%s", response.message.c_str(), summary.c_str());
  else
    ROS_WARN("%s\n%s", response.message.c_str(), summary.c_str());
  return true;
}

bool CalibrationNode::onSave(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& response)
{
  const auto [success, message] = sessions_->save();
  response.success = success;
  response.message = message;
  ROS_INFO("%s", message.c_str());
  return true;
}

bool CalibrationNode::onReset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& response)
{
  std::tie(response.success, response.message) = sessions_->reset();
  ROS_INFO("%s", response.message.c_str());
  return true;
}

}  // namespace odometry_calibration
