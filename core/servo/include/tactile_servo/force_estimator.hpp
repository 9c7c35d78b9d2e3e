// Force estimate (beyond the paper): Eq. 2's tactile force f, corrected at
// low frequency by the arm's estimated external wrench along z_s.
//
// Why (the WTS's firing threshold hides part of a line load; the arm's
// estimated wrench sees all of it, slowly): docs/design.md.
//
// The estimate, each servo cycle with a wrench sample no older than the stale
// timeout (F its force, {g} axes; z_s the sensor normal in {g}):
//   no tactile contact:  F_lp <- F_lp + a_T (F - F_lp),  a_T = max(1 - exp(-dt / tare_tau_s),
//                        dt / (time of samples so far)): a running mean, then a
//                        first-order low-pass. Every tare_hold_s of such
//                        samples F_lp is snapshot, and the tare T takes the
//                        snapshot two intervals back (samples at least
//                        2 tare_hold_s old) if F_lp moved along z_s by at most
//                        tare_gate_n in each of the two intervals since it;
//                        else T is held (one quiet interval is not enough: the
//                        low-pass lags a ramp, a load rising at 2.6 N/s moves
//                        it by 0.09 N in its first interval; the two-interval
//                        rule leaks at most 0.04 N of such a ramp into T,
//                        one interval 0.23 N). So T is the wrench's zero where
//                        nothing touched the pad: the load that builds up while
//                        the pad presses the object but no taxel fires yet
//                        (below the firing threshold) moves F_lp along z_s and
//                        holds T instead of being taken for the zero (a load
//                        that then stays below the threshold, unchanged, for
//                        three tare_hold_s is taken for it), unless |F_lp| >
//                        tare_max_n: a larger offset is a load, never the
//                        zero (the estimate's offset is a few N; a load on the
//                        housing with no taxel firing must still reach the
//                        force-mismatch watchdog). T = 0 until the
//                        first tare (tared()).
//   tactile contact:     f_w = -(F - T) . z_s (press()): the press on the pad as
//                        the wrench reads it, signed: the contact pushes the
//                        pad back toward the flange, along -z_s, so a press is
//                        f_w > 0 and a wrench of the wrong sign reads f_w < 0
//                        (never folded into |.|: the watchdog sees it)
//                        c   <- c + a_c (min(f_w - f, c_img) - c),  a_c = 1 - exp(-dt / tau_s),
//                        |c| <= max_correction_n
//                        c_img = c + f - th n - image_margin_n (with
//                        image_margin_n > 0, else c_img = +inf): the image's
//                        bound. n the taxels that fire, th their firing
//                        threshold (firing_threshold_n), so f - th n is the
//                        load the image carries above the threshold: how far
//                        it is from reading 0 everywhere (n taxels each just
//                        above th read f = th n: a small dip or slip of the
//                        pad drops them all at once, and the contact is lost
//                        while the true force is on target). The law holds
//                        f + c, so every newton c gains is a newton less on the
//                        taxels: c_img is the correction that leaves that load
//                        at image_margin_n. It binds only while the image is
//                        thin (a sharp edge whose load mostly falls below the
//                        threshold, the load at the pad's end) and then costs
//                        the true force at most image_margin_n above the
//                        wrench's estimate, for as long as it binds.
//   f_hat = f + c (source: fused, with contact), else f (source: tactile: the paper).
// The image keeps the fast part of f_hat (its own bandwidth and noise), the
// wrench only the part slower than tau_s: the wrench's noise is averaged over
// tau_s, and a wrench error larger than max_correction_n cannot move the set
// point by more than that. Without a fresh wrench, c and T are held. The
// filters are exact for held samples: the same at every servo rate. The
// force-mismatch watchdog reads F - T (tare()) against f_hat; with source
// tactile f_hat = f and the wrench is tared all the same (an offset of the
// arm's estimate is not a contradiction of the tactile force). The tare needs
// the pad free of load at the
// start, as any force-sensor tare: a load present from the first sample
// (e.g. on the housing) would be taken for the zero.
// Real-time: step() does not allocate, throw, log or block.
#pragma once

#include <kdl/frames.hpp>

#include "tactile_types/config_result.hpp"

namespace tactile {

struct ForceEstimateParams {
  bool fused = false;              ///< source: tactile (false) | fused (true)
  double tau_s = 1.0;              ///< s, (0, 100]: time constant of the correction c
  double max_correction_n = 2.0;   ///< N, (0, 50]: |c| limit
  double tare_tau_s = 0.5;         ///< s, (0, 100]: time constant of the wrench's zero without contact
  double tare_gate_n = 0.3;        ///< N, (0, 50]: largest step of the tare along z_s (a load building up: held)
  double tare_max_n = 5.0;         ///< N, (0, 50]: largest offset taken for the zero (|T|; a larger one is a load)
  double tare_hold_s = 0.2;        ///< s, (0, 10]: interval of the tare's snapshots (T from samples >= 2 of them old)
  double image_margin_n = 0.0;     ///< N, [0, 50]: load above the firing threshold the correction leaves on the image (c_img); 0 = no image bound
  double firing_threshold_n = 0.2; ///< N, [0, 50]: a taxel's firing threshold (the WTS: 0.2 N, App. A)
};

class ForceEstimator {
 public:
  /// Validate (ranges above); `where` prefixes the key in messages.
  ConfigResult configure(const ForceEstimateParams& p, const char* where = "force_estimate");
  void reset();

  /// One cycle: f the tactile force (N, finite), `contact` tactile contact,
  /// `fresh` a wrench sample no older than the stale timeout, F its force ({g},
  /// N), z_s the sensor normal in {g}, dt > 0, `area` the taxels that fire
  /// (the image's bound; ignored with image_margin_n = 0). Returns f_hat (N).
  double step(double f, bool contact, bool fresh, const KDL::Vector& F, const KDL::Vector& z_s, double dt,
              int area = 0);

  /// The press on the pad along z_s as the wrench F ({g}, N) less the tare T
  /// reads it (N, signed; > 0 for a press: the contact's force on the flange
  /// points along -z_s): f_w above.
  static double press(const KDL::Vector& F, const KDL::Vector& T, const KDL::Vector& z_s) { return -dot(F - T, z_s); }

  double correction() const { return c_; }  ///< c (N)
  /// The correction's demand (N): f_w - f low-passed as c is, without its
  /// bounds (max_correction_n, the image's): the load the taxels miss. Beyond
  /// max_correction_n, the estimate no longer bridges the two sensors
  /// (watchdog.hpp, correction_saturated).
  double demand() const { return demand_; }
  bool tared() const { return tared_; }
  const KDL::Vector& tare() const { return tare_; }  ///< T ({g}, N; zero before the first sample)
  const ForceEstimateParams& params() const { return p_; }

 private:
  ForceEstimateParams p_;
  KDL::Vector lp_ = KDL::Vector::Zero();    // F_lp
  KDL::Vector snap_ = KDL::Vector::Zero();  // F_lp at the last snapshot
  KDL::Vector snap_prev_ = KDL::Vector::Zero();  // F_lp at the snapshot before it
  KDL::Vector tare_ = KDL::Vector::Zero();       // T
  bool quiet_prev_ = false;                      // the interval before the last one was within the gate
  bool have_lp_ = false;
  double lp_t_ = 0.0;  // time of the samples in F_lp
  int n_snap_ = 0;
  bool tared_ = false;
  double since_snap_ = 0.0;
  double c_ = 0.0;
  double demand_ = 0.0;
};

}  // namespace tactile
