// Closed-loop convergence against the simple compliant plant of
// servo_test_util.hpp, with the shipped gains, at 100 Hz.
#include <cstdio>
#include <random>

#include "servo_test_util.hpp"

using namespace tactile;
using namespace servo_test;

namespace {

constexpr double kDt = 0.01;  // 100 Hz servo rate

struct LoopResult {
  Vec6 final_error = Vec6::Zero();  // Δs at the end
  double t_converged = -1.0;        // first time after which the watched error stayed below tol
  bool any_nan = false;
};

// Runs `seconds` of closed loop; the robot tracks the command exactly.
LoopResult run(TactileServo& s, const Plant& plant, KDL::Frame T_ge, double seconds, int watch, double tol,
               std::mt19937* jitter = nullptr) {
  LoopResult r;
  ServoInput in;
  ServoOutput out;
  double t = 0.0;
  std::uniform_real_distribution<double> j(0.5, 1.5);
  while (t < seconds) {
    const double dt = jitter ? kDt * j(*jitter) : kDt;
    t += dt;
    in.time_s = t;
    in.flange_measured = toPose(T_ge);
    in.features = plant.features(T_ge, t);
    s.step(in, dt, out);
    if (!poseFinite(out.command.pose)) r.any_nan = true;
    T_ge = toFrame(out.command.pose);
    const double e = std::fabs(out.error(watch));
    if (e > tol) r.t_converged = -1.0;
    else if (r.t_converged < 0) r.t_converged = t;
    r.final_error = out.error;
  }
  return r;
}

// The shipped gains of the edge-control phase, every axis selected, edge Jacobian.
ServoParams shippedAllAxes(PoseUpdate mode) {
  ServoParams p = loadShipped("edge_exploration.yaml");
  TactileServo tmp;
  EXPECT_TRUE(tmp.configure(p).ok());
  PhaseParams ph = tmp.phase(tmp.phaseIndexOf("edge_control"));
  ph.name = "all";
  ph.P = Mat6::Identity();
  ph.jacobian = JacobianMode::Fixed;
  ph.fixed_edge = true;
  ph.s_d << 0, 0, 5.0 * p.c_z, 0, 0, 0;
  ph.transitions.clear();
  p.phases = {ph};
  p.initial_phase.clear();
  p.pose_update = mode;
  return p;
}

}  // namespace

// Each axis converges alone from an initial offset, to 2 % of the offset
// (tolerance: the plant is linear only to first order in the rotation vector,
// so a small bias of order offset^2 remains possible), within 5 s.
TEST(ServoClosedLoop, EachAxisConvergesWithShippedGains) {
  const double d0 = 5.0 / 1800.0;  // 5 N penetration
  struct Case { int axis; double offset; };
  const Case cases[] = {{kX, 0.005}, {kY, 0.004}, {kZ, -0.0015}, {kWX, 0.035}, {kWY, 0.035}, {kWZ, 0.17}};
  for (PoseUpdate mode : {PoseUpdate::Integrated, PoseUpdate::Measured}) {
    for (const Case& c : cases) {
      Plant plant;
      plant.T_go = KDL::Frame(KDL::Rotation::RPY(0.3, -0.2, 1.0), KDL::Vector(0.4, 0.1, 0.3));
      plant.T_es = KDL::Frame(KDL::Rotation::RotX(kPi), KDL::Vector(0, 0, 0.03));
      ServoParams p = shippedAllAxes(mode);
      p.sensor_mount = plant.T_es;
      TactileServo s;
      ASSERT_TRUE(s.configure(p).ok());
      // Start: nominal penetration, offset on one axis of the sensor pose in {o}.
      Vec6 off = Vec6::Zero();
      off(kZ) = d0;
      off(c.axis) += c.offset;
      const KDL::Frame T_os = KDL::addDelta(
          KDL::Frame::Identity(),
          KDL::Twist(KDL::Vector(off(0), off(1), off(2)), KDL::Vector(off(3), off(4), off(5))), 1.0);
      const KDL::Frame T_gs0 = plant.T_go * T_os;
      const KDL::Frame T_ge0 = T_gs0 * plant.T_es.Inverse();
      // Error row watched: the feature the axis moves (plant gain g for rotations).
      const double g = c.axis == kWX ? plant.g_x : c.axis == kWY ? plant.g_y : 1.0;
      const double tol = 0.02 * std::fabs(c.offset) * g;
      const LoopResult r = run(s, plant, T_ge0, 5.0, c.axis, tol);
      EXPECT_FALSE(r.any_nan);
      EXPECT_GT(r.t_converged, 0.0) << "axis " << kAxisNames[c.axis] << " mode " << int(mode) << " final error "
                                    << r.final_error.transpose();
      EXPECT_LT(r.t_converged, 5.0);
      std::printf("[ servo    ] axis %-2s (%s): |error| < 2 %% of the offset after %.2f s\n", kAxisNames[c.axis],
                  mode == PoseUpdate::Integrated ? "Eq. 15" : "Eq. 12", r.t_converged);
      for (int k = 0; k < 6; ++k) EXPECT_LT(std::fabs(r.final_error(k)), 0.05 * std::fabs(c.offset) * g + 1e-6) << k;
    }
  }
}

// dt jitter of +-50 % around 10 ms: the loop still converges (P acts per cycle,
// I integrates the true dt).
TEST(ServoClosedLoop, ConvergesUnderDtJitter) {
  Plant plant;
  plant.T_go = KDL::Frame(KDL::Vector(0.5, 0, 0.3));
  ServoParams p = shippedAllAxes(PoseUpdate::Integrated);
  TactileServo s;
  ASSERT_TRUE(s.configure(p).ok());
  const KDL::Frame T_os(KDL::Rotation::RPY(0.02, -0.03, 0.1), KDL::Vector(0.003, -0.002, 0.002));
  std::mt19937 rng(3);
  const LoopResult r = run(s, plant, plant.T_go * T_os, 8.0, kWZ, 0.002, &rng);
  EXPECT_FALSE(r.any_nan);
  EXPECT_GT(r.t_converged, 0.0);
  EXPECT_LT(r.final_error.cwiseAbs().maxCoeff(), 2e-4) << r.final_error.transpose();
}

// The whole shipped edge-exploration program against a bar: free motion until
// contact, point contact at one end of the tilted pad, alignment to an edge,
// edge control, sliding along x_s at kp.x * 0.025 m per cycle, end of the bar.
TEST(ServoClosedLoop, EdgeExplorationProgramRunsAllPhases) {
  ServoParams p = loadShipped("edge_exploration.yaml");
  p.sensor_mount = KDL::Frame::Identity();
  TactileServo s;
  ASSERT_TRUE(s.configure(p).ok());
  Plant plant;
  plant.infinite_edge = true;
  plant.tilt_point = true;
  plant.bar_end = 0.08;
  plant.T_go = KDL::Frame(KDL::Rotation::RotX(kPi), KDL::Vector(0.5, 0.0, 0.2));  // bar below, z_s down
  // Start 5 mm before the bar, tilted 5 deg about y_s.
  KDL::Frame T_ge = plant.T_go * KDL::Frame(KDL::Rotation::RotY(0.087), KDL::Vector(0, 0.002, -0.005));
  ServoInput in;
  ServoOutput out;
  std::vector<std::string> visited{"free_motion"};
  double t = 0, max_force_explore = 0, max_force_late = 0, x_enter_explore = 0, t_enter_explore = -1;
  double x_prev = -2.0, speed_max = 0.0, speed_min = 1e9;
  for (int k = 0; k < 6000 && out.command.status != ServoStatus::Done; ++k) {
    t += kDt;
    in.time_s = t;
    in.flange_measured = toPose(T_ge);
    in.features = plant.features(T_ge, t);
    s.step(in, kDt, out);
    ASSERT_TRUE(poseFinite(out.command.pose));
    T_ge = toFrame(out.command.pose);
    const std::string name(out.phase.name.data());
    if (name != visited.back()) {
      visited.push_back(name);
      if (name == "explore") {
        x_enter_explore = plant.relative(T_ge).vel.x();
        t_enter_explore = t;
      }
    }
    if (name == "explore" && in.features.contact != ContactType::None) {
      const double ef = std::fabs(in.features.force - 5.0);
      max_force_explore = std::max(max_force_explore, ef);
      if (t > t_enter_explore + 5.0) max_force_late = std::max(max_force_late, ef);
      const double x = plant.relative(T_ge).vel.x();
      if (t > t_enter_explore + 1.0 && x_prev > -1.0) speed_max = std::max(speed_max, std::fabs(x - x_prev) / kDt),
                                                         speed_min = std::min(speed_min, std::fabs(x - x_prev) / kDt);
      x_prev = x;
    }
  }
  const std::vector<std::string> expect{"free_motion", "align", "edge_control", "explore", "done"};
  EXPECT_EQ(visited, expect);
  EXPECT_EQ(out.command.status, ServoStatus::Done);
  // Force while sliding: the integral carried over from phase III overshoots
  // by about 0.6 N (12 %) at the start; after 5 s it is within 0.05 N of 5 N
  // (the plant is exact and the slide does not disturb the force).
  EXPECT_LT(max_force_explore, 0.75);
  EXPECT_LT(max_force_late, 0.05);
  // Slide speed: kp.x * 0.025 m per cycle = 0.004 * 0.025 / 0.01 s = 1 cm/s (1 % tolerance:
  // the only other x motion is the rotation coupling of the small wy corrections).
  EXPECT_NEAR(speed_max, 0.01, 1e-4);
  EXPECT_NEAR(speed_min, 0.01, 1e-4);
  // Slid to the end of the bar (0.08 m) along +x_s.
  EXPECT_GT(plant.relative(T_ge).vel.x() - x_enter_explore, 0.05);
}

// Sec. 5.2.1 in miniature: the sensor meets a bar that is tilted by 2 deg about
// y_s (a bend in the xz plane). The proposed controller (J^-1 with DZMP_y,
// bent_bar.yaml) rotates the sensor onto the bar; the no_rotation ablation
// (constant diag(1,1,1,0,0,1), same file otherwise) cannot: DZMP_y, i.e. the
// uneven line load, stays. (The Li et al. baseline is not scored on this
// linear plant: it reports CoP_x = 0 for an infinite edge, so the baseline's
// CoP rows would see nothing; tests/runner compares it on the simulated pad.)
TEST(ServoClosedLoop, BentBarProposedAlignsNoRotationDoesNot) {
  for (ControllerMode mode : {ControllerMode::Proposed, ControllerMode::NoRotation}) {
    ServoParams p = loadShipped("bent_bar.yaml");
    p.mode = mode;
    p.sensor_mount = KDL::Frame::Identity();
    TactileServo s;
    ASSERT_TRUE(s.configure(p).ok());
    Plant plant;
    plant.infinite_edge = true;
    plant.T_go = KDL::Frame(KDL::Rotation::RotX(kPi), KDL::Vector(0.5, 0.0, 0.2));
    KDL::Frame T_ge = plant.T_go * KDL::Frame(KDL::Rotation::RotY(0.035), KDL::Vector(0, 0, 5.0 / 1800.0));
    ServoInput in;
    ServoOutput out;
    for (int k = 1; k <= 500; ++k) {  // 5 s
      in.time_s = k * kDt;
      in.flange_measured = toPose(T_ge);
      in.features = plant.features(T_ge, in.time_s);
      s.step(in, kDt, out);
      T_ge = toFrame(out.command.pose);
    }
    const double tilt = plant.relative(T_ge).rot.y();
    if (mode == ControllerMode::Proposed) {
      EXPECT_LT(std::fabs(tilt), 0.001);                        // aligned to < 0.06 deg
      EXPECT_LT(std::fabs(in.features.dzmp_y), 0.0001);
    } else {
      EXPECT_NEAR(tilt, 0.035, 1e-9);                           // never rotated about y_s
      EXPECT_NEAR(in.features.dzmp_y, -plant.g_y * 0.035, 1e-9);
    }
    EXPECT_NEAR(in.features.force, 5.0, 0.1);  // both hold the force on this linear plant
  }
}

// The point loop_closed follows (servo.hpp, WRIST) is where the edge passes
// the pad's centre, {g}T{e} {e}T{s} (0, CoP_y, 0), from the measured pose: the
// same place on the contour reads the same whatever CoP_x the image gives
// (the CoP moves along the pad with the load's distribution), and across the
// edge it follows CoP_y. Exact: one KDL frame product (1e-12 m).
TEST(ServoLoopPoint, IsTheEdgeAtThePadCentreNotTheCoP) {
  const ServoParams p = loadShipped("closed_contour.yaml");
  KDL::Frame meas(KDL::Rotation::RPY(3.1, 0.05, 0.7), KDL::Vector(0.55, -0.06, 0.375));
  const KDL::Vector want_centre = meas * p.sensor_mount * KDL::Vector(0.0, 0.0017, 0.0);
  for (double cop_x : {-0.02, 0.0, 0.013}) {
    TactileServo core;
    const ConfigResult r = core.configure(p);
    ASSERT_TRUE(r.ok()) << r.message();
    ServoInput in;
    in.time_s = 0.0;
    in.flange_measured = toPose(meas);
    in.features = makeFeatures(0.0, cop_x, 0.0017, 5.0 / 1800.0, cop_x, 0.0017, 0.0);
    ServoOutput out;
    core.step(in, 0.01, out);
    ASSERT_TRUE(core.requestPhase("explore"));  // its loop_closed transition anchors on its first evaluation in contact
    for (int k = 1; k <= 2; ++k) {
      in.time_s = in.features.time_s = 0.01 * k;
      core.step(in, 0.01, out);
    }
    ASSERT_STREQ(core.program().name(core.program().current()).data(), "explore");
    double a[3];
    ASSERT_TRUE(core.program().loopAnchor(a)) << "cop_x " << cop_x;
    EXPECT_NEAR(a[0], want_centre.x(), 1e-12) << "cop_x " << cop_x;
    EXPECT_NEAR(a[1], want_centre.y(), 1e-12) << "cop_x " << cop_x;
    EXPECT_NEAR(a[2], want_centre.z(), 1e-12) << "cop_x " << cop_x;
  }
}
