// The loop's schedule (Schedule), end rule (EndRule) and the summary's end status (applyEnd).
#include "tactile_sim_runner/loop.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace tactile {
namespace sim {

// ---- Schedule -----------------------------------------------------------------

ConfigResult Schedule::configure(const Rates& r, double duration_s) {
  for (auto [name, v] : {std::pair<const char*, double>{"rates.sim", r.sim}, {"rates.servo", r.servo},
                         {"rates.wts", r.wts}, {"rates.features", r.features}})
    if (!(v > 0.0) || !std::isfinite(v) || v > 1e6) return rangeError(name, v, "must be in (0, 1e6] Hz");
  for (auto [name, v] : {std::pair<const char*, double>{"rates.servo", r.servo}, {"rates.wts", r.wts},
                         {"rates.features", r.features}})
    if (v > r.sim + 1e-9) return rangeError(name, v, "must be <= rates.sim (the physics rate)");
  if (!(duration_s > 0.0) || !std::isfinite(duration_s)) return rangeError("duration", duration_s, "must be > 0 (s)");
  rates_ = r;
  dt_ = 1.0 / r.sim;
  period_ns_ = std::max<int64_t>(1, std::llround(1e9 / r.sim));
  steps_ = std::lround(duration_s * r.sim);
  reset();
  return ConfigResult::success();
}

void Schedule::reset() {
  i_ = 0;
  next_wts_ = next_feat_ = next_servo_ = 0.0;
}

StageFires Schedule::fires() const {
  const double t = time(), eps = 0.25 * dt_;
  StageFires f;
  f.wts = t + eps >= next_wts_;
  f.features = t + eps >= next_feat_;
  f.servo = t + eps >= next_servo_;
  return f;
}

void Schedule::advance() {
  const StageFires f = fires();
  if (f.wts) next_wts_ += 1.0 / rates_.wts;
  if (f.features) next_feat_ += 1.0 / rates_.features;
  if (f.servo) next_servo_ += 1.0 / rates_.servo;
  ++i_;
}

// ---- EndRule ------------------------------------------------------------------

EndReason EndRule::afterServo(ServoStatus st) {
  if (st == ServoStatus::ForceCeiling) return EndReason::ServoForceCeiling;
  if (st == ServoStatus::PhaseTimeout) return EndReason::ServoPhaseTimeout;
  if (st == ServoStatus::ArmStalled) return EndReason::ServoArmStalled;
  if (st == ServoStatus::ForceMismatch) return EndReason::ServoForceMismatch;
  if (st == ServoStatus::SurfaceTooCurved) return EndReason::ServoSurfaceTooCurved;
  if (st == ServoStatus::PhantomContact) return EndReason::ServoPhantomContact;
  if (st == ServoStatus::UnseenLoad) return EndReason::ServoUnseenLoad;
  if (st == ServoStatus::CorrectionSaturated) return EndReason::ServoCorrectionSaturated;
  if (st == ServoStatus::CorrectionDrift) return EndReason::ServoCorrectionDrift;
  // A terminal phase ends the run after one more second of holding.
  if (st == ServoStatus::Done && ++done_cycles_ > done_limit_) return EndReason::DoneHeld;
  return EndReason::None;
}

EndReason EndRule::afterPhysics(SimStatus st) {
  if (fatal(st)) return EndReason::SimFatal;
  if (st == SimStatus::NotConverged) {
    ++unconverged_total_;
    if (++unconverged_cycles_ >= unconverged_limit_) return EndReason::SimFatal;
  } else {
    unconverged_cycles_ = 0;
  }
  if (st == SimStatus::StepRejected) return EndReason::SimRejected;  // time stands still: it never recovers
  if (st != SimStatus::InvalidCommand) {
    invalid_cycles_ = 0;
    return EndReason::None;
  }
  return ++invalid_cycles_ >= invalid_limit_ ? EndReason::SimRejected : EndReason::None;
}

void applyEnd(EndReason reason, SimStatus sim_status, Summary& s) {
  // The servo's fatal statuses: the summary's status and tactile_sim's exit code.
  struct ServoEnd {
    EndReason reason;
    const char* status;
    int exit_code;
  };
  static constexpr ServoEnd kServoEnds[] = {{EndReason::ServoForceCeiling, "servo_force_ceiling", 4},
                                            {EndReason::ServoPhaseTimeout, "servo_phase_timeout", 5},
                                            {EndReason::ServoArmStalled, "servo_arm_stalled", 6},
                                            {EndReason::ServoForceMismatch, "servo_force_mismatch", 7},
                                            {EndReason::ServoSurfaceTooCurved, "servo_surface_too_curved", 8},
                                            {EndReason::ServoPhantomContact, "servo_phantom_contact", 9},
                                            {EndReason::ServoUnseenLoad, "servo_unseen_load", 10},
                                            {EndReason::ServoCorrectionSaturated, "servo_correction_saturated", 11},
                                            {EndReason::ServoCorrectionDrift, "servo_correction_drift", 12}};
  for (const ServoEnd& e : kServoEnds) {
    if (e.reason == reason) {
      s.status = e.status;
      s.exit_code = e.exit_code;
      return;
    }
  }
  if (reason == EndReason::SimFatal || reason == EndReason::SimRejected) {
    s.status = std::string("sim_") + toString(sim_status);
    s.exit_code = 3;
    return;
  }
  s.status = "ok";
  s.exit_code = 0;
}

}  // namespace sim
}  // namespace tactile
