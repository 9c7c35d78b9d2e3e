// The slide speed from the contact (beyond the paper): each servo cycle, the
// fastest slide speed that keeps the true force within a user's error budget,
// picked from what the servo measures. The servo (servo.hpp) passes the slide
// axis's PI rate through slide() (at most speed()) in the phases its
// program's speed_law block lists (SpeedLawConfig, servo_params.hpp);
// SpeedLawFilter below turns the raw signals of a cycle into SpeedLawInput.
//
// Inputs (SpeedLawInput, one cycle):
//   force_error_n   e = f_d - f_hat (N) and force_error_rate (N/s): the error
//                   predicted horizon_s ahead, |e + horizon_s de/dt|, against
//                   the budget, past a dead band d (the estimate's own noise
//                   must not hold the slide back):
//                   a_f = 1 - max(0, |e + h de/dt| - d) / (force_budget_n - d);
//   angle_rate      the edge angle's rate (rad/s, alpha_z of Eq. B.5 per
//                   second): a bend arriving; a_w = 1 - |w| / angle_rate_ref;
//   curvature       of the edge line along the pad (1/m; the contact line's
//                   points, tactile_features/edge_line.hpp): a wave or a dip
//                   under the pad before the force shows it; a_k = 1 - |k| / curvature_ref
//                   (curvature_ref: the tightest curvature the program follows,
//                   1 / 0.182 m for bent_bar_fused, params/scenes/curved/README.md);
//   extent_m        the image's extent along the edge (sqrt(12 lambda1)):
//                   a_e = (extent - extent_min) / (extent_full - extent_min);
//   wrench_excess_n the arm's wrench along z_s less the force the taxels
//                   report (f_hat, or Eq. 2's tactile force f: SpeedLawConfig's
//                   excess_against, servo_params.hpp) (N): load the taxels do
//                   not carry (the pad's ends, its housing), past a dead band
//                   d_x (against f, the load the firing threshold always hides):
//                   a_x = 1 - max(0, excess - d_x - k_x e) / (excess_ref - d_x),
//                   e the image's extent if it is at most excess_short_max_m,
//                   else 0: a short image (a convex bend under the rigid pad)
//                   hides more of its load below the threshold than a line
//                   along the pad or two spots at its ends (a bridged trough)
//                   do; k_x = excess_deadband_per_m.
// Each a_i is clamped to [0, 1]; the target speed is
//   v* = max(v_min, v_max min_i a_i)
// (the slowest input decides: the fastest speed every input allows). The
// output follows v* down at once (slow down before the bend, not after the
// force left the band) and up at most at accel_mps2 (speed up only as fast as
// the loop settles). v_max is the safety limit (safety.max_trans_speed).
// A non-finite input holds v_min and reports InvalidInput.
//
// The slide (slide(): the rate the servo commands along the slide axis, from
// the phase's pull, the CoP_x term of Eq. 13):
//   * capped at the speed above, +-speed();
//   * driven: at least drive_fraction speed() in the pull's direction. Over
//     a crest the image shrinks to a spot that travels back along the pad
//     towards the CoP_x set point, the pull fades with it, and the pad
//     crawls at a third of what the law allows; the drive carries it over;
//   * guarded: while the taxels miss more than guard_excess_n of the wrench
//     (wrench_excess_n, low-passed), the load is leaving them (the pad tips
//     off a crest into a trough it will bridge): no drive, and the slide's
//     speed rises at most at guard_accel_mps2, so the pull's jump as two
//     spots at the pad's ends appear does not take the pad into the trough;
//   * crawling: once the excess has held the target at v_min (a_x = 0) for
//     crawl_after_s, the pad bridges the trough steadily (its housing or
//     ends carry the load, the true force in its band): the excess input
//     allows crawl_mps instead of stopping the slide, until it allows more
//     than crawl_mps (an excess hovering about excess_ref_n keeps the crawl;
//     before the crawl, any excess below it starts the wait afresh).
// Real-time: step() and slide() do not allocate, throw, log or block.
#pragma once

#include "tactile_types/config_result.hpp"

namespace tactile {

struct SpeedLawParams {
  double v_max = 0.05;            ///< m/s, (0, 1]: the safety limit
  double v_min = 0.002;           ///< m/s, [0, v_max]: the slowest slide while the law allows none
  double accel_mps2 = 0.05;       ///< m/s^2, (0, 10]: the largest rise of the speed
  double force_budget_n = 0.5;    ///< N, (0, 50]: the user's error budget for the true force
  double force_deadband_n = 0.0;  ///< N, [0, force_budget_n): the predicted error that does not slow the slide
  double horizon_s = 0.2;         ///< s, [0, 10]: how far ahead the force error is predicted
  double angle_rate_ref = 0.5;    ///< rad/s, (0, 100]: the edge angle's rate that stops the slide
  double curvature_ref = 5.5;     ///< 1/m, (0, 1e4]: the edge line's curvature that stops the slide
  double extent_full_m = 0.0476;  ///< m, (extent_min_m, 1]: the image's extent at full speed (the pad)
  double extent_min_m = 0.0119;   ///< m, [0, 1): the extent at which the slide stops (a quarter of the pad)
  double excess_ref_n = 1.2;      ///< N, (0, 1e4]: the wrench's excess that stops the slide
  double excess_deadband_n = 0.0; ///< N, [0, excess_ref_n): the excess that does not slow the slide
  double excess_deadband_per_m = 0.0; ///< N/m, [0, 1e4]: the dead band's growth with the extent of a short image
  double excess_short_max_m = 0.04;   ///< m, [0, 1]: the longest image that grows it (a longer one: a line along the
                                      ///< pad or two spots at its ends)
  double drive_fraction = 0.0;    ///< [0, 1]: the slide's least share of speed() in the pull's direction (0: cap only)
  double guard_excess_n = 1e4;    ///< N, (0, 1e4]: the excess above which the slide is not driven and rises slowly
  double guard_accel_mps2 = 10.0; ///< m/s^2, (0, 10]: the slide's largest rise while guarded
  double crawl_mps = 0.0;         ///< m/s, [0, v_max]: the slide the excess allows once it has stopped it a while
                                  ///< (0: v_min)
  double crawl_after_s = 0.2;     ///< s, [0, 10]: how long the excess must have stopped the slide first
};

struct SpeedLawInput {
  double force_error_n = 0.0;      ///< f_d - f_hat (N)
  double force_error_rate = 0.0;   ///< its rate (N/s)
  double angle_rate = 0.0;         ///< d alpha_z / dt (rad/s)
  double curvature = 0.0;          ///< of the edge line along the pad (1/m)
  double extent_m = 0.0476;        ///< the image's extent along the edge (m)
  double wrench_excess_n = 0.0;    ///< wrench along z_s less the taxels' force (N)
};

enum class SpeedLawStatus : unsigned char {
  Full = 0,          ///< v* = v_max
  Limited = 1,       ///< an input holds the speed below v_max
  InvalidInput = 2,  ///< a non-finite input or dt: v_min
  NotConfigured = 3
};

/// Which input decided v* (the smallest a_i), for logs and plots.
enum class SpeedLimiter : unsigned char { None = 0, Force, AngleRate, Curvature, Extent, WrenchExcess };

/// The raw signals of one cycle, as the servo has them.
struct SpeedLawSignals {
  double force_error_n = 0.0;   ///< f_d - f_hat (N)
  double alpha_z = 0.0;         ///< rad (Eq. B.5)
  bool alpha_defined = false;   ///< alpha_z is a measurement (ContactFeatures::alpha_defined)
  double curvature = 0.0;       ///< 1/m (ContactFeatures::curvature)
  double extent_m = 0.0;        ///< sqrt(12 lambda1) (m)
  double wrench_excess_n = 0.0; ///< wrench along z_s less f_hat or f (N); 0 without a fresh wrench
};

/// Low-passes the force error, the curvature and the wrench's excess with
/// tau, and differentiates the low-passed force error and edge angle (rates
/// low-passed with tau as well); alpha_z's step is taken modulo pi (an edge
/// angle is defined modulo pi) and counts only while alpha is defined. The
/// extent is passed through (its drop is the warning). Allocation-free.
class SpeedLawFilter {
 public:
  /// `tau_s` low-passes the force error, its rate, the angle's rate and the
  /// curvature; `excess_tau_s` the wrench's excess (0: tau_s).
  void configure(double tau_s, double excess_tau_s = 0.0) {
    tau_ = tau_s;
    excess_tau_ = excess_tau_s > 0.0 ? excess_tau_s : tau_s;
    reset();
  }
  void reset() { init_ = false; }
  /// dt > 0 and finite signals; otherwise the state is kept and `out` holds non-finite values.
  void step(const SpeedLawSignals& s, double dt, SpeedLawInput& out);

 private:
  double tau_ = 0.05;
  double excess_tau_ = 0.05;
  bool init_ = false;
  double ef_ = 0, ef_rate_ = 0, alpha_prev_ = 0, alpha_rate_ = 0, kappa_ = 0, excess_ = 0;
  bool alpha_prev_ok_ = false;
};

class SpeedLaw {
 public:
  /// Validate (ranges above); `where` prefixes the key in messages.
  ConfigResult configure(const SpeedLawParams& p, const char* where = "speed_law");
  /// The speed back to v_min (a new contact: start slow).
  void reset();
  /// One cycle of dt > 0 s: speed() and limiter() updated.
  SpeedLawStatus step(const SpeedLawInput& in, double dt);
  /// The slide rate (m/s, signed) for the phase's pull `pull_mps` along the
  /// slide axis, after step() of the same cycle (header: capped, driven,
  /// guarded). A non-finite pull or dt gives 0.
  double slide(double pull_mps, double dt);
  bool guarded() const { return guarded_; }
  double speed() const { return v_; }          ///< m/s
  double target() const { return target_; }    ///< v* (m/s)
  SpeedLimiter limiter() const { return limiter_; }
  const SpeedLawParams& params() const { return p_; }

 private:
  SpeedLawParams p_;
  bool configured_ = false;
  double v_ = 0.0;
  double target_ = 0.0;
  /// The excess has held a_x at 0 for crawl_after_s (header: crawling).
  bool crawling() const { return stopped_s_ >= p_.crawl_after_s - 1e-9; }
  double stopped_s_ = 0.0;   // how long the excess has held a_x at 0
  double slide_prev_ = 0.0;  // |slide()| of the last cycle (m/s)
  bool guarded_ = false;
  SpeedLimiter limiter_ = SpeedLimiter::None;
};

}  // namespace tactile
