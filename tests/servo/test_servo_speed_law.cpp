// The speed law inside the servo (servo.hpp, SpeedLawConfig): in the phases
// its block lists it caps the slide axis's rate, starting at v_min on
// entering the phase; elsewhere it does nothing; a bend (the edge angle
// turning) or a force error slows the slide; a phase name it does not know is
// a configuration error naming the key; no allocation in step().
#include "alloc_counter.hpp"
#include "servo_test_util.hpp"

using namespace tactile;
using namespace servo_test;

namespace {

// One phase pulling along x_s: s_d.cop_x = -25 mm against a CoP held at 0
// (the plant below does not move the contact: a straight edge under a sliding
// pad), K_P,x = 4 1/s: 100 mm/s asked; every other axis's gain 0.
ServoParams slide(bool with_law) {
  PhaseParams ph = identityPhase("explore", 0.0, 0.0);
  ph.s_d(0) = -0.025;
  ph.s_d(kZ) = 5.0 / 1800.0;  // f_d = 5 N
  ph.kp(0) = 4.0;
  ServoParams p = singlePhase(ph);
  p.safety.max_trans_speed = 0.2;
  if (with_law) {
    p.speed_law.phases = {"explore"};
    p.speed_law.law.v_max = 0.06;
    p.speed_law.law.v_min = 0.005;
    p.speed_law.law.accel_mps2 = 0.1;
  }
  return p;
}

// An edge across the whole pad at the set point's force.
ContactFeatures edge() {
  ContactFeatures f = makeFeatures(0, 0, 0, 5.0 / 1800.0, 0, 0, 0, ContactType::Edge);
  f.lambda1 = 0.0476 * 0.0476 / 12.0;
  return f;
}

struct Loop : ServoLoop {
  explicit Loop(const ServoParams& p) : ServoLoop(p, edge()) {}
  /// One cycle; returns the slide's rate |u_x| / dt (m/s).
  double slide(double dt = 0.01) {
    step(dt);
    return std::fabs(out.u_s(0)) / dt;
  }
  double slideFor(double seconds) {
    double v = 0;
    for (int k = 0; k < static_cast<int>(std::lround(seconds / 0.01)); ++k) v = slide();
    return v;
  }
};

}  // namespace

TEST(ServoSpeedLaw, WithoutTheLawTheGainSetsTheSpeed) {
  Loop l(slide(false));
  EXPECT_NEAR(l.slideFor(1.0), 0.1, 1e-9);  // K_P 4 x 25 mm
  EXPECT_EQ(l.out.slide_speed, 0.0);
}

TEST(ServoSpeedLaw, TheLawCapsTheSlideFromVMinUpToVMax) {
  Loop l(slide(true));
  l.slide();  // Starting
  EXPECT_NEAR(l.slide(), 0.005 + 0.1 * 0.01, 1e-9);  // v_min, then up at accel_mps2
  EXPECT_NEAR(l.slideFor(2.0), 0.06, 1e-9);               // nothing to slow for: v_max
  EXPECT_EQ(l.out.speed_limiter, SpeedLimiter::None);
}

// The servo's slide is the law's slide() (speed_law.hpp): with the pull weak
// (K_P,x 1 1/s x 25 mm = 25 mm/s) below drive_fraction 0.6 of v_max (36 mm/s),
// the drive raises it; with drive_fraction 0 the pull passes unchanged.
TEST(ServoSpeedLaw, TheDriveRaisesAWeakPullToItsShareOfTheLawsSpeed) {
  ServoParams p = slide(true);
  p.phases[0].kp(0) = 1.0;
  {
    Loop l(p);
    EXPECT_NEAR(l.slideFor(2.0), 0.025, 1e-9);
  }
  p.speed_law.law.drive_fraction = 0.6;
  Loop l(p);
  EXPECT_NEAR(l.slideFor(2.0), 0.036, 1e-9);
  EXPECT_NEAR(l.out.slide_speed, 0.06, 1e-12);
}

// The edge turning at half the angle rate reference: half of v_max; a force
// error of half the budget (the true force 0.25 N low) likewise.
TEST(ServoSpeedLaw, ABendOrAForceErrorSlowsTheSlide) {
  {
    Loop l(slide(true));
    l.slideFor(2.0);
    for (int k = 0; k < 100; ++k) {
      l.in.features.alpha_z += 0.25 * 0.01;  // 0.25 rad/s, angle_rate_ref 0.5 rad/s
      l.slide();
    }
    EXPECT_NEAR(l.out.slide_speed, 0.03, 1e-4);
    EXPECT_EQ(l.out.speed_limiter, SpeedLimiter::AngleRate);
  }
  {
    Loop l(slide(true));
    l.slideFor(2.0);
    l.in.features.force = 4.75;
    l.in.features.d_z = 4.75 / 1800.0;
    l.slideFor(1.0);
    EXPECT_NEAR(l.out.slide_speed, 0.03, 1e-4);  // |0.25| / 0.5 N: a = 1/2
    EXPECT_EQ(l.out.speed_limiter, SpeedLimiter::Force);
  }
  {
    Loop l(slide(true));
    l.slideFor(2.0);
    l.in.features.lambda1 = 0.012 * 0.012 / 12.0;  // the image shrunk to a quarter of the pad
    EXPECT_NEAR(l.slide(), 0.005, 1e-9);          // at once: v_min
    EXPECT_EQ(l.out.speed_limiter, SpeedLimiter::Extent);
  }
}

// The wrench's excess (speed_law.excess_against): the arm's wrench along z_s
// 2.8 N above the taxels' 5 N, the force estimate following the wrench within
// 0.02 s (bounded at 5 N, bent_bar_speed_law.yaml's). Against the tactile
// force the excess is the load the taxels miss: 1.2 N past the 1.6 N dead
// band of 4 N, half of v_max. Against f_hat, which has taken that load in,
// there is none, and only the force error (f_hat 2.8 N above f_d, against a
// 50 N budget here) slows the slide.
TEST(ServoSpeedLaw, TheWrenchExcessIsTheLoadTheTaxelsMiss) {
  for (const bool tactile : {true, false}) {
    ServoParams p = slide(true);
    p.force_estimate.fused = true;
    p.force_estimate.tau_s = 0.02;
    p.force_estimate.max_correction_n = 5.0;
    p.speed_law.law.force_budget_n = 50.0;
    p.speed_law.law.excess_deadband_n = 1.6;
    p.speed_law.law.excess_ref_n = 4.0;
    p.speed_law.excess_against_tactile = tactile;
    Loop l(p);
    l.in.features.force = 5.0;
    l.in.have_wrench = true;
    l.in.wrench.w[2] = -7.8;
    l.slideFor(2.0);
    if (tactile) {
      EXPECT_NEAR(l.out.slide_speed, 0.03, 1e-4);
      EXPECT_EQ(l.out.speed_limiter, SpeedLimiter::WrenchExcess);
    } else {
      EXPECT_NEAR(l.out.slide_speed, 0.06 * (1.0 - 2.8 / 50.0), 1e-3);
      EXPECT_EQ(l.out.speed_limiter, SpeedLimiter::Force);
    }
  }
}

TEST(ServoSpeedLaw, AnUnknownPhaseIsNamed) {
  ServoParams p = slide(true);
  p.source = "prog.yaml";
  p.speed_law.phases = {"explroe"};
  TactileServo s;
  const ConfigResult r = s.configure(p);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("prog.yaml: speed_law.phases: no phase 'explroe'"), std::string::npos) << r.message();
  p.speed_law.phases = {"explore"};
  p.speed_law.law.v_min = 1.0;  // above v_max
  const ConfigResult r2 = s.configure(p);
  ASSERT_FALSE(r2.ok());
  EXPECT_NE(r2.message().find("speed_law.v_min"), std::string::npos) << r2.message();
}

TEST(ServoSpeedLaw, StepDoesNotAllocate) {
  Loop l(slide(true));
  l.slideFor(0.5);
  test::AllocationScope scope;
  for (int k = 0; k < 200; ++k) {
    l.in.features.alpha_z += 0.001;
    l.slide();
  }
  EXPECT_EQ(scope.count(), 0u);
}
