// The servo's phase program (paper Sec. 5, Algorithm 1's phases I-IV): named
// phases and the event-driven transitions between them.
//
// Each evaluation (a cycle with valid features), the current phase's
// transitions are checked in their listed order; the first whose condition has
// held for `for_s` seconds of consecutive evaluations (each counting its dt,
// the first included) fires. Events: contact, edge, point
// (the extractor's contact type), aligned (chosen |Δs| rows, |Δforce| = |Δd_z| /
// c_z, |CoC| below tolerances; optionally low-passed with `filter_s`), contact_lost, force_above, timeout (time in
// the phase). A request (by index) is kept until the caller enters it.
// Real-time: nothing here allocates, throws or logs after configure().
#pragma once

#include <array>
#include <vector>

#include "tactile_servo/servo_params.hpp"

namespace tactile {

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
};

}  // namespace tactile
