#include "tactile_servo/force_estimator.hpp"
#include "tactile_servo/servo_schema.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace tactile {

ConfigResult ForceEstimator::configure(const ForceEstimateParams& p, const char* where) {
  const ConfigResult r = schema::checkRanges(forceEstimateSchema(), p, where);
  if (!r) return r;
  p_ = p;
  reset();
  return ConfigResult::success();
}

void ForceEstimator::reset() {
  lp_ = snap_ = snap_prev_ = tare_ = KDL::Vector::Zero();
  quiet_prev_ = false;
  have_lp_ = false;
  lp_t_ = 0.0;
  n_snap_ = 0;
  tared_ = false;
  since_snap_ = 0.0;
  c_ = 0.0;
  demand_ = 0.0;
}

double ForceEstimator::step(double f, bool contact, bool fresh, const KDL::Vector& F, const KDL::Vector& z_s,
                            double dt, int area) {
  const bool usable = fresh && std::isfinite(F.x()) && std::isfinite(F.y()) && std::isfinite(F.z()) &&
                      std::isfinite(dt) && dt > 0.0;
  if (!contact) {
    if (usable) {  // the wrench's zero: nothing the taxels see touches the pad
      // A running mean until tare_tau_s of samples, then the first-order low-pass.
      lp_t_ += dt;
      lp_ = have_lp_ ? lp_ + (F - lp_) * std::max(1.0 - std::exp(-dt / p_.tare_tau_s), dt / lp_t_) : F;
      have_lp_ = true;
      since_snap_ += dt;
      if (since_snap_ >= p_.tare_hold_s - 1e-9) {
        // T takes the snapshot two intervals back (samples at least
        // 2 tare_hold_s old) when the wrench moved along z_s by at most
        // tare_gate_n in each of the two intervals since: a load building up
        // shows in the second interval even where the low-pass's lag hides
        // it in the first. An offset larger than tare_max_n is a load, not a
        // zero: never tared (the watchdog's no-contact check must still see it).
        const bool quiet = n_snap_ > 0 && std::fabs(dot(lp_ - snap_, z_s)) <= p_.tare_gate_n;
        if (quiet && quiet_prev_ && snap_prev_.Norm() <= p_.tare_max_n) {
          tare_ = snap_prev_;
          tared_ = true;
        }
        quiet_prev_ = quiet;
        snap_prev_ = snap_;
        snap_ = lp_;
        ++n_snap_;
        since_snap_ = 0.0;
      }
    }
    return f;
  }
  // Source tactile (the paper): Eq. 2's force; the tare above still gives the
  // force-mismatch watchdog the wrench less its zero.
  if (!p_.fused) return f;
  if (usable && std::isfinite(f)) {
    const double f_w = press(F, tare_, z_s);
    const double a = 1.0 - std::exp(-dt / p_.tau_s);  // exact for held samples
    double target = f_w - f;
    demand_ += a * (target - demand_);
    // The image's bound (header): the correction that leaves the peak taxel
    // at min_peak_taxel_n once the law has moved f by the change of c.
    if (p_.image_margin_n > 0.0)
      target = std::max(std::min(target, c_ + f - p_.firing_threshold_n * static_cast<double>(area) - p_.image_margin_n),
                        target - p_.image_margin_n);
    c_ = std::clamp(c_ + a * (target - c_), -p_.max_correction_n, p_.max_correction_n);
  }
  return f + c_;
}

}  // namespace tactile
