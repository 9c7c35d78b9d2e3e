// The servo's control law (paper Sec. 4, Eq. 7-15), per phase of a program:
//
//   Δs       = s_d - J^-1(β) s                          (Eq. 7, 8; β from the contact type, Eq. 5)
//   Δs_task  = P Δs                                     (Eq. 9, 10)
//   u_s      = (S clamp(K_P Δs_task + K_I ∫Δs_task dt) + v_ff) dt   (Eq. 13, PI per axis, as a rate)
//   {g}T{e}' = ({g}T{e} {e}T{s} (+) R_gs u_s) {e}T{s}^-1  (Eq. 13 sensor-to-base; Eq. 12 or 15
//              by the choice of the base pose passed in)
//
// See servo.hpp for the decisions (6x6 J^-1, P, motion sign S, units). The
// integrator is the only state. Validation messages name the file, the key
// and the valid range. Real-time: nothing here allocates, throws or logs after
// configure().
#pragma once

#include <vector>

#include "tactile_servo/servo_params.hpp"

namespace tactile {

class ServoControlLaw {
 public:
  /// Validates c_z, motion_sign, sensor_mount and every phase's s_d, J^-1, P
  /// and gains, and takes them. Allocates (configuration time).
  ConfigResult configure(const ServoParams& params);
  bool configured() const { return configured_; }
  int phaseCount() const { return static_cast<int>(phases_.size()); }

  /// J^-1 (Eq. 8) of `phase` for contact type `c` (modes baseline and
  /// no_rotation: their constant one, liJinv / noRotationJinv); `beta` = 1 when
  /// the edge Jacobian is used. `phase` must be valid.
  const Mat6& jacobian(int phase, ContactType c, uint8_t& beta) const;
  /// Δs (Eq. 7) for `phase`; zero for an invalid phase.
  Vec6 featureError(int phase, const ContactFeatures& f, uint8_t& beta) const;
  /// Δs_task = P Δs (Eq. 9).
  Vec6 project(int phase, const Vec6& error) const;
  /// u_s (Eq. 13): PI rate per axis (integrator clamped to |K_I ∫| <=
  /// integral_limit, rate to u_max), motion sign S, plus the feed-forward
  /// twist; all times dt (rates in m/s, rad/s: independent of the servo rate).
  /// Advances the integrator by task * dt.
  Vec6 increment(int phase, const Vec6& task, double dt);
  void resetIntegrator() { integral_.setZero(); }
  const Vec6& integral() const { return integral_; }

  /// Eq. 13: the increment u_s, in {s} and applied at the origin of {s}, added
  /// to the sensor pose of the flange pose `base` ({g}T{e}); returns the new
  /// flange pose. `base` is the measured pose (Eq. 12) or the previous command (Eq. 15).
  KDL::Frame apply(const KDL::Frame& base, const Vec6& u_s) const;

  double c_z() const { return c_z_; }
  const KDL::Frame& sensorMount() const { return T_es_; }

 private:
  struct Phase {
    Vec6 s_d;
    Mat6 j_point, j_edge;
    bool touch, fixed_edge;
    Mat6 P;
    Vec6 kp, ki, i_lim, u_max, ff;
  };
  bool configured_ = false;
  ControllerMode mode_ = ControllerMode::Proposed;
  std::vector<Phase> phases_;
  Vec6 motion_sign_ = defaultMotionSign();
  KDL::Frame T_es_, T_se_;
  double c_z_ = 1.0 / 1800.0;
  Vec6 integral_ = Vec6::Zero();
  Mat6 constant_ = liJinv();  ///< J^-1 of the constant modes
};

}  // namespace tactile
