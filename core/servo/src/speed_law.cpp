#include "tactile_servo/speed_law.hpp"
#include "tactile_servo/servo_schema.hpp"
#include "tactile_types/conventions.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace tactile {

namespace {
double unit(double a) { return std::clamp(a, 0.0, 1.0); }
}  // namespace

ConfigResult SpeedLaw::configure(const SpeedLawParams& p, const char* where) {
  configured_ = false;
  const ConfigResult r = schema::checkRanges(speedLawSchema(), p, where);
  if (!r) return r;
  p_ = p;
  configured_ = true;
  reset();
  return ConfigResult::success();
}

void SpeedLaw::reset() {
  v_ = p_.v_min;
  target_ = p_.v_min;
  limiter_ = SpeedLimiter::None;
  stopped_s_ = 0.0;
  slide_prev_ = p_.v_min;
  guarded_ = false;
}

SpeedLawStatus SpeedLaw::step(const SpeedLawInput& in, double dt) {
  if (!configured_) return SpeedLawStatus::NotConfigured;
  const bool finite = std::isfinite(in.force_error_n) && std::isfinite(in.force_error_rate) &&
                      std::isfinite(in.angle_rate) && std::isfinite(in.curvature) && std::isfinite(in.extent_m) &&
                      std::isfinite(in.wrench_excess_n) && std::isfinite(dt) && dt > 0.0;
  if (!finite) {
    v_ = target_ = p_.v_min;
    limiter_ = SpeedLimiter::None;
    stopped_s_ = 0.0;
    guarded_ = true;  // no drive on what is not measured
    return SpeedLawStatus::InvalidInput;
  }
  // The wrench excess's dead band: grown by a short image's extent (header).
  const double short_extent = in.extent_m > p_.excess_short_max_m ? 0.0 : std::max(0.0, in.extent_m);
  const double excess_deadband = p_.excess_deadband_n + p_.excess_deadband_per_m * short_extent;
  // One admissible fraction of v_max per input (header); the smallest decides.
  double a[5] = {
      unit(1.0 - std::max(0.0, std::fabs(in.force_error_n + p_.horizon_s * in.force_error_rate) - p_.force_deadband_n) /
                     (p_.force_budget_n - p_.force_deadband_n)),
      unit(1.0 - std::fabs(in.angle_rate) / p_.angle_rate_ref),
      unit(1.0 - std::fabs(in.curvature) / p_.curvature_ref),
      unit((in.extent_m - p_.extent_min_m) / (p_.extent_full_m - p_.extent_min_m)),
      unit(1.0 - std::max(0.0, in.wrench_excess_n - excess_deadband) / (p_.excess_ref_n - p_.excess_deadband_n))};
  // The crawl (header): the excess has stopped the slide for crawl_after_s;
  // once crawling, only an excess that allows more than the crawl ends it.
  if (a[4] <= 0.0)
    stopped_s_ += dt;
  else if (!crawling() || p_.v_max * a[4] >= p_.crawl_mps)
    stopped_s_ = 0.0;
  if (p_.crawl_mps > 0.0 && crawling()) a[4] = std::max(a[4], p_.crawl_mps / p_.v_max);
  guarded_ = in.wrench_excess_n > p_.guard_excess_n;
  int k = 0;
  for (int i = 1; i < 5; ++i)
    if (a[i] < a[k]) k = i;
  limiter_ = a[k] < 1.0 ? static_cast<SpeedLimiter>(k + 1) : SpeedLimiter::None;
  target_ = std::max(p_.v_min, p_.v_max * a[k]);
  // Down at once, up at most accel_mps2.
  v_ = target_ <= v_ ? target_ : std::min(target_, v_ + p_.accel_mps2 * dt);
  return target_ < p_.v_max ? SpeedLawStatus::Limited : SpeedLawStatus::Full;
}

double SpeedLaw::slide(double pull_mps, double dt) {
  if (!configured_ || !std::isfinite(pull_mps) || !std::isfinite(dt) || !(dt > 0.0)) {
    slide_prev_ = 0.0;
    return 0.0;
  }
  double v = std::clamp(pull_mps, -v_, v_);
  const double drive = p_.drive_fraction * v_;
  if (!guarded_ && pull_mps != 0.0 && std::fabs(v) < drive) v = std::copysign(drive, pull_mps);
  if (guarded_) {
    const double lim = slide_prev_ + p_.guard_accel_mps2 * dt;
    v = std::clamp(v, -lim, lim);
  }
  slide_prev_ = std::fabs(v);
  return v;
}

void SpeedLawFilter::step(const SpeedLawSignals& s, double dt, SpeedLawInput& out) {
  const bool ok = std::isfinite(dt) && dt > 0.0 && std::isfinite(s.force_error_n) && std::isfinite(s.alpha_z) &&
                  std::isfinite(s.curvature) && std::isfinite(s.extent_m) && std::isfinite(s.wrench_excess_n);
  if (!ok) {
    out.force_error_n = std::numeric_limits<double>::quiet_NaN();  // SpeedLaw::step: InvalidInput, v_min
    return;
  }
  if (!init_) {
    ef_ = s.force_error_n;
    ef_rate_ = alpha_rate_ = 0.0;
    kappa_ = s.curvature;
    excess_ = s.wrench_excess_n;
    alpha_prev_ = s.alpha_z;
    alpha_prev_ok_ = s.alpha_defined;
    init_ = true;
  } else {
    const double a = dt / (tau_ + dt);  // first-order low-pass, time constant tau
    const double ef_prev = ef_;
    ef_ += a * (s.force_error_n - ef_);
    ef_rate_ += a * ((ef_ - ef_prev) / dt - ef_rate_);
    kappa_ += a * (s.curvature - kappa_);
    excess_ += dt / (excess_tau_ + dt) * (s.wrench_excess_n - excess_);
    double w = 0.0;
    if (s.alpha_defined && alpha_prev_ok_) w = std::remainder(s.alpha_z - alpha_prev_, kPi) / dt;  // modulo pi
    alpha_rate_ += a * (w - alpha_rate_);
    if (s.alpha_defined) alpha_prev_ = s.alpha_z;
    alpha_prev_ok_ = s.alpha_defined;
  }
  out.force_error_n = ef_;
  out.force_error_rate = ef_rate_;
  out.angle_rate = alpha_rate_;
  out.curvature = kappa_;
  out.extent_m = s.extent_m;
  out.wrench_excess_n = excess_;
}

}  // namespace tactile
