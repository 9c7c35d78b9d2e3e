// Shared helpers for the servo tests: a simple compliant plant and builders.
#pragma once

#include <gtest/gtest.h>
#include <kdl/frames.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include "tactile_servo/program_io.hpp"
#include "tactile_servo/servo.hpp"

namespace servo_test {

using namespace tactile;

inline std::string programPath(const std::string& name) { return std::string(TACTILE_SERVO_PROGRAM_DIR) + "/" + name; }

inline ServoParams loadShipped(const std::string& name) {
  ServoParams p;
  const ConfigResult r = loadServoProgram(programPath(name), p);
  EXPECT_TRUE(r.ok()) << r.message();
  return p;
}

inline Pose toPose(const KDL::Frame& f) {
  Pose p;
  p.p = {f.p.x(), f.p.y(), f.p.z()};
  f.M.GetQuaternion(p.q[0], p.q[1], p.q[2], p.q[3]);
  return p;
}

inline KDL::Frame toFrame(const Pose& p) {
  return KDL::Frame(KDL::Rotation::Quaternion(p.q[0], p.q[1], p.q[2], p.q[3]), KDL::Vector(p.p[0], p.p[1], p.p[2]));
}

inline bool poseFinite(const Pose& p) {
  for (double v : p.p)
    if (!std::isfinite(v)) return false;
  for (double v : p.q)
    if (!std::isfinite(v)) return false;
  return true;
}

/// Translation (m) and rotation angle (rad) between two poses.
inline double transDist(const Pose& a, const Pose& b) {
  return std::sqrt(std::pow(a.p[0] - b.p[0], 2) + std::pow(a.p[1] - b.p[1], 2) + std::pow(a.p[2] - b.p[2], 2));
}
inline double rotDist(const Pose& a, const Pose& b) {
  const KDL::Vector r = KDL::diff(toFrame(a).M, toFrame(b).M);
  return r.Norm();
}

inline ContactFeatures makeFeatures(double t, double cop_x, double cop_y, double d_z, double coc_x, double coc_y,
                                    double alpha_z, ContactType c = ContactType::Edge, double c_z = 1.0 / 1800.0) {
  ContactFeatures f;
  f.time_s = t;
  f.cop_x = cop_x;
  f.cop_y = cop_y;
  f.d_z = d_z;
  f.coc_x = coc_x;
  f.coc_y = coc_y;
  f.alpha_z = alpha_z;
  f.dzmp_x = cop_y - coc_y;
  f.dzmp_y = cop_x - coc_x;
  f.force = d_z / c_z;
  f.contact = c;
  f.status = c == ContactType::None ? FeatureStatus::NoContact : FeatureStatus::Ok;
  f.alpha_defined = c == ContactType::Point || c == ContactType::Edge;  // as the extractor reports a clean contact
  return f;
}

/// The servo period the tests step at (s): the values below are given per
/// cycle of it and converted to the servo's per-second units.
constexpr double kTestPeriod = 0.01;

/// A phase with every axis selected (P = I) and the given gains, per cycle of
/// kTestPeriod (kp: increment per unit error per cycle; ki: per cycle per
/// second of integral), i.e. K_P = kp / kTestPeriod (1/s), K_I = ki /
/// kTestPeriod (1/s^2); wide limits (1 per cycle).
inline PhaseParams identityPhase(const std::string& name, double kp, double ki) {
  PhaseParams ph;
  ph.name = name;
  ph.P = Mat6::Identity();
  ph.kp = Vec6::Constant(kp / kTestPeriod);
  ph.ki = Vec6::Constant(ki / kTestPeriod);
  ph.integral_limit = Vec6::Constant(1.0 / kTestPeriod);
  ph.u_max = Vec6::Constant(1.0 / kTestPeriod);
  return ph;
}

inline ServoParams singlePhase(const PhaseParams& ph) {
  ServoParams p;
  p.phases.push_back(ph);
  p.safety.max_trans_speed = 0.01 / kTestPeriod;  // 10 mm per cycle
  p.safety.max_rot_speed = 0.1 / kTestPeriod;     // 0.1 rad per cycle
  p.safety.force_ceiling = 1e6;
  return p;
}

/// Simple compliant plant: an object whose contact frame sits at {o} = the
/// nominal sensor pose (aligned, centred, zero penetration). The robot reaches
/// the commanded flange pose exactly. Features are linear in the sensor's pose
/// relative to {o} (small-angle rotation vector d.rot, translation d.vel, in {o}):
///   CoP = -(dx, dy)          (the contact moves opposite to the sensor)
///   d_z = dz                 (penetration; pad compliance C_z: f = d_z / C_z)
///   DZMP_x = +g_x rot_x      (a positive rotation about x_s loads the +y_s side)
///   DZMP_y = -g_y rot_y      (a positive rotation about y_s unloads the +x_s side)
///   alpha_z = -rot_z         CoC = CoP - DZMP (Eq. 3)
/// g_x, g_y (m/rad) follow from a uniform elastic pad under a line load of
/// length L: DZMP = -theta L^2 / (12 d_z)  (L = 20.4 mm across, 47.6 mm along).
struct Plant {
  KDL::Frame T_go = KDL::Frame::Identity();
  KDL::Frame T_es = KDL::Frame::Identity();
  double c_z = 1.0 / 1800.0;
  double g_x = 0.0204 * 0.0204 / (12.0 * 0.00278);
  double g_y = 0.0476 * 0.0476 / (12.0 * 0.00278);
  ContactType type = ContactType::Edge;
  bool infinite_edge = false;   ///< an edge longer than the pad: CoP_x = 0
  double bar_end = 1e9;         ///< |dx| beyond which the bar ends (no contact)
  bool tilt_point = false;      ///< |rot_y| > edge_angle -> point contact at the pad's end
  double edge_angle = 0.01;     ///< rad

  KDL::Twist relative(const KDL::Frame& T_ge) const {
    return KDL::diff(KDL::Frame::Identity(), T_go.Inverse() * (T_ge * T_es));
  }

  ContactFeatures features(const KDL::Frame& T_ge, double t) const {
    const KDL::Twist d = relative(T_ge);
    ContactFeatures f;
    f.time_s = t;
    const double ry = d.rot.y();
    bool point = type == ContactType::Point;
    f.cop_x = infinite_edge ? 0.0 : -d.vel.x();
    f.cop_y = -d.vel.y();
    f.d_z = d.vel.z();
    f.dzmp_x = g_x * d.rot.x();
    f.dzmp_y = -g_y * ry;
    f.alpha_z = -d.rot.z();
    if (tilt_point && std::fabs(ry) > edge_angle) {  // only one end of the pad touches
      point = true;
      const double half = 0.0238;
      f.d_z = d.vel.z() + std::fabs(ry) * half;
      f.cop_x = -half * std::tanh(ry / 0.02);
      f.dzmp_y = 0.0;
      f.alpha_z = 0.0;
    }
    f.coc_x = f.cop_x - f.dzmp_y;
    f.coc_y = f.cop_y - f.dzmp_x;
    f.force = std::max(0.0, f.d_z) / c_z;
    const bool contact = f.d_z > 0.0 && std::fabs(d.vel.x()) < bar_end;
    f.contact = contact ? (point ? ContactType::Point : ContactType::Edge) : ContactType::None;
    f.status = contact ? FeatureStatus::Ok : FeatureStatus::NoContact;
    f.alpha_defined = contact;
    if (!contact) {
      const double tt = f.time_s;
      f = ContactFeatures();
      f.time_s = tt;
      f.status = FeatureStatus::NoContact;
    }
    return f;
  }
};

/// The increment u_s of the servo's second cycle (the first one only takes
/// the measured pose, Eq. 15) on the features `f`, from the identity pose.
inline Vec6 secondCycleIncrement(const ServoParams& p, const ContactFeatures& f) {
  TactileServo s;
  EXPECT_TRUE(s.configure(p).ok());
  ServoInput in;
  in.flange_measured = Pose();
  in.features = f;
  ServoOutput out;
  EXPECT_EQ(s.step(in, 0.01, out), ServoStatus::Starting);
  s.step(in, 0.01, out);
  return Vec6(out.u_s);
}

/// The servo in a loop with an arm that reaches each command (arm_follows;
/// not while the robot is not ready): the measured pose is the flange at
/// (0.5, 0, 0.3) until the first command; the features are the caller's
/// (`in.features`, stamped with the loop's time each step).
struct ServoLoop {
  TactileServo s;
  ServoInput in;
  ServoOutput out;
  double t = 0.0;
  bool arm_follows = true;
  ServoLoop(const ServoParams& p, const ContactFeatures& f) {
    const ConfigResult r = s.configure(p);
    EXPECT_TRUE(r.ok()) << r.message();
    in.flange_measured = toPose(KDL::Frame(KDL::Vector(0.5, 0.0, 0.3)));
    in.features = f;
  }
  ServoStatus step(double dt = kTestPeriod) {
    in.time_s = t;
    in.features.time_s = t;
    in.wrench.time_s = t;
    const ServoStatus st = s.step(in, dt, out);
    if (arm_follows && in.robot_ready && out.valid) in.flange_measured = out.command.pose;
    t += dt;
    return st;
  }
  /// Steps for `seconds`; returns the first status equal to `stop`, else the last.
  ServoStatus run(double seconds, double dt, ServoStatus stop) {
    ServoStatus st = ServoStatus::NotConfigured;
    const int n = static_cast<int>(std::lround(seconds / dt));
    for (int k = 0; k < n; ++k)
      if ((st = step(dt)) == stop) return st;
    return st;
  }
};

}  // namespace servo_test

