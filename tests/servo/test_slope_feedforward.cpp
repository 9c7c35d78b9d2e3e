// The slide's slope fed forward along z_s (tactile_servo/slope_feedforward.hpp):
// the slope of a straight inclined path, measured in {s} whatever the pad's
// orientation, along x_s or y_s; nothing before a window's slide; 0 after a
// reset and a fresh window; clamped; off at window 0; the ranges
// named; step() does not allocate. Inside the servo: on an inclined bar a
// change of the slide speed disturbs the force far less with the feed-forward
// than without it, and a phase name it does not know is a configuration error.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "alloc_counter.hpp"
#include "servo_test_util.hpp"
#include "tactile_servo/slope_feedforward.hpp"

using namespace tactile;
using namespace servo_test;

namespace {

// The sensor at orientation R sliding `s` metres along its own `axis` with
// the rise `slope * s` along its own z_s, from p0 (all in {g}).
KDL::Frame along(const KDL::Rotation& R, const KDL::Vector& p0, int axis, double s, double slope) {
  const KDL::Vector d_s = axis == 0 ? KDL::Vector(s, 0, slope * s) : KDL::Vector(0, s, slope * s);
  return KDL::Frame(R, p0 + R * d_s);
}

SlopeFeedforward configured(double window, int axis = 0) {
  SlopeFeedforward ff;
  const ConfigResult r = ff.configure(window, axis);
  EXPECT_TRUE(r.ok()) << r.message();
  return ff;
}

}  // namespace

// Analytic: a straight path of slope sigma in {s} gives sigma, for a pad
// pitched, rolled and yawed against {g} and along either slide axis. The
// tolerance is rounding (a few ulp of the 1e-4 m displacements).
TEST(SlopeFeedforward, AStraightInclinedPathGivesItsSlope) {
  const KDL::Vector p0(0.5, -0.1, 0.3);
  for (const KDL::Rotation& R : {KDL::Rotation::Identity(), KDL::Rotation::RPY(0.2, -0.3, 1.1),
                                 KDL::Rotation::RPY(-0.4, 0.5, -2.0)}) {
    for (int axis : {0, 1}) {
      for (double sigma : {-0.3, 0.0, 0.12, 0.7}) {
        SlopeFeedforward ff = configured(0.0005, axis);
        for (int k = 0; k <= 40; ++k) ff.step(along(R, p0, axis, -0.0002 * k, sigma));  // 8 mm, backwards too
        EXPECT_NEAR(ff.slope(), sigma, 1e-9) << "axis " << axis << " sigma " << sigma;
      }
    }
  }
}

// The slope is measured over a window of slide: nothing before the first
// window ends, the new slope once it has (here after 3 steps of 0.2 mm).
TEST(SlopeFeedforward, TheSlopeChangesOnlyAfterAWindowOfSlide) {
  SlopeFeedforward ff = configured(0.0005);
  const KDL::Rotation R = KDL::Rotation::Identity();
  const KDL::Vector p0(0, 0, 0);
  EXPECT_EQ(ff.step(along(R, p0, 0, 0.0, 0.2)), 0.0);     // the window's start
  EXPECT_EQ(ff.step(along(R, p0, 0, 0.0002, 0.2)), 0.0);  // 0.2 mm
  EXPECT_EQ(ff.step(along(R, p0, 0, 0.0004, 0.2)), 0.0);  // 0.4 mm
  EXPECT_NEAR(ff.step(along(R, p0, 0, 0.0006, 0.2)), 0.2, 1e-12);  // 0.6 mm >= 0.5 mm
  // Standing still (no slide): the slope holds, however the pad moves along z_s.
  for (int k = 1; k <= 10; ++k)
    EXPECT_NEAR(ff.step(KDL::Frame(R, KDL::Vector(0.0006, 0, 0.00012 + 0.001 * k))), 0.2, 1e-12);
}

// A reset (the servo's on a contact lost or a new phase): 0, and the next
// window starts afresh.
TEST(SlopeFeedforward, AResetIsZeroAndStartsAfresh) {
  SlopeFeedforward ff = configured(0.0005);
  const KDL::Rotation R = KDL::Rotation::Identity();
  for (int k = 0; k <= 10; ++k) ff.step(along(R, KDL::Vector(), 0, 0.0002 * k, 0.3));
  ASSERT_NEAR(ff.slope(), 0.3, 1e-12);
  ff.reset();
  EXPECT_EQ(ff.slope(), 0.0);
  // Back in contact 10 mm further and 5 mm higher: the jump is not a slope.
  const KDL::Vector p1(0.012, 0, 0.005);
  EXPECT_EQ(ff.step(along(R, p1, 0, 0.0, -0.1)), 0.0);
  EXPECT_EQ(ff.step(along(R, p1, 0, 0.0002, -0.1)), 0.0);
  EXPECT_NEAR(ff.step(along(R, p1, 0, 0.0006, -0.1)), -0.1, 1e-12);
}

TEST(SlopeFeedforward, SteeperThan45DegIsClampedAndOffIsZero) {
  SlopeFeedforward ff = configured(0.0005);
  for (int k = 0; k <= 10; ++k) ff.step(along(KDL::Rotation::Identity(), KDL::Vector(), 0, 0.0002 * k, -3.0));
  EXPECT_EQ(ff.slope(), -SlopeFeedforward::kMaxSlope);
  SlopeFeedforward off = configured(0.0);
  for (int k = 0; k <= 10; ++k) off.step(along(KDL::Rotation::Identity(), KDL::Vector(), 0, 0.0002 * k, 0.3));
  EXPECT_EQ(off.slope(), 0.0);
}

TEST(SlopeFeedforward, TheRangesAreNamed) {
  SlopeFeedforward ff;
  for (double w : {-0.001, 0.051, std::nan("")}) {
    const ConfigResult r = ff.configure(w, 0, "prog.yaml: slope_feedforward");
    ASSERT_FALSE(r.ok()) << w;
    EXPECT_NE(r.message().find("prog.yaml: slope_feedforward.window_m"), std::string::npos) << r.message();
    EXPECT_NE(r.message().find("[0, 0.05] m"), std::string::npos) << r.message();
  }
  const ConfigResult r = ff.configure(0.001, 2, "prog.yaml: slope_feedforward");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("slope_feedforward.axis = 2: must be one of x, y"), std::string::npos) << r.message();
}

TEST(SlopeFeedforward, StepDoesNotAllocate) {
  SlopeFeedforward ff = configured(0.0005);
  test::AllocationScope scope;
  for (int k = 0; k < 500; ++k) {
    ff.step(along(KDL::Rotation::RPY(0.1, 0.2, 0.3), KDL::Vector(), 0, 0.0001 * k, 0.1));
    if (k % 100 == 0) ff.reset();
  }
  EXPECT_EQ(scope.count(), 0u);
}

namespace {

// One phase sliding along an inclined bar: the object (the plant of
// servo_test_util.hpp, an edge longer than the pad) pitched by atan(0.1)
// against the pad, whose pitch is not controlled (P: x and z only). The slide
// is K_P,x 2 1/s times the CoP_x error; the force loop is the bar programs'
// (K_P,z 8 1/s, K_I,z 16 1/s^2) at f_d = 5 N.
ServoParams inclinedSlide(bool feedforward) {
  PhaseParams ph = identityPhase("explore", 0.0, 0.0);
  ph.P = Mat6::Zero();
  ph.P(0, 0) = 1.0;
  ph.P(kZ, kZ) = 1.0;
  ph.jacobian = JacobianMode::Fixed;
  ph.fixed_edge = true;
  ph.s_d.setZero();
  ph.s_d(0) = -0.025;
  ph.s_d(kZ) = 5.0 / 1800.0;
  ph.kp(0) = 2.0;
  ph.kp(kZ) = 8.0;
  ph.ki(kZ) = 16.0;
  ServoParams p = singlePhase(ph);
  p.safety.max_trans_speed = 0.1;
  if (feedforward) p.slope_feedforward.phases = {"explore"};
  return p;
}

// 3 s at 10 mm/s (the CoP_x error held at 5 mm), then the slide speed steps
// to 50 mm/s (the error at 25 mm) for 1 s: the largest force error (N) after
// the step.
double worstForceErrorAfterASpeedStep(bool feedforward) {
  TactileServo s;
  const ConfigResult r = s.configure(inclinedSlide(feedforward));
  EXPECT_TRUE(r.ok()) << r.message();
  Plant plant;
  plant.infinite_edge = true;
  plant.T_go = KDL::Frame(KDL::Rotation::RotY(std::atan(0.1)), KDL::Vector(0.5, 0.0, 0.3));
  // At the set point's penetration (d_z = 5 N x C_z along the object's z).
  KDL::Frame T_ge(KDL::Vector(0.5, 0.0, 0.3) + plant.T_go.M.UnitZ() * (5.0 / 1800.0));
  ServoInput in;
  ServoOutput out;
  double worst = 0.0;
  for (int k = 1; k <= 400; ++k) {
    const double t = 0.01 * k;
    in.time_s = t;
    in.flange_measured = toPose(T_ge);
    in.features = plant.features(T_ge, t);
    in.features.cop_x = t <= 3.0 ? -0.020 : 0.0;  // the pull: 5 mm, then 25 mm
    s.step(in, 0.01, out);
    T_ge = toFrame(out.command.pose);
    EXPECT_EQ(in.features.contact, ContactType::Edge) << "t " << t;
    if (t > 3.0) worst = std::max(worst, std::fabs(in.features.force - 5.0));
  }
  return worst;
}

}  // namespace

// The speed law's case: the slide speed changes on a sloped bar. Without the
// feed-forward the force PI's integral must add the slope times the change
// (4 mm/s along z_s) and the force leaves its set point meanwhile; with it,
// the slope measured over the slow slide carries the new speed at once. The
// bound (a fifth) is the claim; the values are printed.
TEST(ServoSlopeFeedforward, ASpeedChangeOnAnInclinedBarBarelyDisturbsTheForce) {
  const double without = worstForceErrorAfterASpeedStep(false), with = worstForceErrorAfterASpeedStep(true);
  std::printf("worst force error after the speed step: %.3f N with the feed-forward, %.3f N without\n", with, without);
  EXPECT_GT(without, 0.3) << "the speed step must disturb the force without the feed-forward";
  EXPECT_LT(with, without / 5.0);
}

TEST(ServoSlopeFeedforward, AnUnknownPhaseOrAWindowOutOfRangeIsNamed) {
  ServoParams p = inclinedSlide(true);
  p.source = "prog.yaml";
  p.slope_feedforward.phases = {"explroe"};
  TactileServo s;
  const ConfigResult r = s.configure(p);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("prog.yaml: slope_feedforward.phases: no phase 'explroe'"), std::string::npos)
      << r.message();
  p.slope_feedforward.phases = {"explore"};
  p.slope_feedforward.window_m = 0.5;
  const ConfigResult r2 = s.configure(p);
  ASSERT_FALSE(r2.ok());
  EXPECT_NE(r2.message().find("prog.yaml: slope_feedforward.window_m"), std::string::npos) << r2.message();
}
