// Physics and timing effects of the world (WorldParams, core/sim/lwr/README.md
// "Physics and timing effects"), each against a computed expectation:
// Coulomb friction at the pad (mu N while sliding, zero at rest, the drag
// moment's sign on the pressure centre and hence DZMP_y = CoP_x - CoC_x),
// the FRI delay and the KRC sample-and-hold (sample-exact in the per-step
// series), the dynamic tray on a quasi-static arm (free oscillation period
// and decay from its inertia, spring and bearing damping), and no allocation
// in step() with every effect on.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "alloc_counter.hpp"
#include "tactile_sim_lwr/world.hpp"
#include "sim_scenes.hpp"

using namespace tactile;
using namespace tactile::sim;

namespace {
using simtest::downPose;

constexpr double kX0 = 0.58;   // start of the slide (m)
constexpr double kPress = 0.005;  // flange command below first contact (m): ~5 N on the table

// A table under the whole pad (flat contact over all 6 x 14 taxels).
WorldParams tableScene(Fidelity f, double mu) {
  WorldParams p;
  p.fidelity = f;
  const ObjectParams table = simtest::tablePlane();
  p.objects = {table};
  p.use_initial_flange_pose = true;
  p.initial_flange_pose = downPose(kX0, 0.0, 0.02 + 0.001);  // 1 mm above the table
  p.friction_mu = mu;
  return p;
}

struct SlideResult {
  SimState s;
  double cop_x = 0.0;  ///< true pressure centre of the layer, x_s (m)
  int slipping_steps = 0;
};

// Press, hold, then slide along +x_g at `speed` (command every 1 ms step).
SlideResult pressAndSlide(Fidelity f, double mu, double speed, double t_slide) {
  World w;
  const ConfigResult r = w.configure(tableScene(f, mu));
  EXPECT_TRUE(r.ok()) << r.message();
  SlideResult out;
  const double dt = 0.001;
  const double z = 0.02 - kPress;
  for (int i = 0; i < 1500; ++i) EXPECT_FALSE(fatal(w.step(downPose(kX0, 0.0, z), dt, out.s)));
  const int n = static_cast<int>(std::lround(t_slide / dt));
  for (int i = 1; i <= n; ++i) {
    EXPECT_FALSE(fatal(w.step(downPose(kX0 + speed * i * dt, 0.0, z), dt, out.s))) << toString(out.s.status);
    out.slipping_steps += out.s.slipping ? 1 : 0;
  }
  RawTactileFrame raw;
  SensorTruth truth;
  w.acquire(raw, truth);
  out.cop_x = truth.layer.cop_x;
  return out;
}

}  // namespace

// Return mapping: while sliding, |F_t| = mu N to the solver's residual.
constexpr double kFrictionTolerance = 1e-6;  // relative

TEST(EffectsFriction, SlidingAtConstantSpeedDragsWithMuTimesNormalForce) {
  const double mu = 0.5, speed = 0.01;
  for (Fidelity f : {Fidelity::QuasiStatic, Fidelity::Dynamics}) {
    const SlideResult r = pressAndSlide(f, mu, speed, 1.0);
    const SlideResult dry = pressAndSlide(f, 0.0, speed, 1.0);
    const SimState& s = r.s;
    const double N = -s.wrench_s[2];
    ASSERT_GT(N, 3.0) << toString(f);
    EXPECT_TRUE(s.slipping) << toString(f);
    // The sensor moves along +x_g = -x_s: the drag on it points along +x_s.
    EXPECT_NEAR(s.wrench_s[0], mu * N, kFrictionTolerance * mu * N) << toString(f);
    EXPECT_NEAR(s.wrench_s[1], 0.0, 1e-6 * N) << toString(f);
    // The impedance carries the drag (Eq. 11): the flange lags further
    // behind the command than without friction by mu N / k_trans along x_g
    // (k_trans 1000 N/m; in dynamics the damping's D v lag is in both runs).
    const double extra_lag = dry.s.flange_g.p[0] - s.flange_g.p[0];
    EXPECT_NEAR(extra_lag, mu * N / 1000.0, 0.01 * mu * N / 1000.0) << toString(f);
    EXPECT_EQ(dry.s.wrench_s[0], 0.0);
  }
}

TEST(EffectsFriction, AtRestWithoutTangentialLoadThereIsNoFriction) {
  for (Fidelity f : {Fidelity::QuasiStatic, Fidelity::Dynamics}) {
    const SlideResult r = pressAndSlide(f, 0.8, 0.0, 0.5);  // pressed, no slide command
    EXPECT_GT(-r.s.wrench_s[2], 3.0);
    EXPECT_FALSE(r.s.slipping) << toString(f);
    EXPECT_EQ(r.slipping_steps, 0) << toString(f);
    // Quasi-static: exactly the press, no shear. Dynamics: the press's own
    // lateral transient (the arm's coupling) leaves a small shear held by
    // the stuck layer, well below the limit.
    const double ft = std::hypot(r.s.wrench_s[0], r.s.wrench_s[1]);
    if (f == Fidelity::QuasiStatic)
      EXPECT_LT(ft, 1e-3) << toString(f);  // N
    else
      EXPECT_LT(ft, 0.02 * 0.8 * -r.s.wrench_s[2]) << toString(f);
  }
}

TEST(EffectsFriction, StickingBelowTheLimitHoldsATangentialLoad) {
  // A tangential command offset of 1 mm (1 N through k_trans) against mu N = 4 N:
  // the layer shears, nothing slides, the friction balances the impedance.
  World w;
  ASSERT_TRUE(w.configure(tableScene(Fidelity::QuasiStatic, 0.8)).ok());
  SimState s;
  const double z = 0.02 - kPress;
  for (int i = 0; i < 200; ++i) w.step(downPose(kX0, 0.0, z), 0.001, s);
  for (int i = 0; i < 200; ++i) w.step(downPose(kX0 + 0.001, 0.0, z), 0.001, s);
  EXPECT_FALSE(s.slipping);
  const double fx_g = -s.wrench_s[0];  // x_s = -x_g
  const double shift = s.flange_g.p[0] - kX0;
  // Series springs: layer shear k_t = 5000 N/m against k_trans = 1000 N/m
  // (within 3 %: the shear's moment about the flange tilts it a little).
  EXPECT_NEAR(shift, 0.001 * 1000.0 / (1000.0 + 5000.0), 0.03 * 0.001 / 6.0);
  EXPECT_NEAR(fx_g, -1000.0 * (0.001 - shift), 2e-3);
}

TEST(EffectsFriction, DragMomentShiftsThePressureCentreTowardsTheMotion) {
  // The drag acts at the surface, 20 mm from the flange: its moment about the
  // flange, 0.02 mu N about y_s, is shared by the arm's rotational impedance
  // (k_rot 100 N m/rad) and the layer under the flat pad (k_c = modulus *
  // integral of x^2 dA = 5e7 * 20.4 mm * 47.6^3 mm^3 / 12 = 9.2 N m/rad): the
  // layer's share shifts the pressure centre by -0.02 mu k_c / (k_c + k_rot)
  // (~ -0.84 mm at mu 0.5) towards the leading edge, along -x_s (the sensor
  // moves along -x_s). With a full-area contact CoC_x stays 0: DZMP_y = CoP_x
  // shifts by the same amount, negative.
  const double mu = 0.5;
  const SlideResult dry = pressAndSlide(Fidelity::QuasiStatic, 0.0, 0.01, 1.0);
  const SlideResult wet = pressAndSlide(Fidelity::QuasiStatic, mu, 0.01, 1.0);
  EXPECT_NEAR(dry.cop_x, 0.0, 2e-5);
  const double kc = 5e7 * 0.0204 * std::pow(0.0476, 3) / 12.0;
  const double expected = -0.02 * mu * kc / (kc + 100.0);
  EXPECT_LT(wet.cop_x - dry.cop_x, 0.0);
  EXPECT_NEAR(wet.cop_x - dry.cop_x, expected, 0.25 * std::fabs(expected));
}

TEST(EffectsTiming, FriDelayAndKrcCycleShiftACommandStepSampleExactly) {
  struct Case {
    double delay, krc;
  };
  for (Fidelity f : {Fidelity::QuasiStatic, Fidelity::Dynamics}) {
    for (Case c : {Case{0.0, 0.0}, Case{0.002, 0.0}, Case{0.0, 0.002}, Case{0.003, 0.002}, Case{0.0015, 0.0}}) {
      WorldParams p = tableScene(f, 0.0);
      p.objects.clear();  // free space
      p.physics_step_s = 0.0005;  // 2 kHz: 1.5 ms is 3 steps
      p.fri_delay_s = c.delay;
      p.krc_cycle_s = c.krc;
      World w;
      ASSERT_TRUE(w.configure(p).ok());
      const Pose p0 = toPose(w.state().T_ge);
      Pose p1 = p0;
      p1.p[0] += 0.001;
      const long i0 = 11, D = std::lround(c.delay / 0.0005), H = std::max(1L, std::lround(c.krc / 0.0005));
      // Expected: the first step i whose KRC sample instant (i - i mod H) sees command i - D >= i0.
      long expected = i0;
      while ((expected - expected % H) - D < i0) ++expected;
      SimState s;
      long first_set = -1, first_move = -1;
      for (long i = 0; i < 40; ++i) {
        w.step(i < i0 ? p0 : p1, 0.0005, s);
        if (first_set < 0 && s.setpoint_g.p[0] != p0.p[0]) first_set = i;
        if (first_move < 0 && std::fabs(s.flange_g.p[0] - p0.p[0]) > 1e-9) first_move = i;
        EXPECT_EQ(s.command_g.p[0], (i < i0 ? p0 : p1).p[0]);  // the command as given, undelayed
      }
      EXPECT_EQ(first_set, expected) << toString(f) << " delay " << c.delay << " krc " << c.krc;
      EXPECT_EQ(first_move, expected) << toString(f) << " delay " << c.delay << " krc " << c.krc;
    }
  }
}

TEST(EffectsTiming, DelayMustBeWholePhysicsSteps) {
  WorldParams p = tableScene(Fidelity::QuasiStatic, 0.0);
  p.fri_delay_s = 0.0015;  // 1.5 steps at 1 kHz
  World w;
  ConfigResult r = w.configure(p);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("effects.fri_delay_s"), std::string::npos) << r.message();
  EXPECT_NE(r.message().find("whole number of physics steps"), std::string::npos) << r.message();
  p.fri_delay_s = 0.0;
  p.krc_cycle_s = -1.0;
  r = w.configure(p);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("effects.krc_cycle_s"), std::string::npos) << r.message();
  p.krc_cycle_s = 0.0;
  p.physics_step_s = 2.0;  // the 2 s physics step
  r = w.configure(p);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("physics_step_s"), std::string::npos) << r.message();
  EXPECT_NE(r.message().find("(0, max_step_s = 0.01"), std::string::npos) << r.message();
}

namespace {
// A tray whose bar is far from the sensor (no contact): its roll is a damped
// oscillator, I theta'' + c theta' + k theta = 0 (gravity gives no roll
// torque: the masses lie on the roll axis' plane through the bearing).
WorldParams freeTray(bool dynamic_tray) {
  WorldParams p;
  p.fidelity = Fidelity::QuasiStatic;
  p.tray_dynamics = dynamic_tray;
  p.start_in_equilibrium = false;
  p.arm.q_init = {-0.693, -1.694, -1.470, -1.416, 1.434, 1.491, -0.711};  // flange up near (0.6, 0, 0.37)
  ObjectParams tray;
  tray.name = "tray";
  tray.type = ObjectType::Tray;
  tray.tray.mass_to = tray.tray.mass_from;  // no move
  tray.tray.roll_stiffness = 1.0;           // N m/rad
  tray.tray.pitch_stiffness = 100.0;
  tray.tray.inertia_x = 0.05;
  tray.tray.inertia_y = 0.01;               // kg m^2
  tray.tray.bearing_damping = 0.02;         // N m s/rad
  tray.tray.initial_roll = 0.05;
  p.objects = {tray};
  p.use_initial_flange_pose = true;
  p.initial_flange_pose.p = {0.6, 0.0, 0.33};  // sensor 4 cm below the bar: the arm just holds
  p.physics_step_s = 0.0002;
  return p;
}
}  // namespace

TEST(EffectsTrayFidelity, DynamicTrayOnAQuasiStaticArmOscillatesWithItsOwnPeriodAndDecay) {
  World w;
  const ConfigResult r = w.configure(freeTray(true));
  ASSERT_TRUE(r.ok()) << r.message();
  const double dt = 0.0002;
  const Pose hold = toPose(w.state().T_ge);
  SimState s;
  std::vector<double> t_up, peaks;  // upward zero crossings (interpolated), positive peaks
  double prev = w.state().tray_roll, prev2 = prev;
  for (int i = 1; i <= 15000; ++i) {
    ASSERT_FALSE(fatal(w.step(hold, dt, s)));
    const double th = s.tray_roll;
    if (prev < 0.0 && th >= 0.0) t_up.push_back(s.time_s - dt * th / (th - prev));
    if (i > 2 && prev > prev2 && prev >= th && prev > 0.0) peaks.push_back(prev);
    prev2 = prev;
    prev = th;
    EXPECT_EQ(s.normal_force, 0.0);
  }
  // I = 0.01, k = 1, c = 0.02: omega_n = 10 rad/s, zeta = c / (2 sqrt(k I)) = 0.1,
  // T_d = 2 pi / (omega_n sqrt(1 - zeta^2)) = 0.63148 s, peak ratio exp(-zeta omega_n T_d).
  const double wn = 10.0, zeta = 0.1, Td = 2.0 * kPi / (wn * std::sqrt(1.0 - zeta * zeta));
  ASSERT_GE(t_up.size(), 3u);
  ASSERT_GE(peaks.size(), 3u);
  const double T_meas = (t_up.back() - t_up.front()) / static_cast<double>(t_up.size() - 1);
  EXPECT_NEAR(T_meas, Td, 0.002 * Td);
  // Decay rate zeta * omega_n = 1 /s; backward Euler adds ~omega_n^2 dt / 2 = 0.01 /s.
  const double rate = std::log(peaks.front() / peaks.back()) / (Td * static_cast<double>(peaks.size() - 1));
  EXPECT_NEAR(rate, zeta * wn, 0.03 * zeta * wn);
  EXPECT_NEAR(peaks.front(), 0.05 * std::exp(-zeta * wn * Td), 0.03 * 0.05);

  // The same tray at the arm's fidelity (quasi-static, solved with the arm):
  // at its static equilibrium (roll 0) from the first step, no oscillation.
  World q;
  ASSERT_TRUE(q.configure(freeTray(false)).ok());
  q.step(hold, dt, s);
  EXPECT_NEAR(s.tray_roll, 0.0, 1e-6);
}

TEST(EffectsAllocation, StepDoesNotAllocateWithEveryEffectOn) {
  std::vector<WorldParams> scenes;
  for (Fidelity f : {Fidelity::QuasiStatic, Fidelity::Dynamics}) {
    WorldParams p = tableScene(f, 0.6);
    p.fri_delay_s = 0.002;
    p.krc_cycle_s = 0.002;
    scenes.push_back(p);
  }
  WorldParams t = freeTray(true);
  t.friction_mu = 0.6;
  t.fri_delay_s = 0.001;
  scenes.push_back(t);
  for (const WorldParams& p : scenes) {
    World w;
    ConfigResult r = w.configure(p);
    ASSERT_TRUE(r.ok()) << r.message();
    Pose cmd = toPose(w.state().T_ge);
    SimState s;
    RawTactileFrame raw;
    SensorTruth truth;
    const double dt = p.physics_step_s;
    tactile::test::AllocationScope scope;
    for (int i = 0; i < 300; ++i) {
      cmd.p[2] -= 2e-5;  // into contact (the table scenes)
      if (i > 150) cmd.p[0] += 1e-5;  // and sliding
      w.step(cmd, dt, s);
      if (i % 7 == 0) w.acquire(raw, truth);
    }
    EXPECT_EQ(scope.count(), 0u) << toString(p.fidelity);
    EXPECT_FALSE(fatal(s.status)) << toString(s.status);
  }
}
