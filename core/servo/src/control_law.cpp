#include "tactile_servo/control_law.hpp"
#include "tactile_servo/servo_schema.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "servo_config.hpp"
#include "tactile_types/kdl_pose.hpp"

namespace tactile {

using servo_config::err;

const char* const kToleranceNames[kNumTol] = {"cop_x", "cop_y", "d_z", "dzmp_x", "dzmp_y", "alpha_z",
                                              "force", "coc_x", "coc_y"};
const char* const kFeatureNames[6] = {"cop_x", "cop_y", "d_z", "coc_x", "coc_y", "alpha_z"};
const char* const kAxisNames[6] = {"x", "y", "z", "wx", "wy", "wz"};

// Eq. 6: s = [CoP_x, CoP_y, d_z, CoC_x, CoC_y, alpha_z].
Vec6 featureVector(const ContactFeatures& f) {
  Vec6 s;
  s << f.cop_x, f.cop_y, f.d_z, f.coc_x, f.coc_y, f.alpha_z;
  return s;
}

// Eq. 8 in its 6x6 form (decision documented in servo.hpp).
Mat6 paperJinv(double beta) {
  Mat6 j = Mat6::Zero();
  j(0, 0) = 1.0;    // CoP_x
  j(1, 1) = 1.0;    // CoP_y
  j(2, 2) = 1.0;    // d_z
  j(3, 1) = 1.0;    // DZMP_x = CoP_y - β CoC_y (Eq. 3)
  j(3, 4) = -beta;
  j(4, 0) = 1.0;    // DZMP_y = CoP_x - β CoC_x (Eq. 3)
  j(4, 3) = -beta;
  j(5, 5) = beta;   // α_z, edge only
  return j;
}

// Li et al. (RSS 2013), ref. [7] of the paper: constant inverse tactile
// Jacobian on CoP_x, CoP_y, force and alpha_z. Rows 4/5 (wx, wy) keep the
// CoP -> rotation coupling of their framework (roll the sensor to centre the
// contact); unlike Eq. 8 the CoC columns are zero (no DZMP, Eq. 3) and no
// entry depends on the contact type (Eq. 5): for β = 0 it equals Eq. 8 except
// the alpha_z row, which Li et al. keep on for a point too. Sec. 5.2.1 and 6:
// the DZMP rows are what the proposed controller adds.
Mat6 liJinv() {
  Mat6 j = Mat6::Zero();
  j(0, 0) = 1.0;  // CoP_x  -> x
  j(1, 1) = 1.0;  // CoP_y  -> y
  j(2, 2) = 1.0;  // d_z    -> z (force, Eq. 2)
  j(3, 1) = 1.0;  // CoP_y  -> wx (rolling)
  j(4, 0) = 1.0;  // CoP_x  -> wy (rolling)
  j(5, 5) = 1.0;  // alpha_z -> wz
  return j;
}

// Ablation: Li et al.'s features without the rotation rows.
Mat6 noRotationJinv() {
  Vec6 d;
  d << 1, 1, 1, 0, 0, 1;
  return d.asDiagonal();
}

const char* const kControllerModeNames = "proposed, baseline or no_rotation";

const char* toString(ControllerMode m) {
  switch (m) {
    case ControllerMode::Proposed: return "proposed";
    case ControllerMode::Baseline: return "baseline";
    case ControllerMode::NoRotation: return "no_rotation";
  }
  return "?";
}

bool parseControllerMode(const std::string& name, ControllerMode& mode) {
  for (ControllerMode m : {ControllerMode::Proposed, ControllerMode::Baseline, ControllerMode::NoRotation})
    if (name == toString(m)) {
      mode = m;
      return true;
    }
  return false;
}

// Eq. 10.
Mat6 projection(double gx, double gy, double gz, double gwx, double gwy, double gwz, double gcom) {
  Vec6 d;
  d << gx, gy, gz, gwx, gwy, gwz;
  Mat6 p = d.asDiagonal();
  p(kX, kWY) = gcom;
  return p;
}

Vec6 defaultMotionSign() {
  Vec6 s;
  s << -1, -1, 1, 1, -1, -1;
  return s;
}

ConfigResult ServoControlLaw::configure(const ServoParams& p) {
  configured_ = false;
  if (const ConfigResult r = schema::checkRanges(controllerSchema(), p, servo_config::where(p, "", "controller")); !r)
    return r;
  for (int i = 0; i < 6; ++i)
    if (p.motion_sign(i) != 1.0 && p.motion_sign(i) != -1.0)
      return err(p, "", std::string("motion_sign.") + kAxisNames[i], p.motion_sign(i), "must be +1 or -1");
  if (!frameFinite(p.sensor_mount)) return err(p, "", "sensor_mount", "non-finite", "must be finite");
  for (const PhaseParams& ph : p.phases) {
    const std::string& nm = ph.name;
    if (!ph.s_d.allFinite()) return err(p, nm, "s_d", "non-finite", "must be finite");
    if (!ph.jinv_point.allFinite()) return err(p, nm, "jacobian.point", "non-finite", "must be finite");
    if (!ph.jinv_edge.allFinite()) return err(p, nm, "jacobian.edge", "non-finite", "must be finite");
    if (!ph.P.allFinite()) return err(p, nm, "P", "non-finite", "must be finite");
    const std::string at = servo_config::where(p, "", "phases.") + nm;  // "<file>: phases.<name>"
    if (const ConfigResult r = schema::checkRanges(phaseSchema(), ph, at); !r) return r;
  }
  phases_.clear();
  phases_.reserve(p.phases.size());
  for (const PhaseParams& ph : p.phases) {
    Phase q;
    q.s_d = ph.s_d;
    q.j_point = ph.jinv_point;
    q.j_edge = ph.jinv_edge;
    q.touch = ph.jacobian == JacobianMode::Touch;
    q.fixed_edge = ph.fixed_edge;
    q.P = ph.P;
    q.kp = ph.kp;
    q.ki = ph.ki;
    q.i_lim = ph.integral_limit;
    q.u_max = ph.u_max;
    q.ff = ph.feedforward;
    phases_.push_back(q);
  }
  mode_ = p.mode;
  constant_ = p.mode == ControllerMode::NoRotation ? noRotationJinv() : liJinv();
  motion_sign_ = p.motion_sign;
  T_es_ = p.sensor_mount;
  T_se_ = p.sensor_mount.Inverse();
  c_z_ = p.c_z;
  integral_.setZero();
  configured_ = true;
  return ConfigResult::success();
}

// Touch dependence (Eq. 8 with Eq. 5): edge -> β = 1, point/none -> β = 0.
const Mat6& ServoControlLaw::jacobian(int phase, ContactType c, uint8_t& beta) const {
  if (mode_ != ControllerMode::Proposed) {  // Li et al. or the ablation: constant, no β
    beta = 0;
    return constant_;
  }
  const Phase& ph = phases_[static_cast<std::size_t>(phase)];
  const bool edge = ph.touch ? (c == ContactType::Edge) : ph.fixed_edge;
  beta = edge ? 1 : 0;
  return edge ? ph.j_edge : ph.j_point;
}

Vec6 ServoControlLaw::featureError(int phase, const ContactFeatures& f, uint8_t& beta) const {
  if (phase < 0 || phase >= phaseCount()) return Vec6::Zero();
  const Mat6& j = jacobian(phase, f.contact, beta);
  Vec6 e = phases_[static_cast<std::size_t>(phase)].s_d - j * featureVector(f);  // Eq. 7
  // alpha_z not resolved above the noise (or a multiple contact): its row
  // must not drive a rotation about z_s.
  if (!f.alpha_defined) e(5) = 0.0;
  return e;
}

Vec6 ServoControlLaw::project(int phase, const Vec6& error) const {
  return phases_[static_cast<std::size_t>(phase)].P * error;  // Eq. 9
}

Vec6 ServoControlLaw::increment(int phase, const Vec6& task, double dt) {
  const Phase& ph = phases_[static_cast<std::size_t>(phase)];
  // Eq. 13 as a rate: PI per axis (K_P in 1/s, K_I in 1/s^2), integrator
  // clamped so that |K_I ∫| <= integral_limit (m/s or rad/s), the rate
  // clamped to u_max, then integrated over the cycle: u = (S rate + v_ff) dt.
  // The motion per second is therefore independent of the servo rate.
  integral_ += task * dt;
  for (int a = 0; a < 6; ++a) {
    if (ph.ki(a) > 0.0) {
      const double lim = ph.i_lim(a) / ph.ki(a);
      integral_(a) = std::max(-lim, std::min(lim, integral_(a)));
    } else {
      integral_(a) = 0.0;
    }
  }
  Vec6 rate = ph.kp.cwiseProduct(task) + ph.ki.cwiseProduct(integral_);
  rate = rate.cwiseMax(-ph.u_max).cwiseMin(ph.u_max);
  return (motion_sign_.cwiseProduct(rate) + ph.ff) * dt;
}

KDL::Frame ServoControlLaw::apply(const KDL::Frame& base, const Vec6& u_s) const {
  // Eq. 13: {g}T{s} = {g}T{e} {e}T{s}; the increment, expressed in {s} and
  // applied at the origin of {s}, is rotated into {g} (same reference point).
  const KDL::Frame T_gs = base * T_es_;
  const KDL::Twist t_s(KDL::Vector(u_s(0), u_s(1), u_s(2)), KDL::Vector(u_s(3), u_s(4), u_s(5)));
  const KDL::Twist t_g = T_gs.M * t_s;
  // Eq. 12 / Eq. 15: x_d = x + u.
  const KDL::Frame T_gs_new = KDL::addDelta(T_gs, t_g, 1.0);
  return T_gs_new * T_se_;
}

}  // namespace tactile
