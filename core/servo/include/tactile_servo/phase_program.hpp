// The servo's phase program (paper Sec. 5, Algorithm 1's phases I-IV): named
// phases and the event-driven transitions between them.
//
// Each evaluation (a cycle with valid features), the current phase's
// transitions are checked in their listed order; the first whose condition has
// held for `for_s` seconds of consecutive evaluations (each counting its dt,
// the first included) fires. Events: contact, edge, point
// (the extractor's contact type), aligned (chosen |Δs| rows, |Δforce| = |Δd_z| /
// c_z, |CoC| below tolerances; optionally low-passed with `filter_s`), contact_lost, force_above, timeout (time in
// the phase), and from the arm's measured pose (observe()): wrist_wound
// (|accumulated yaw about z_s| >= angle), wrist_unwound (the yaw has come back
// by >= angle since the phase was entered) and loop_closed (the caller's loop
// point in {g}, the servo's: where the edge passes the pad's centre, servo.hpp
// WRIST; anchored where a loop_closed transition was first evaluated in
// contact, has gone further than leave_m from the anchor and is back within
// radius_m; the anchor is kept across phases until reset()) and, from the
// measured joints, joint_margin (a joint within angle of its limit). A request (by
// index) is kept until the caller enters it.
// Real-time: nothing here allocates, throws or logs after configure().
#pragma once

#include <array>
#include <limits>
#include <vector>

#include "tactile_servo/servo_params.hpp"

namespace tactile {

/// What the phase program reads besides the features: from the arm's measured
/// pose (the controller's own data, never the simulator's ground truth).
struct ProgramSignals {
  double wrist_yaw = 0.0;       ///< rad: rotation of {s} about z_s accumulated since the servo started
  bool have_point = false;      ///< a contact point this cycle
  double point[3] = {0, 0, 0};  ///< m: the contact point (CoP) in {g}
  /// rad: the measured joint closest to its limit, its distance from it
  /// (kArmJointLimit); +inf while the joints are unknown.
  double joint_margin = std::numeric_limits<double>::infinity();
};

class PhaseProgram {
 public:
  /// Validates names (unique, 1..kPhaseNameLen-1 characters), transitions
  /// (targets, for_s, tolerances, timeouts, forces), the initial phase and
  /// that every phase is reachable from it. Allocates (configuration time).
  ConfigResult configure(const ServoParams& params);
  bool configured() const { return configured_; }

  /// Back to the initial phase, not yet entered; no request pending.
  void reset();
  /// Request a switch (the caller enters it at its next cycle); false for an invalid index.
  bool request(int index);
  /// The requested phase, -1 if none; clearPending() forgets it.
  int pending() const { return pending_; }
  void clearPending() { pending_ = -1; }
  /// The pose-derived signals of this cycle (before evaluate() and enter()).
  void observe(const ProgramSignals& s) { signals_ = s; }
  const ProgramSignals& signals() const { return signals_; }
  /// The accumulated wrist yaw (rad) when the current phase was entered.
  double yawAtEnter() const { return yaw_enter_; }
  /// loop_closed: the anchor (valid once set) and whether the contact has left it.
  bool loopAnchor(double p[3]) const {
    for (int i = 0; i < 3; ++i) p[i] = anchor_[static_cast<std::size_t>(i)];
    return anchor_valid_;
  }
  /// Enters phase `index` at `now` (resets its transitions' counters).
  void enter(int index, double now);
  /// Entered since the last reset()?
  bool entered() const { return entered_; }

  /// Checks the current phase's transitions (see the file comment) for
  /// features `f` and feature error `error` (Eq. 7); true and `target` set
  /// when one fires (the caller enters it). `dt` (s) is this cycle's length,
  /// counted towards `for_s`. `c_z` converts Δd_z to force.
  bool evaluate(const ContactFeatures& f, const Vec6& error, double now, double dt, double c_z, int& target);

  int count() const { return static_cast<int>(phases_.size()); }
  int current() const { return current_; }
  int initial() const { return initial_; }
  double enteredAt() const { return t_enter_; }
  /// Moves the entry time on by dt (s): time that does not count as time in
  /// the phase (the servo holding for the robot: TactileServo ROBOT STATE).
  void delayEntry(double dt) { t_enter_ += dt; }
  int indexOf(const char* name) const;  ///< -1 if unknown
  const std::array<char, kPhaseNameLen>& name(int index) const { return phases_[static_cast<std::size_t>(index)].name; }
  bool requiresContact(int index) const { return phases_[static_cast<std::size_t>(index)].requires_contact; }
  bool resetsIntegrator(int index) const { return phases_[static_cast<std::size_t>(index)].reset_integrator; }
  bool terminal(int index) const { return phases_[static_cast<std::size_t>(index)].terminal; }
  /// P = 0: the phase only follows its feed-forward twist (status FreeMotion).
  bool freeMotion(int index) const { return phases_[static_cast<std::size_t>(index)].free_motion; }

  /// The contact test of the events and of contact loss.
  static bool hasContact(const ContactFeatures& f) {
    return f.contact != ContactType::None && f.status != FeatureStatus::NoContact;
  }

 private:
  struct Transition {
    TransitionEvent on;
    int to;
    double for_s;
    double filter_s;  ///< aligned: low-pass time constant of the tested errors (0 = raw)
    std::array<double, kNumTol> tol;
    double timeout_s, force_n;
    double angle_rad, radius_m, leave_m;
    double held_s;  ///< s the condition has held so far
    bool holding;
    std::array<double, kNumTol> filtered;  ///< aligned: the low-passed signed errors
    bool filtered_valid;
  };
  struct Phase {
    std::array<char, kPhaseNameLen> name{};
    bool requires_contact, reset_integrator, terminal, free_motion;
    int first_transition, num_transitions;
  };
  bool configured_ = false;
  std::vector<Phase> phases_;
  std::vector<Transition> transitions_;
  int initial_ = 0;
  int current_ = 0;
  int pending_ = -1;
  bool entered_ = false;
  double t_enter_ = 0.0;
  ProgramSignals signals_;
  double yaw_enter_ = 0.0;  ///< accumulated yaw when the current phase was entered
  std::array<double, 3> anchor_{};
  bool anchor_valid_ = false, left_anchor_ = false;
};

}  // namespace tactile
