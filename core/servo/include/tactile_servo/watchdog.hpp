// The servo's watchdogs (beyond the paper): conditions that must end a run
// with a named status instead of passing silently. Each one latches (the
// servo then holds its command) until reset() or an explicit phase request.
//
//  * phase timeout: longer in a phase than its max_duration_s (a phase that
//    never ends; distinct from the `timeout` transition, a normal event);
//  * arm stalled: over a window of commanded motion (the increments u_s of
//    Eq. 13, summed in {g}), the measured sensor origin {g}T{e} {e}T{s} moved
//    less than min_fraction of the commanded translation, or turned less than
//    min_fraction of the commanded rotation, while that command was at least
//    min_distance / min_angle (an arm or simulator that does not follow);
//  * the two sensors against each other (sensorsAgree), with Eq. 2's
//    tactile force f = d_z / C_z (never the fused estimate f_hat = f + c,
//    whose correction moves toward the wrench and would hide the
//    contradiction) and f_w = -(F - T) . z_s, the press the arm's estimated
//    wrench (less its zero T, force_estimator.hpp) reads along z_s, signed: a
//    wrench of the wrong sign (the KRC's estExtTcpFT against the convention
//    fri.yaml states, docs/bringup.md) reads a press as f_w < 0 and is a
//    phantom contact at the first touch, never folded into |f_w|; a wrench
//    older than `stale_s` is not used (the windows hold). Each contradiction
//    has its own status and window:
//      phantom contact     with tactile contact, f - f_w > max(tolerance_n,
//                          tolerance_rel f) for phantom.window_s: the taxels
//                          read a load the arm does not carry (a stuck or
//                          pressed region, the cable or the cover, a
//                          calibration too high). Its window is short (0.05 s
//                          by default): the arm must not chase such a contact
//                          by more than a few millimetres;
//      force mismatch      with tactile contact, f_w - f > max(tolerance_n,
//                          tolerance_rel f_w) + hidden_n for window_s, hidden_n
//                          the load the fused estimate may place below the
//                          firing threshold (its max_correction_n; 0 with
//                          source tactile): a pad much softer than calibrated,
//                          the housing carrying part of the load;
//      unseen load         without tactile contact, |f_w| > unseen.max_n for
//                          unseen.window_s: a load no taxel sees;
//      correction saturated  source fused: the correction's demand (f_w - f
//                          low-passed as c is, without c's bounds) at or
//                          beyond max_correction_n + margin_n for window_s
//                          on cycles that update it (tactile contact, a
//                          fresh wrench): a correction held at its limit, or
//                          at the image's bound below it, is a disagreement
//                          the estimate cannot bridge, not a steady state;
//      correction drift    source fused, off unless correction_drift.max_change_n
//                          > 0: in a phase that holds a force set point, the
//                          demand low-passed with tau_s moves more than
//                          max_change_n from its value settle_s after the
//                          contact began in the phase (the anchor; taken
//                          anew when the image's extent, low-passed as the
//                          demand, leaves [min_extent_ratio, 1 /
//                          min_extent_ratio] times its value then: the pad
//                          running off the edge's end changes the load it
//                          misses, a drift does not). Where the load the pad
//                          misses is stationary (a straight edge at a constant
//                          set point), a moving correction is a wrench that
//                          drifts, which the estimate would otherwise carry
//                          into the true force (a slow drift follows the
//                          correction below its bound: correction_saturated
//                          alone comes only when the drift reaches it).
//    On one of these, the servo holds, or retreats along -z_s by
//    retreat_m at the step limit and then holds (on_fault).
//    With the paper's tactile-only source and no wrench at all (the port
//    unconnected), none of these can run: what bounds the arm then is the
//    tactile force ceiling, the step limits, the workspace box, the phase
//    timeouts and the arm-stall watchdog (docs/design.md).
//  * surface too curved (off unless surface_too_curved.tau_s > 0): in a phase
//    that holds a force set point f_d, the arm's wrench along z_s (less its
//    zero), low-passed with tau_s (against its noise; the filter starts from
//    no excess as the phase begins), exceeds f_d by more than
//    excess_n while the image spans at most max_extent_m along its principal
//    axis (sqrt(12 lambda1): the length of a uniform line), or its taxels
//    carry at most max_tactile_share of the wrench (Eq. 2's f <= share f_w:
//    a trough that the pad bridges fires a few taxels at both of its ends, a
//    long image of little load), or no taxel fires.
//    The law holds the force the taxels see (or f_hat) at f_d; a wrench well
//    above it with the image shrunk to part of the pad is load the taxels do
//    not carry: the surface curves more tightly than the rigid pad reaches
//    (47.6 mm), and its ends or housing take the load. Raised before the
//    force-mismatch window (which needs a 4 N contradiction for 0.5 s) and
//    before the true force reaches f_d + excess_n + the low-pass's lag.
// Real-time: nothing here allocates, throws or logs after configure().
#pragma once

#include <kdl/frames.hpp>

#include "tactile_servo/servo_params.hpp"

namespace tactile {

class ServoWatchdogs {
 public:
  /// Validates the watchdog parameters (names the key and the valid range).
  ConfigResult configure(const ServoParams& params);
  const WatchdogParams& params() const { return p_; }

  /// No latch, windows restarted.
  void reset();
  /// Clears the latch (an explicit phase request) and restarts the windows.
  void clear() { reset(); }
  /// The latched status, ServoStatus::Ok when none.
  ServoStatus latched() const { return latched_; }

  /// Phase timeout: `in_phase_s` seconds in a phase with limit `max_s` (0 = none).
  bool phaseTimeout(double in_phase_s, double max_s);

  /// Arm stall, on a cycle that commanded the increment `u_s` ({s}, Eq. 13)
  /// from the measured sensor pose `T_gs_meas` at time `now`. In contact
  /// (`in_contact`), the directions the contact constrains (App. C's natural
  /// constraints: z_s translation, rotations about x_s and y_s) are left out:
  /// pressing into an object or tilting against it is force control through
  /// the impedance, where the pose lags the command by design (5 N at
  /// 1000 N/m is 5 mm), and so is a tangential command held by pad friction
  /// up to mu N / k; only x_s, y_s translation and z_s rotation are checked.
  bool armStalled(const KDL::Frame& T_gs_meas, const Vec6& u_s, bool in_contact, double now);
  /// A cycle without commanded motion: the stall window starts over.
  void restartStall() { stall_active_ = false; }

  /// What sensorsAgree() compares on one cycle.
  struct SensorSample {
    double f = 0.0;         ///< N, Eq. 2's tactile force (raw: not the fused estimate)
    bool contact = false;   ///< tactile contact
    bool fresh = false;     ///< a wrench sample no older than the stale timeout
    double f_w = 0.0;       ///< N, -(F - T) . z_s: the press the wrench less its zero reads (signed)
    double hidden_n = 0.0;  ///< N, the load the estimate may carry below the threshold (0: source tactile)
    double c = 0.0;         ///< N, the fused estimate's demand (ForceEstimator::demand(): c unbounded)
    double c_max = 0.0;     ///< N, its limit; 0: source tactile (not checked)
    int phase = -1;         ///< the phase (a change restarts the drift's anchor)
    bool regulated = false; ///< the phase holds a force set point (requires contact, f_d > 0)
    double extent_m = 0.0;  ///< the image's extent along its principal axis (m)
  };
  /// The two sensors against each other on a cycle of `dt` s (header):
  /// latches and returns PhantomContact, ForceMismatch, UnseenLoad,
  /// CorrectionSaturated or CorrectionDrift; ServoStatus::Ok while they agree.
  ServoStatus sensorsAgree(const SensorSample& s, double dt);
  /// Once sensorsAgree() latched and on_fault is retreat: this cycle's move
  /// along -z_s (m, at most `max_step`), 0 once retreat_m was made (hold).
  double faultRetreat(double max_step);

  /// Surface too curved on a cycle of `dt` s: `f_w` the wrench's force along
  /// z_s less its zero (N), `f_d` the phase's force set point (N), `regulated`
  /// the phase holds it (requires contact, f_d > 0; else the filter restarts),
  /// `contact` tactile contact, `f` Eq. 2's tactile force (N), `extent_m` the image's extent along its
  /// principal axis, `fresh` a wrench no older than the stale timeout (else
  /// the filter is held).
  bool surfaceTooCurved(double f_w, double f_d, bool regulated, bool contact, double f, double extent_m,
                        bool fresh, double dt);
  /// The first reaction's excess (N): the low-passed f_w - f_d while the image
  /// is short and it is above surface_too_curved.lift_n, else 0.
  double curvedLift() const {
    return p_.curved_lift_n > 0.0 && curved_have_ && curved_short_ && curved_lp_ > p_.curved_lift_n ? curved_lp_ : 0.0;
  }

 private:
  bool latch(ServoStatus s) {
    latched_ = s;
    return true;
  }
  ServoStatus latchedAs(ServoStatus s) {
    latched_ = s;
    return s;
  }
  WatchdogParams p_;
  ServoStatus latched_ = ServoStatus::Ok;
  bool stall_active_ = false;
  double stall_t0_ = 0.0;
  KDL::Frame stall_pose0_;
  KDL::Vector stall_cmd_t_, stall_cmd_r_;
  double mismatch_s_ = 0.0;
  double phantom_s_ = 0.0;
  double unseen_s_ = 0.0;
  double saturated_s_ = 0.0;
  // Correction drift: the low-passed demand, its anchor, the time in contact
  // in the phase, the phase it counts for.
  double drift_lp_ = 0.0;
  double drift_anchor_ = 0.0;
  double drift_extent_lp_ = 0.0;
  double drift_extent_anchor_ = 0.0;
  double drift_in_s_ = -1.0;  // < 0: no contact in a regulated phase yet
  bool drift_anchored_ = false;
  int drift_phase_ = -1;
  bool correctionDrifts(const SensorSample& s, double dt);
  double retreat_moved_ = 0.0;
  double curved_lp_ = 0.0;  // low-passed f_w - f_d
  bool curved_have_ = false;
  bool curved_short_ = false;  // the image short (or gone) on the last cycle
};

}  // namespace tactile
