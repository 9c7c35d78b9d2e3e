#include "tactile_servo/watchdog.hpp"
#include "tactile_servo/servo_schema.hpp"

#include <algorithm>
#include <cmath>

#include "servo_config.hpp"

namespace tactile {

using servo_config::err;

ConfigResult ServoWatchdogs::configure(const ServoParams& p) {
  const WatchdogParams& w = p.watchdogs;
  const ConfigResult r = schema::checkRanges(watchdogSchema(), w, servo_config::where(p, "", "watchdogs"));
  if (!r) return r;
  p_ = w;
  reset();
  return ConfigResult::success();
}

void ServoWatchdogs::reset() {
  latched_ = ServoStatus::Ok;
  stall_active_ = false;
  mismatch_s_ = phantom_s_ = unseen_s_ = saturated_s_ = 0.0;
  drift_lp_ = drift_anchor_ = drift_extent_lp_ = drift_extent_anchor_ = 0.0;
  drift_in_s_ = -1.0;
  drift_anchored_ = false;
  drift_phase_ = -1;
  retreat_moved_ = 0.0;
  curved_lp_ = 0.0;
  curved_have_ = false;
  curved_short_ = false;
}

bool ServoWatchdogs::phaseTimeout(double in_phase_s, double max_s) {
  if (max_s > 0.0 && in_phase_s > max_s) return latch(ServoStatus::PhaseTimeout);
  return false;
}

bool ServoWatchdogs::armStalled(const KDL::Frame& T_gs, const Vec6& u_s, bool in_contact, double now) {
  if (!(p_.stall_window_s > 0.0)) return false;
  if (!stall_active_) {
    stall_active_ = true;
    stall_t0_ = now;
    stall_pose0_ = T_gs;
    stall_cmd_t_ = KDL::Vector::Zero();
    stall_cmd_r_ = KDL::Vector::Zero();
  }
  // The commanded increment (Eq. 13, in {s}) summed in {g}.
  const double c = in_contact ? 0.0 : 1.0;  // the contact-constrained directions
  stall_cmd_t_ += T_gs.M * KDL::Vector(u_s(0), u_s(1), c * u_s(2));
  stall_cmd_r_ += T_gs.M * KDL::Vector(c * u_s(3), c * u_s(4), u_s(5));
  if (now - stall_t0_ < p_.stall_window_s - 1e-6) return false;
  const double cmd_t = stall_cmd_t_.Norm(), cmd_r = stall_cmd_r_.Norm();
  const double moved_t = (T_gs.p - stall_pose0_.p).Norm();
  const double moved_r = KDL::diff(stall_pose0_.M, T_gs.M).Norm();
  stall_active_ = false;  // the next cycle starts a new window
  const bool stalled_t = cmd_t >= p_.stall_min_distance && moved_t < p_.stall_min_fraction * cmd_t;
  const bool stalled_r = cmd_r >= p_.stall_min_angle && moved_r < p_.stall_min_fraction * cmd_r;
  return (stalled_t || stalled_r) ? latch(ServoStatus::ArmStalled) : false;
}

namespace {
/// A window of `window_s` (0 = off) over which `bad` must hold: `held` the
/// time it has, advanced by dt or restarted; true once it covers the window.
bool held(bool bad, double window_s, double dt, double& held_s) {
  if (!(window_s > 0.0)) return false;
  held_s = bad ? held_s + dt : 0.0;
  return held_s >= window_s - 1e-6;
}
}  // namespace

ServoStatus ServoWatchdogs::sensorsAgree(const SensorSample& s, double dt) {
  if (!s.fresh || !std::isfinite(s.f) || !std::isfinite(s.f_w) || !(dt > 0.0)) return ServoStatus::Ok;  // held
  // Phantom contact: the taxels carry more than the arm does.
  const bool phantom = s.contact && s.f - s.f_w > std::max(p_.phantom_tolerance_n, p_.phantom_tolerance_rel * s.f);
  if (held(phantom, p_.phantom_window_s, dt, phantom_s_)) return latchedAs(ServoStatus::PhantomContact);
  // Force mismatch: the arm carries more than the taxels and the estimate's bound.
  const double tol = std::max(p_.mismatch_tolerance_n, p_.mismatch_tolerance_rel * s.f_w) + s.hidden_n;
  if (held(s.contact && s.f_w - s.f > tol, p_.mismatch_window_s, dt, mismatch_s_))
    return latchedAs(ServoStatus::ForceMismatch);
  // Unseen load: no taxel fires, the arm carries a load.
  if (held(!s.contact && std::fabs(s.f_w) > p_.unseen_max_n, p_.unseen_window_s, dt, unseen_s_))
    return latchedAs(ServoStatus::UnseenLoad);
  // Correction saturated: counted on the cycles that update it (contact).
  if (s.c_max > 0.0 && s.contact &&
      held(std::fabs(s.c) >= s.c_max + p_.correction_margin_n, p_.correction_window_s, dt, saturated_s_))
    return latchedAs(ServoStatus::CorrectionSaturated);
  if (correctionDrifts(s, dt)) return latchedAs(ServoStatus::CorrectionDrift);
  return ServoStatus::Ok;
}

bool ServoWatchdogs::correctionDrifts(const SensorSample& s, double dt) {
  if (!(p_.drift_max_change_n > 0.0) || !(s.c_max > 0.0)) return false;
  if (!s.contact || !s.regulated || s.phase != drift_phase_) {  // the anchor starts over
    drift_phase_ = s.phase;
    drift_in_s_ = -1.0;
    drift_anchored_ = false;
    return false;
  }
  if (drift_in_s_ < 0.0) {  // the contact began in this phase: the filters start at the samples
    drift_in_s_ = 0.0;
    drift_lp_ = s.c;
    drift_extent_lp_ = s.extent_m;
  }
  drift_in_s_ += dt;
  const double a = 1.0 - std::exp(-dt / p_.drift_tau_s);  // exact for held samples
  drift_lp_ += a * (s.c - drift_lp_);
  drift_extent_lp_ += a * (s.extent_m - drift_extent_lp_);
  const double r = p_.drift_min_extent_ratio;
  const bool same_image = drift_extent_lp_ >= r * drift_extent_anchor_ && r * drift_extent_lp_ <= drift_extent_anchor_;
  if (!drift_anchored_ || !same_image) {
    if (drift_in_s_ < p_.drift_settle_s - 1e-9) return false;
    drift_anchor_ = drift_lp_;
    drift_extent_anchor_ = drift_extent_lp_;
    drift_anchored_ = true;
    return false;
  }
  return std::fabs(drift_lp_ - drift_anchor_) > p_.drift_max_change_n;
}

double ServoWatchdogs::faultRetreat(double max_step) {
  const bool sensor_fault = latched_ == ServoStatus::PhantomContact || latched_ == ServoStatus::ForceMismatch ||
                            latched_ == ServoStatus::UnseenLoad || latched_ == ServoStatus::CorrectionSaturated ||
                            latched_ == ServoStatus::CorrectionDrift;
  if (!sensor_fault || !p_.fault_retreat) return 0.0;
  const double d = std::min(std::max(max_step, 0.0), p_.fault_retreat_m - retreat_moved_);
  if (!(d > 0.0)) return 0.0;
  retreat_moved_ += d;
  return d;
}

bool ServoWatchdogs::surfaceTooCurved(double f_w, double f_d, bool regulated, bool contact, double f,
                                      double extent_m, bool fresh, double dt) {
  if (!(p_.curved_tau_s > 0.0)) return false;
  if (!regulated) {  // a phase that does not hold a force: nothing to compare against
    curved_have_ = curved_short_ = false;
    return false;
  }
  if (!fresh || !std::isfinite(f_w) || !std::isfinite(f_d) || !(dt > 0.0)) return false;  // held
  const double e = f_w - f_d;
  // The filter starts from no excess when a force-holding phase begins: one
  // sample of the wrench's noise at the first contact (0.5 N sigma; 1.24 N
  // above f_d on one seed's first frame) must not stop the run.
  if (!curved_have_) curved_lp_ = 0.0;
  curved_lp_ += (1.0 - std::exp(-dt / p_.curved_tau_s)) * (e - curved_lp_);
  curved_have_ = true;
  curved_short_ =
      !contact || !(extent_m > p_.curved_max_extent_m) || !(f > p_.curved_max_tactile_share * f_w);
  return curved_lp_ > p_.curved_excess_n && curved_short_ ? latch(ServoStatus::SurfaceTooCurved) : false;
}

}  // namespace tactile
