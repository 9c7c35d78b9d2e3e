// The servo stage of the loop: features + measured flange pose -> pose command
// (tactile::TactileServo, Sec. 4, Algorithm 1, Eq. 7-15). The one
// implementation used by tactile::ServoComponent (RTT) and by the headless
// runner (tactile_sim): they only move data to and from it.
//
// On top of the core it owns the two things both hosts need:
//  * the measured pose gate: until a valid measured pose (tactile::validPose)
//    has arrived, the core's own gate waits (status WaitingForPose, no
//    command: a default pose never seeds the command) and the stage keeps
//    the first cycle's nominal period for the first cycle with a pose;
//  * the cycle time: dt = now - previous cycle, `nominal_period_s` on the first
//    cycle after reset().
//
// RTT-free, allocation-free, exception-free per step; configuration allocates.
#pragma once

#include "tactile_servo/servo.hpp"

namespace tactile {

class ServoStage {
 public:
  /// `nominal_period_s` (> 0): dt of the first cycle (the servo period).
  ConfigResult configure(const ServoParams& params, double nominal_period_s);

  /// Start of a run: initial phase, no measured pose yet, first cycle next.
  void reset();

  /// A measured flange pose {g}T{e}. Returns false when invalid: before the
  /// first valid one it is ignored; afterwards the core sees it and holds
  /// (status InvalidInput).
  bool setMeasuredPose(const Pose& flange_g);
  bool havePose() const { return have_pose_; }
  /// The arm's estimated external wrench ({g} axes, time-stamped), for the
  /// force-mismatch watchdog. Returns false (and ignores it) when not finite.
  bool setEstimatedWrench(const Wrench& w);
  /// The arm side's state (port robot_state): while it is not commandable
  /// the servo holds (TactileServo ROBOT STATE). Until one arrives the arm
  /// counts as commandable (a deployment without the port). Returns false
  /// (and ignores it) when its time is not finite.
  bool setRobotState(const RobotState& r);

  /// One servo cycle at time `now` (s) on the latest features. Returns true
  /// when `out.command` is a command to send (a valid pose was seen and the
  /// core has a command); `status` is the cycle's ServoStatus (WaitingForPose while
  /// no measured pose arrived).
  bool step(double now, const ContactFeatures& features, ServoOutput& out, ServoStatus& status);

  /// Switch phase at the next cycle (see TactileServo::requestPhase).
  bool requestPhase(int index) { return servo_.requestPhase(index); }

  const TactileServo& servo() const { return servo_; }
  double nominalPeriod() const { return nominal_period_; }

 private:
  TactileServo servo_;
  ServoInput in_;
  double nominal_period_ = 0.01;
  bool have_pose_ = false;
  bool first_cycle_ = true;
  double last_time_ = 0.0;
};

}  // namespace tactile
