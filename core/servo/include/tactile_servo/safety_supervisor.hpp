// The servo's safety supervisor (beyond the paper; see servo.hpp, SAFETY):
//
//  * speed limits: every increment's translation and rotation norms at most
//    max_trans_speed * dt, max_rot_speed * dt (m/s, rad/s), direction kept;
//  * workspace box on the commanded flange position {g}p{e}; from a pose
//    already outside it only motion back towards it (no jumps onto it);
//  * force ceiling: features.force > force_ceiling latches; retreat along
//    -z_s by ceiling_retreat at the step limit, then hold; until cleared;
//  * stale data: features older (or newer) than stale_timeout, or with an
//    unusable status, hold; so is a frozen image (frozenImage: new frames
//    that repeat the last image while the arm moves);
//  * contact loss in a phase that needs contact: hold, back off (along -z_s
//    by backoff_distance) or search (along +z_s at search_speed, at most
//    search_max_distance), each at the step limit.
// Real-time: nothing here allocates, throws or logs after configure().
#pragma once

#include "tactile_servo/servo_params.hpp"

namespace tactile {

class SafetySupervisor {
 public:
  /// Validates the safety limits (names the key and the valid range).
  ConfigResult configure(const ServoParams& params);
  bool configured() const { return configured_; }
  const SafetyParams& params() const { return p_; }

  /// Ceiling latch off, recovery distances zero.
  void reset();
  /// Clears the force-ceiling latch (an explicit phase request).
  void clearCeiling() { ceiling_latched_ = false; }

  /// NaN/Inf in any feature field used by the servo?
  static bool featuresFinite(const ContactFeatures& f);

  /// Force ceiling, latched: true while latched (the servo commands nothing
  /// else); `retreat` (m, >= 0) is this cycle's move along -z_s (at most
  /// max_trans_speed * dt), 0 once the full ceiling_retreat was made (hold).
  /// `finite`: featuresFinite(f).
  bool forceCeiling(const ContactFeatures& f, bool finite, double dt, double& retreat);
  bool ceilingLatched() const { return ceiling_latched_; }

  /// Unusable status, or time stamp further than stale_timeout from `now`.
  bool stale(const ContactFeatures& f, double now) const;

  /// A frozen image (SafetyParams::frozen_image_travel; false when off): in
  /// contact, f repeats the image of the last frame that changed it for at
  /// least frozen_image_s (`now`, s) while the measured flange position
  /// `flange` ({g}, m) moved more than frozen_image_travel from where that
  /// image arrived. Latched until a frame brings a different image or the
  /// contact ends. Call once per cycle with the cycle's features.
  bool frozenImage(const ContactFeatures& f, const KDL::Vector& flange, double now);

  /// Contact lost in a phase that needs it: this cycle's recovery move along
  /// z_s (m; < 0 backoff, > 0 search), 0 = hold (mode hold, or distance done).
  double contactLoss(double dt);
  /// Contact present (or a new phase): the next loss starts a new recovery.
  void resetRecovery() { recovery_moved_ = 0.0; }

  /// Scales u's translation and rotation to the speed limits over `dt` (s);
  /// true if it did.
  bool limitStep(Vec6& u, double dt) const;
  /// The largest translation (m) / rotation (rad) of a cycle of `dt` s.
  /// dt is counted at most max_step_dt; <= 0 or NaN gives 0.
  double maxTransStep(double dt) const { return p_.max_trans_speed * stepDt(dt); }
  double maxRotStep(double dt) const { return p_.max_rot_speed * stepDt(dt); }
  /// Clips T_ge's position to the workspace box widened to include `from`
  /// (the pose the increment started at); true if it did.
  bool clipWorkspace(const KDL::Vector& from, KDL::Frame& T_ge) const;

 private:
  double stepDt(double dt) const { return dt > 0.0 ? (dt < p_.max_step_dt ? dt : p_.max_step_dt) : 0.0; }
  bool configured_ = false;
  SafetyParams p_;
  bool ceiling_latched_ = false;
  double ceiling_moved_ = 0.0;
  double recovery_moved_ = 0.0;
  // frozenImage(): the image of the last frame that changed it, where and when it arrived.
  struct Image {
    double force = 0.0, cop_x = 0.0, cop_y = 0.0, coc_x = 0.0, coc_y = 0.0, lambda1 = 0.0, lambda2 = 0.0,
           max_taxel = 0.0;
    uint16_t area = 0;
    bool operator==(const Image& o) const;
  };
  bool have_image_ = false;
  bool frozen_ = false;
  uint32_t image_seq_ = 0;
  Image image_;
  KDL::Vector image_at_ = KDL::Vector::Zero();
  double image_since_ = 0.0;
};

}  // namespace tactile
