#include "tactile_servo/servo_stage.hpp"

#include <cmath>

namespace tactile {

ConfigResult ServoStage::configure(const ServoParams& params, double nominal_period_s) {
  if (!(nominal_period_s > 0.0) || !std::isfinite(nominal_period_s) || nominal_period_s > 10.0)
    return rangeError("servo period", nominal_period_s, "must be in (0, 10] s");
  ConfigResult r = servo_.configure(params);
  if (!r) return r;
  nominal_period_ = nominal_period_s;
  reset();
  return ConfigResult::success();
}

void ServoStage::reset() {
  servo_.reset();
  in_ = ServoInput();
  have_pose_ = false;
  first_cycle_ = true;
  last_time_ = 0.0;
}

bool ServoStage::setMeasuredPose(const Pose& p) {
  const bool ok = validPose(p);  // the one pose-validity rule (tactile_types)
  // Before the first valid pose an invalid one is ignored (it must not seed
  // the command); afterwards it reaches the core, which holds (InvalidInput).
  if (ok || have_pose_) in_.flange_measured = p;
  if (ok) have_pose_ = true;
  return ok;
}

bool ServoStage::setEstimatedWrench(const Wrench& w) {
  bool ok = std::isfinite(w.time_s);
  for (double v : w.w) ok = ok && std::isfinite(v);
  if (ok) {
    in_.wrench = w;
    in_.have_wrench = true;
  }
  return ok;
}

bool ServoStage::setRobotState(const RobotState& r) {
  if (!std::isfinite(r.time_s)) return false;
  in_.robot_ready = r.commandable;
  in_.dry_run = r.dry_run;
  in_.robot_setpoint = validPose(r.setpoint) ? r.setpoint : kNoPose;
  in_.have_q = true;
  for (double v : r.q) in_.have_q = in_.have_q && std::isfinite(v);
  if (in_.have_q) in_.q = r.q;
  return true;
}

bool ServoStage::step(double now, const ContactFeatures& features, ServoOutput& out, ServoStatus& status) {
  in_.time_s = now;
  in_.features = features;
  if (!have_pose_) {  // the core waits (WaitingForPose, no command) and reports its phase;
    status = servo_.step(in_, nominal_period_, out);  // the first real cycle keeps the nominal dt
    return out.valid;
  }
  const double dt = first_cycle_ ? nominal_period_ : now - last_time_;
  first_cycle_ = false;
  last_time_ = now;
  status = servo_.step(in_, dt, out);
  return out.valid;
}

}  // namespace tactile
