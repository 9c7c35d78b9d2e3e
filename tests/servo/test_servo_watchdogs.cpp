// The servo's watchdogs (tactile_servo/watchdog.hpp): a phase that never
// ends, an arm that does not follow, a tactile force the estimated wrench
// contradicts. Each latches a named status and holds the command; each is
// checked against the case it must catch and the one it must let pass, at
// 100 Hz and 1 kHz, without allocation.
#include <set>
#include <string>

#include "alloc_counter.hpp"
#include "temp_file.hpp"
#include "tactile_servo/program_io.hpp"
#include "servo_test_util.hpp"

using namespace tactile;
using namespace servo_test;

namespace {

// A free-motion phase (P = 0) following 10 mm/s along +z_s, then a terminal one.
ServoParams freeMotion() {
  PhaseParams a = identityPhase("move", 0.0, 0.0);
  a.P = Mat6::Zero();
  a.feedforward(kZ) = 0.01;
  a.requires_contact = false;
  PhaseParams b = identityPhase("done", 0.0, 0.0);
  b.terminal = true;
  b.requires_contact = false;
  TransitionParams t;
  t.on = TransitionEvent::ForceAbove;
  t.force_n = 1e3;
  t.to = "done";
  a.transitions.push_back(t);
  ServoParams p;
  p.phases = {a, b};
  return p;
}

struct Loop : ServoLoop {
  explicit Loop(const ServoParams& p) : ServoLoop(p, makeFeatures(0, 0, 0, 0, 0, 0, 0, ContactType::None)) {}
};

}  // namespace

TEST(ServoWatchdogs, PhaseTimeoutAfterMaxDurationNotBeforeAndNotOnATimeoutTransition) {
  for (double dt : {0.01, 0.001}) {
    ServoParams p = freeMotion();
    p.phases[0].max_duration_s = 0.5;
    Loop l(p);
    ASSERT_EQ(l.step(dt), ServoStatus::Starting);
    EXPECT_EQ(l.run(0.49, dt, ServoStatus::PhaseTimeout), ServoStatus::FreeMotion) << dt;
    EXPECT_EQ(l.run(0.03, dt, ServoStatus::PhaseTimeout), ServoStatus::PhaseTimeout) << dt;
    EXPECT_NEAR(l.t - dt - l.s.program().enteredAt(), 0.5, dt + 1e-9);
    // Latched, the command held; a phase request clears it.
    const Pose held = l.out.command.pose;
    EXPECT_EQ(l.step(dt), ServoStatus::PhaseTimeout);
    EXPECT_EQ(l.out.command.pose.p, held.p);
    EXPECT_TRUE(l.s.requestPhase("move"));
    EXPECT_EQ(l.step(dt), ServoStatus::FreeMotion);
  }
  // A `timeout` transition (a normal event) before max_duration_s: no PhaseTimeout.
  ServoParams p = freeMotion();
  p.phases[0].max_duration_s = 0.5;
  p.phases[0].transitions[0].on = TransitionEvent::Timeout;
  p.phases[0].transitions[0].timeout_s = 0.3;
  p.phases[1].max_duration_s = 0.1;  // terminal: never times out
  Loop l(p);
  l.step(0.01);
  EXPECT_EQ(l.run(2.0, 0.01, ServoStatus::PhaseTimeout), ServoStatus::Done);
}

TEST(ServoWatchdogs, ArmStalledWhenTheMeasuredPoseDoesNotFollow) {
  for (double dt : {0.01, 0.001}) {
    // The arm follows: 5 s of free motion, no stall.
    Loop ok(freeMotion());
    ok.step(dt);
    EXPECT_EQ(ok.run(5.0, dt, ServoStatus::ArmStalled), ServoStatus::FreeMotion) << dt;
    // The arm does not move: stalled after one window (1 s) of commanded motion.
    Loop stuck(freeMotion());
    stuck.arm_follows = false;
    stuck.step(dt);
    EXPECT_EQ(stuck.run(0.95, dt, ServoStatus::ArmStalled), ServoStatus::FreeMotion) << dt;
    EXPECT_EQ(stuck.run(0.2, dt, ServoStatus::ArmStalled), ServoStatus::ArmStalled) << dt;
    EXPECT_EQ(stuck.step(dt), ServoStatus::ArmStalled);  // latched
    // Moving at a tenth of the commanded speed is a stall too (min_fraction 0.2).
    Loop slow(freeMotion());
    slow.arm_follows = false;
    slow.step(dt);
    ServoStatus st = ServoStatus::FreeMotion;
    for (int k = 0; k < static_cast<int>(std::lround(1.5 / dt)) && st != ServoStatus::ArmStalled; ++k) {
      const Pose before = slow.in.flange_measured;
      st = slow.step(dt);
      slow.in.flange_measured.p[2] = before.p[2] + 0.1 * slow.out.u_s(kZ);  // z_s = z_g here
    }
    EXPECT_EQ(st, ServoStatus::ArmStalled) << dt;
  }
  // Switched off (window 0): the stuck arm goes unnoticed.
  ServoParams p = freeMotion();
  p.watchdogs.stall_window_s = 0.0;
  Loop off(p);
  off.arm_follows = false;
  off.step(0.01);
  EXPECT_EQ(off.run(3.0, 0.01, ServoStatus::ArmStalled), ServoStatus::FreeMotion);
}

TEST(ServoWatchdogs, ForceMismatchAgainstTheEstimatedWrench) {
  // A contact phase holding the features constant (the arm follows a zero increment).
  auto contactLoop = [](double tactile_n, double wrench_n, bool contact, bool have_wrench, double dt) {
    ServoParams p = freeMotion();
    p.phases[0].feedforward.setZero();
    Loop l(p);
    l.in.features = makeFeatures(0, 0, 0, tactile_n / 1800.0, 0, 0, 0,
                                 contact ? ContactType::Edge : ContactType::None);
    l.in.features.force = contact ? tactile_n : 0.0;
    // The sensor's z axis is z_g here (identity mount and orientation); the
    // estimate's sign convention does not matter (|F . z_s|).
    l.in.wrench.w = {0.3, -0.2, -wrench_n, 0, 0, 0};
    l.in.have_wrench = have_wrench;
    l.step(dt);
    return l.run(2.0, dt, ServoStatus::ForceMismatch);
  };
  for (double dt : {0.01, 0.001}) {
    // The soft-pad case: 5 N measured, 46 N on the arm.
    EXPECT_EQ(contactLoop(5.0, 46.0, true, true, dt), ServoStatus::ForceMismatch) << dt;
    // Agreement within the shipped experiments' ~1 N: fine.
    EXPECT_NE(contactLoop(5.0, 6.2, true, true, dt), ServoStatus::ForceMismatch) << dt;
    EXPECT_NE(contactLoop(20.0, 26.0, true, true, dt), ServoStatus::ForceMismatch) << dt;  // 30 % of 26 N
    // No tactile contact, but the arm carries 20 N (the housing): an unseen load
    // (its own status); 5 N: fine.
    EXPECT_EQ(contactLoop(0.0, 20.0, false, true, dt), ServoStatus::UnseenLoad) << dt;
    EXPECT_FALSE(watchdogStatus(contactLoop(0.0, 5.0, false, true, dt))) << dt;
    // No wrench input (port unconnected): the check is off.
    EXPECT_NE(contactLoop(5.0, 46.0, true, false, dt), ServoStatus::ForceMismatch) << dt;
  }
  // A mismatch shorter than the window (0.5 s) does not trip.
  ServoParams p = freeMotion();
  p.phases[0].feedforward.setZero();
  Loop l(p);
  l.in.features = makeFeatures(0, 0, 0, 5.0 / 1800.0, 0, 0, 0, ContactType::Edge);
  l.in.features.force = 5.0;
  l.in.have_wrench = true;
  l.step(0.01);
  for (int k = 0; k < 300; ++k) {
    l.in.wrench.w[2] = (k / 40) % 2 ? -46.0 : -5.0;  // 0.4 s on, 0.4 s off
    ASSERT_NE(l.step(0.01), ServoStatus::ForceMismatch) << k;
  }
  // A stale wrench (older than stale_timeout) is not used.
  Loop stale(p);
  stale.in.features = l.in.features;
  stale.in.have_wrench = true;
  stale.in.wrench.w[2] = -46.0;
  stale.step(0.01);
  for (int k = 0; k < 200; ++k) {
    stale.in.time_s = stale.in.features.time_s = stale.t;
    stale.in.wrench.time_s = stale.t - 1.0;
    ASSERT_NE(stale.s.step(stale.in, 0.01, stale.out), ServoStatus::ForceMismatch);
    stale.t += 0.01;
  }
}

TEST(ServoWatchdogs, ProgramKeysAndRangesNamed) {
  ServoParams p = freeMotion();
  p.source = "prog.yaml";
  TactileServo s;
  ServoParams q = p;
  q.watchdogs.stall_min_fraction = 0.0;
  EXPECT_NE(s.configure(q).message().find("prog.yaml: watchdogs.arm_stall.min_fraction"), std::string::npos);
  q = p;
  q.watchdogs.mismatch_tolerance_n = -1.0;
  EXPECT_NE(s.configure(q).message().find("watchdogs.force_mismatch.tolerance_n"), std::string::npos);
  q = p;
  q.watchdogs.phantom_window_s = -0.1;
  EXPECT_NE(s.configure(q).message().find("prog.yaml: watchdogs.phantom_contact.window_s"), std::string::npos);
  q = p;
  q.watchdogs.phantom_tolerance_rel = 1.5;
  EXPECT_NE(s.configure(q).message().find("watchdogs.phantom_contact.tolerance_rel"), std::string::npos);
  q = p;
  q.watchdogs.unseen_max_n = 0.0;
  EXPECT_NE(s.configure(q).message().find("watchdogs.unseen_load.max_n"), std::string::npos);
  q = p;
  q.watchdogs.correction_window_s = 61.0;
  EXPECT_NE(s.configure(q).message().find("watchdogs.correction_saturated.window_s"), std::string::npos);
  q = p;
  q.watchdogs.correction_margin_n = -1.0;
  EXPECT_NE(s.configure(q).message().find("watchdogs.correction_saturated.margin_n"), std::string::npos);
  q = p;
  q.watchdogs.drift_max_change_n = 51.0;
  EXPECT_NE(s.configure(q).message().find("watchdogs.correction_drift.max_change_n"), std::string::npos);
  q = p;
  q.watchdogs.drift_tau_s = 0.0;
  EXPECT_NE(s.configure(q).message().find("watchdogs.correction_drift.tau_s = 0: must be in (0, 10] s"), std::string::npos)
      << s.configure(q).message();
  q = p;
  q.watchdogs.drift_settle_s = -1.0;
  EXPECT_NE(s.configure(q).message().find("watchdogs.correction_drift.settle_s"), std::string::npos);
  q = p;
  q.watchdogs.drift_min_extent_ratio = 0.0;
  EXPECT_NE(s.configure(q).message().find("watchdogs.correction_drift.min_extent_ratio = 0: must be in (0, 1]"),
            std::string::npos);
  q = p;
  q.watchdogs.fault_retreat_m = 0.2;
  const std::string m = s.configure(q).message();
  EXPECT_NE(m.find("watchdogs.retreat_m"), std::string::npos) << m;
  EXPECT_NE(m.find("[0, 0.1] m"), std::string::npos) << m;
  q = p;
  q.phases[0].max_duration_s = -1.0;
  EXPECT_NE(s.configure(q).message().find("phases.move.max_duration_s"), std::string::npos);
  // The shipped programs' defaults.
  const ServoParams e = loadShipped("edge_exploration.yaml");
  EXPECT_DOUBLE_EQ(e.watchdogs.stall_window_s, 1.0);
  EXPECT_DOUBLE_EQ(e.watchdogs.mismatch_window_s, 0.5);
}

TEST(ServoWatchdogs, NoAllocationPerCycle) {
  ServoParams p = freeMotion();
  p.phases[0].max_duration_s = 3.0;
  Loop l(p);
  l.arm_follows = false;
  l.in.have_wrench = true;
  l.step(0.01);
  tactile::test::AllocationScope scope;
  int fired = 0;
  for (int k = 0; k < 2000; ++k) {
    l.in.features = makeFeatures(l.t, 0, 0, 0.002, 0, 0, 0, k % 7 ? ContactType::Edge : ContactType::None);
    l.in.wrench.w[2] = k % 300 < 150 ? -3.6 : -40.0;
    const ServoStatus st = l.step(0.01);
    if (watchdogStatus(st)) {
      ++fired;
      l.s.requestPhase(0);
    }
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_GT(fired, 0);
}

// Surface too curved (watchdog.hpp): the wrench along z_s, low-passed with
// tau_s, above the set point by more than excess_n while the image is short,
// carries at most its share of the wrench, or is gone. The trip cycle is the
// first k with (f_w - f_d) (1 - exp(-k dt / tau)) > excess_n, at 100 Hz and 1 kHz.
TEST(ServoWatchdogs, SurfaceTooCurvedWhenTheWrenchExceedsTheSetPointOffTheImage) {
  ServoParams p = freeMotion();
  p.source = "prog.yaml";
  {
    ServoWatchdogs off;  // the default: off
    ASSERT_TRUE(off.configure(p).ok());
    for (int k = 0; k < 100; ++k) ASSERT_FALSE(off.surfaceTooCurved(40.0, 5.0, true, false, 0.0, 0.0, true, 0.01));
  }
  p.watchdogs.curved_tau_s = 0.05;
  p.watchdogs.curved_excess_n = 1.2;
  p.watchdogs.curved_max_extent_m = 0.0238;
  p.watchdogs.curved_max_tactile_share = 0.5;
  // (f_w, contact, f, extent): the cycle it trips on, -1 = never (2 s).
  struct Case {
    double f_w;
    bool contact;
    double f, extent;
    bool trips;
  };
  const Case cases[] = {
      {7.0, true, 4.0, 0.012, true},    // the image shrunk to a quarter of the pad
      {7.0, true, 1.0, 0.070, true},    // a trough bridged: taxels at both ends, 1 N of 7
      {7.0, false, 0.0, 0.0, true},     // no taxel fires
      {7.0, true, 4.0, 0.040, false},   // a long image carrying 57 % of the wrench: not this watchdog's case
      {6.1, true, 1.0, 0.012, false},   // 1.1 N above the set point: within excess_n
  };
  for (double dt : {0.01, 0.001}) {
    for (const Case& c : cases) {
      ServoWatchdogs w;
      ASSERT_TRUE(w.configure(p).ok());
      // The filter starts from no excess; a first sample at the set point,
      // as after a contact at f_d, leaves it there.
      ASSERT_FALSE(w.surfaceTooCurved(5.0, 5.0, true, true, 5.0, 0.04, true, dt));
      int tripped = -1;
      for (int k = 1; k <= static_cast<int>(2.0 / dt) && tripped < 0; ++k)
        if (w.surfaceTooCurved(c.f_w, 5.0, true, c.contact, c.f, c.extent, true, dt)) tripped = k;
      if (!c.trips) {
        EXPECT_EQ(tripped, -1) << dt << " " << c.f_w << " " << c.f << " " << c.extent;
        continue;
      }
      const int expected = static_cast<int>(std::ceil(-0.05 * std::log(1.0 - 1.2 / (c.f_w - 5.0)) / dt - 1e-9));
      EXPECT_EQ(tripped, expected) << dt << " " << c.f << " " << c.extent;
      EXPECT_EQ(w.latched(), ServoStatus::SurfaceTooCurved);
      EXPECT_STREQ(toString(w.latched()), "surface_too_curved");
      EXPECT_TRUE(watchdogStatus(w.latched()));
    }
  }
  // The filter starts from no excess: at the first contact, one sample of
  // the wrench's noise well above excess_n (2.5 N over f_d, the image a
  // single taxel) does not stop the run; the same excess held does, on the
  // cycle the formula above gives counting that first sample.
  for (double dt : {0.01, 0.001}) {
    ServoWatchdogs w;
    ASSERT_TRUE(w.configure(p).ok());
    EXPECT_FALSE(w.surfaceTooCurved(7.5, 5.0, true, true, 0.2, 0.0, true, dt));
    EXPECT_FALSE(w.surfaceTooCurved(5.0, 5.0, true, true, 3.0, 0.0, true, dt));
    ServoWatchdogs held;
    ASSERT_TRUE(held.configure(p).ok());
    int tripped = -1;
    for (int k = 1; k <= static_cast<int>(2.0 / dt) && tripped < 0; ++k)
      if (held.surfaceTooCurved(7.5, 5.0, true, true, 0.2, 0.0, true, dt)) tripped = k;
    EXPECT_EQ(tripped, static_cast<int>(std::ceil(-0.05 * std::log(1.0 - 1.2 / 2.5) / dt - 1e-9))) << dt;
  }
  // A phase that holds no force set point restarts the filter; a stale wrench holds it.
  ServoWatchdogs w;
  ASSERT_TRUE(w.configure(p).ok());
  for (int k = 0; k < 200; ++k) ASSERT_FALSE(w.surfaceTooCurved(40.0, 0.0, false, false, 0.0, 0.0, true, 0.01));
  ASSERT_FALSE(w.surfaceTooCurved(5.0, 5.0, true, true, 5.0, 0.04, true, 0.01));
  for (int k = 0; k < 200; ++k) ASSERT_FALSE(w.surfaceTooCurved(40.0, 5.0, true, false, 0.0, 0.0, false, 0.01));
  // Ranges, naming the file and the key.
  TactileServo s;
  ServoParams q = p;
  q.watchdogs.curved_tau_s = -1.0;
  EXPECT_NE(s.configure(q).message().find("prog.yaml: watchdogs.surface_too_curved.tau_s"), std::string::npos);
  q = p;
  q.watchdogs.curved_excess_n = 0.0;
  EXPECT_NE(s.configure(q).message().find("watchdogs.surface_too_curved.excess_n"), std::string::npos);
  q = p;
  q.watchdogs.curved_max_tactile_share = 1.5;
  EXPECT_NE(s.configure(q).message().find("watchdogs.surface_too_curved.max_tactile_share"), std::string::npos);
  // The shipped bent bar (fused) has it on, the paper's programs not.
  EXPECT_DOUBLE_EQ(loadShipped("bent_bar_to_end_cap.yaml").watchdogs.curved_tau_s, 0.05);
  EXPECT_DOUBLE_EQ(loadShipped("bent_bar.yaml").watchdogs.curved_tau_s, 0.0);
}

// The first reaction (surface_too_curved.lift_n): while the image is short and
// the low-passed excess is above lift_n, curvedLift() is that excess (the law
// then holds f_d + it); 0 with a long image carrying its share, below lift_n,
// or with lift_n 0.
TEST(ServoWatchdogs, SurfaceTooCurvedLiftsByTheExcessBeforeItStops) {
  ServoParams p = freeMotion();
  p.watchdogs.curved_tau_s = 0.05;
  p.watchdogs.curved_excess_n = 1.2;
  p.watchdogs.curved_lift_n = 0.4;
  ServoWatchdogs w;
  ASSERT_TRUE(w.configure(p).ok());
  ASSERT_FALSE(w.surfaceTooCurved(5.0, 5.0, true, true, 5.0, 0.04, true, 0.01));
  EXPECT_EQ(w.curvedLift(), 0.0);
  // 1 N of excess, the image a quarter of the pad: the filter settles at 1 N
  // (below excess_n: no stop) and the lift follows it once above 0.4 N.
  double lift = 0.0;
  for (int k = 0; k < 100; ++k) {
    ASSERT_FALSE(w.surfaceTooCurved(6.0, 5.0, true, true, 1.0, 0.012, true, 0.01)) << k;
    lift = w.curvedLift();
    if (k == 0) {
      EXPECT_EQ(lift, 0.0);  // 1 - exp(-0.2) of 1 N = 0.18 N < 0.4 N
    }
  }
  EXPECT_NEAR(lift, 1.0, 1e-6);  // 1 s = 20 tau
  // A long image carrying its share: no lift.
  ASSERT_FALSE(w.surfaceTooCurved(6.0, 5.0, true, true, 4.0, 0.04, true, 0.01));
  EXPECT_EQ(w.curvedLift(), 0.0);
  // lift_n 0: off.
  p.watchdogs.curved_lift_n = 0.0;
  ServoWatchdogs off;
  ASSERT_TRUE(off.configure(p).ok());
  for (int k = 0; k < 100; ++k) ASSERT_FALSE(off.surfaceTooCurved(6.0, 5.0, true, true, 1.0, 0.012, true, 0.01));
  EXPECT_EQ(off.curvedLift(), 0.0);
  // Range, naming the key.
  p.watchdogs.curved_lift_n = -1.0;
  TactileServo s;
  EXPECT_NE(s.configure(p).message().find("watchdogs.surface_too_curved.lift_n"), std::string::npos);
  EXPECT_DOUBLE_EQ(loadShipped("bent_bar_to_end_cap.yaml").watchdogs.curved_lift_n, 0.4);
}

// What the operator reads (tactile_sim, the deployments' state machines
// through ServoComponent::statusText()): every status has its own sentence, and
// each watchdog's names what happened.
TEST(ServoWatchdogs, EveryStatusExplainedToTheOperator) {
  std::set<std::string> seen;
  for (int k = 0; k <= static_cast<int>(kLastServoStatus); ++k) {
    if (k == 9) continue;  // no status has the value 9
    const ServoStatus s = static_cast<ServoStatus>(k);
    EXPECT_STRNE(toString(s), "unknown") << k;
    const std::string text = explain(s);
    EXPECT_NE(text, "unknown status") << toString(s);
    EXPECT_TRUE(seen.insert(text).second) << toString(s) << ": the same sentence as another status";
  }
  EXPECT_EQ(std::string(explain(static_cast<ServoStatus>(99))), "unknown status");
  EXPECT_NE(std::string(explain(ServoStatus::SurfaceTooCurved)).find("curves more tightly than the rigid pad"),
            std::string::npos);
  EXPECT_NE(std::string(explain(ServoStatus::ForceMismatch)).find("estimated wrench"), std::string::npos);
  EXPECT_NE(std::string(explain(ServoStatus::ArmStalled)).find("did not follow"), std::string::npos);
  EXPECT_NE(std::string(explain(ServoStatus::PhaseTimeout)).find("max_duration_s"), std::string::npos);
  EXPECT_NE(std::string(explain(ServoStatus::PhantomContact)).find("does not carry"), std::string::npos);
  EXPECT_NE(std::string(explain(ServoStatus::UnseenLoad)).find("no taxel sees"), std::string::npos);
  EXPECT_NE(std::string(explain(ServoStatus::CorrectionSaturated)).find("max_correction_n"), std::string::npos);
  for (ServoStatus s : {ServoStatus::PhantomContact, ServoStatus::UnseenLoad, ServoStatus::CorrectionSaturated})
    EXPECT_TRUE(watchdogStatus(s)) << toString(s);
}

// ---- The two sensors against each other ---------------------------------------
namespace {

// A contact phase that chases the CoP (x_s, y_s at 1/s) and holds 5 N along
// z_s: the phase a phantom contact would drive the arm in (align, explore).
// The tactile force f and the wrench along z_s are the test's inputs; the arm
// follows the command.
struct SensorLoop : ServoLoop {
  SensorLoop(const ServoParams& p, double f_n, double cop_m)
      : ServoLoop(p, makeFeatures(0, cop_m, cop_m, f_n / 1800.0, 0, 0, 0, ContactType::Edge)) {
    in.have_wrench = true;
  }
  /// Sets the arm's wrench along z_s (N; the KRC's sign: the load pushes the pad back).
  void wrench(double n) { in.wrench.w = {0.2, -0.1, -n, 0, 0, 0}; }
};

ServoParams chaseCop(bool fused, double max_correction_n) {
  PhaseParams a = identityPhase("align", 0.01, 0.0);  // K_P = 1/s
  a.s_d(kZ) = 5.0 / 1800.0;
  a.requires_contact = true;
  ServoParams p = singlePhase(a);
  p.safety.max_trans_speed = 0.05;  // the shipped 50 mm/s
  p.force_estimate.fused = fused;
  p.force_estimate.max_correction_n = max_correction_n;
  p.force_estimate.tau_s = 0.1;
  return p;
}

}  // namespace

// The pad reads a steady 8 N (a stuck region, `wts_sim --pattern blob`) that
// the wrench does not carry. Fused, the correction moves toward the wrench by
// its whole bound (4.5 N), and f_hat = f + c came within the old 4 N
// tolerance of the wrench: the check must compare the taxels' own f. Stopped
// within the 0.05 s window, before the arm travels 3 mm (50 mm/s x 0.06 s).
TEST(ServoSensorChecks, PhantomContactStopsBeforeTheArmTravels) {
  for (bool fused : {false, true}) {
    for (double dt : {0.01, 0.001}) {
      SensorLoop l(chaseCop(fused, 4.5), 8.0, 0.01);
      l.wrench(0.0);
      ASSERT_EQ(l.step(dt), ServoStatus::Starting);
      const Pose start = l.in.flange_measured;
      const ServoStatus st = l.run(2.0, dt, ServoStatus::PhantomContact);
      EXPECT_EQ(st, ServoStatus::PhantomContact) << fused << " " << dt;
      EXPECT_LE(l.t, 0.05 + 3 * dt + 1e-9) << fused << " " << dt;
      EXPECT_LT(transDist(start, l.in.flange_measured), 0.003) << fused << " " << dt;
      // Latched and held (on_fault: hold).
      const Pose held = l.out.command.pose;
      for (int k = 0; k < 10; ++k) EXPECT_EQ(l.step(dt), ServoStatus::PhantomContact);
      EXPECT_EQ(transDist(held, l.out.command.pose), 0.0);
    }
  }
}

// The paper's tactile-only set-up with no wrench at all (the port
// unconnected): no sensor check can run, and a phantom press is chased. What
// bounds the arm then is the workspace box (here 20 mm around the start: the
// command never leaves it) and the phase timeout (here 2 s: a named stop).
TEST(ServoSensorChecks, WithoutAWrenchTheBoxAndThePhaseTimeoutBoundAPhantom) {
  const double dt = 0.01;
  ServoParams p = chaseCop(false, 4.5);
  p.phases[0].max_duration_s = 2.0;
  p.safety.workspace_min = {0.49, -0.01, 0.29};
  p.safety.workspace_max = {0.51, 0.01, 0.31};
  SensorLoop l(p, 8.0, 0.01);  // the press 10 mm off centre: the arm chases it
  l.in.have_wrench = false;
  ASSERT_EQ(l.step(dt), ServoStatus::Starting);
  const Pose start = l.in.flange_measured;
  double travel = 0.0;
  ServoStatus st = ServoStatus::Ok;
  while (l.t < 5.0 && !watchdogStatus(st)) {
    st = l.step(dt);
    travel = std::max(travel, transDist(start, l.out.command.pose));
    const KDL::Vector p_cmd = toFrame(l.out.command.pose).p;
    ASSERT_GE(p_cmd.x(), 0.49 - 1e-9);
    ASSERT_LE(p_cmd.x(), 0.51 + 1e-9);
    ASSERT_GE(p_cmd.y(), -0.01 - 1e-9);
    ASSERT_LE(p_cmd.y(), 0.01 + 1e-9);
  }
  EXPECT_EQ(st, ServoStatus::PhaseTimeout);
  EXPECT_NEAR(l.t - dt, 2.0 + dt, 2 * dt);
  EXPECT_GT(travel, 0.005);  // it did chase the press: nothing else stopped it
}

TEST(ServoSensorChecks, AgreeingSensorsAndShortContradictionsPass) {
  const double dt = 0.01;
  // The wrench within the tolerance below the taxels: max(2 N, 40 %).
  for (double w : {3.5, 5.0, 7.0}) {
    SensorLoop l(chaseCop(true, 4.5), 5.0, 0.0);
    l.wrench(w);
    l.step(dt);
    EXPECT_FALSE(watchdogStatus(l.run(3.0, dt, ServoStatus::PhantomContact))) << w;
  }
  // 8 N against 4.5 N (3.5 N > 3.2 N): a phantom; against 5 N (3 N < 3.2 N): agreement.
  SensorLoop bad(chaseCop(false, 4.5), 8.0, 0.0);
  bad.wrench(4.5);
  bad.step(dt);
  EXPECT_EQ(bad.run(1.0, dt, ServoStatus::PhantomContact), ServoStatus::PhantomContact);
  SensorLoop ok(chaseCop(false, 4.5), 8.0, 0.0);
  ok.wrench(5.0);
  ok.step(dt);
  EXPECT_FALSE(watchdogStatus(ok.run(1.0, dt, ServoStatus::PhantomContact)));
  // A contradiction shorter than the window (0.04 s of every 0.2 s) passes.
  SensorLoop flick(chaseCop(false, 4.5), 8.0, 0.0);
  flick.step(dt);
  for (int k = 0; k < 300; ++k) {
    flick.wrench(k % 20 < 4 ? 0.0 : 8.0);
    ASSERT_FALSE(watchdogStatus(flick.step(dt))) << k;
  }
}

// The fused estimate bridges a hidden load up to max_correction_n; a
// demand held beyond it (by margin_n, 0.5 N) is a fault of its own. Here the
// taxels read 2 N of the 8 N the wrench carries (a calibration at a quarter
// of the truth): the demand passes 3 N (the force-mismatch bound, 4 N + 30 %
// + 2.5 N, is not reached: 6 N < 6.9 N) and the stop follows one window (2 s)
// after it.
TEST(ServoSensorChecks, CorrectionHeldAtItsLimitIsAFault) {
  for (double dt : {0.01, 0.001}) {
    SensorLoop l(chaseCop(true, 2.5), 2.0, 0.0);
    l.arm_follows = false;  // the features stay as given
    l.wrench(8.0);
    l.step(dt);
    double t_sat = -1.0;
    ServoStatus st = ServoStatus::Ok;
    while (l.t < 5.0 && !watchdogStatus(st)) {
      st = l.step(dt);
      if (t_sat < 0.0 && std::fabs(l.s.forceEstimator().demand()) >= 2.5 + 0.5) t_sat = l.t - dt;
    }
    EXPECT_EQ(st, ServoStatus::CorrectionSaturated) << dt;
    ASSERT_GT(t_sat, 0.0) << dt;
    EXPECT_NEAR(l.t - dt - t_sat, 2.0, 2 * dt + 1e-9) << dt;  // correction_saturated.window_s
    EXPECT_NEAR(l.s.forceEstimator().correction(), 2.5, 1e-9) << dt;  // c itself at its bound
  }
  // Within its bound (1 N hidden of 5 N), the correction is a steady state: no stop.
  SensorLoop ok(chaseCop(true, 2.5), 4.0, 0.0);
  ok.arm_follows = false;
  ok.wrench(5.0);
  ok.step(0.01);
  EXPECT_FALSE(watchdogStatus(ok.run(5.0, 0.01, ServoStatus::CorrectionSaturated)));
  // Source tactile: no correction, nothing to saturate.
  SensorLoop tactile(chaseCop(false, 2.5), 2.0, 0.0);
  tactile.arm_follows = false;
  tactile.wrench(5.0);
  tactile.step(0.01);
  EXPECT_FALSE(watchdogStatus(tactile.run(5.0, 0.01, ServoStatus::CorrectionSaturated)));
}

TEST(ServoSensorChecks, UnseenLoadAboveTheProgramsBound) {
  for (double dt : {0.01, 0.001}) {
    ServoParams p = freeMotion();
    p.watchdogs.unseen_max_n = 6.0;
    Loop l(p);
    l.in.have_wrench = true;
    l.in.wrench.w = {0, 0, 7.0, 0, 0, 0};  // either sign: |F . z_s|
    l.step(dt);
    EXPECT_EQ(l.run(1.0, dt, ServoStatus::UnseenLoad), ServoStatus::UnseenLoad) << dt;
    EXPECT_NEAR(l.t - dt, 0.1 + dt, dt + 1e-9) << dt;  // unseen_load.window_s after the first cycle
    Loop below(p);
    below.in.have_wrench = true;
    below.in.wrench.w = {0, 0, -5.5, 0, 0, 0};
    below.step(dt);
    EXPECT_FALSE(watchdogStatus(below.run(1.0, dt, ServoStatus::UnseenLoad))) << dt;
  }
}

// on_fault: retreat: after a sensor fault the command moves retreat_m along
// -z_s at the step limit, then holds.
TEST(ServoSensorChecks, OnFaultRetreatMovesAlongMinusZsThenHolds) {
  const double dt = 0.01;
  ServoParams p = chaseCop(false, 4.5);
  p.watchdogs.fault_retreat = true;
  p.watchdogs.fault_retreat_m = 0.01;
  SensorLoop l(p, 8.0, 0.0);
  l.wrench(0.0);
  l.step(dt);
  ASSERT_EQ(l.run(1.0, dt, ServoStatus::PhantomContact), ServoStatus::PhantomContact);
  const KDL::Frame at_fault = toFrame(l.out.command.pose);
  for (int k = 0; k < 100; ++k) ASSERT_EQ(l.step(dt), ServoStatus::PhantomContact) << k;
  const KDL::Frame after = toFrame(l.out.command.pose);
  // z_s is z_g here (identity mount and orientation): the flange moved down
  // z_g... along -z_s by 0.01 m less the first retreat step made at the fault.
  const KDL::Vector d = after.p - at_fault.p;
  EXPECT_NEAR(d.x(), 0.0, 1e-12);
  EXPECT_NEAR(d.y(), 0.0, 1e-12);
  EXPECT_NEAR(d.z(), -0.01 + 0.05 * dt, 1e-9);
}

// The wrench with the wrong sign (the KRC's estExtTcpFT against the stated
// convention, or the fault schedule's wrench_sign): a 5 N press reads
// f_w = -5 N. Folded into |f_w| it agreed with the taxels and the fused
// estimate ran on; signed it is 10 N below them, a phantom contact within
// the 0.05 s window, with the fused source and without.
TEST(ServoSensorChecks, AWrenchOfTheWrongSignIsAPhantomContactAtTheFirstTouch) {
  for (bool fused : {false, true}) {
    SensorLoop l(chaseCop(fused, 4.5), 5.0, 0.0);
    l.arm_follows = false;
    l.wrench(-5.0);
    ASSERT_EQ(l.step(0.01), ServoStatus::Starting);
    EXPECT_EQ(l.run(1.0, 0.01, ServoStatus::PhantomContact), ServoStatus::PhantomContact) << fused;
    EXPECT_LE(l.t, 0.05 + 3 * 0.01 + 1e-9) << fused;
    // The same press with the stated sign: the sensors agree, no stop.
    SensorLoop right(chaseCop(fused, 4.5), 5.0, 0.0);
    right.arm_follows = false;
    right.wrench(5.0);
    right.step(0.01);
    EXPECT_FALSE(watchdogStatus(right.run(1.0, 0.01, ServoStatus::PhantomContact))) << fused;
  }
}

namespace {
ServoParams driftChecked() {
  ServoParams p = chaseCop(true, 4.5);
  p.watchdogs.drift_max_change_n = 1.0;
  p.watchdogs.drift_tau_s = 1.0;
  p.watchdogs.drift_settle_s = 2.0;
  return p;
}
}  // namespace

// The wrench drifts (10 N/min) while the taxels hold a steady 4 N of a 5 N
// press: the fused correction follows the drift below its bound, so neither
// correction_saturated (4.5 N + 0.5 N) nor force_mismatch comes for tens of
// seconds. The drift check anchors the low-passed demand (tau 1 s) 2 s into
// the contact and stops once it moved by 1 N. The filter starts at the
// demand's first sample (0: the demand itself rises to the 1 N hidden with
// tau_s 0.1 s), so with the ramp r = 1/6 N/s it reads
// lp(t) = 1 - e^-t + r (t - 1 + e^-t): the anchor lp(2) = 1.054 N, and
// lp(t) = 2.054 N at t = 7.32 s. Tolerance 0.2 s: the demand's own 0.1 s lag
// behind the ramp, and the cycle.
TEST(ServoSensorChecks, AWrenchThatDriftsIsStoppedByTheCorrectionDriftCheck) {
  for (double dt : {0.01, 0.001}) {
    SensorLoop l(driftChecked(), 4.0, 0.0);
    l.arm_follows = false;
    l.wrench(5.0);
    l.step(dt);
    ServoStatus st = ServoStatus::Ok;
    while (l.t < 30.0 && !watchdogStatus(st)) {
      l.wrench(5.0 + (10.0 / 60.0) * l.t);
      st = l.step(dt);
    }
    EXPECT_EQ(st, ServoStatus::CorrectionDrift) << dt;
    EXPECT_NEAR(l.t, 7.32, 0.2) << dt;
    EXPECT_LT(std::fabs(l.s.forceEstimator().correction()), 4.5) << dt;  // below its bound: saturation alone came later
  }
}

// What the drift check leaves alone: a steady hidden load with noise (the
// nominal slide), a phase switch that changes the demand (the anchor starts
// over), the check off (max_change_n 0), and the tactile source (no
// correction).
TEST(ServoSensorChecks, TheCorrectionDriftCheckIgnoresASteadyCorrectionAndRestartsPerPhase) {
  const double dt = 0.01;
  SensorLoop steady(driftChecked(), 4.0, 0.0);
  steady.arm_follows = false;
  steady.step(dt);
  ServoStatus st = ServoStatus::Ok;
  for (int k = 0; k < 3000 && !watchdogStatus(st); ++k) {
    steady.wrench(5.0 + 0.8 * std::sin(0.5 * k * dt) + (k % 7 - 3) * 0.3);  // +-0.8 N slow, +-0.9 N fast
    st = steady.step(dt);
  }
  EXPECT_FALSE(watchdogStatus(st)) << static_cast<int>(st);
  // A load that steps by 2 N at a phase switch: a new anchor, no stop.
  ServoParams two = driftChecked();
  PhaseParams b = two.phases[0];
  b.name = "press";
  b.s_d(kZ) = 7.0 / 1800.0;
  TransitionParams later;  // reachable from align (the program's check); the test switches by request
  later.on = TransitionEvent::Timeout;
  later.timeout_s = 1000.0;
  later.to = "press";
  two.phases[0].transitions.push_back(later);
  two.phases.push_back(b);
  SensorLoop sw(two, 4.0, 0.0);
  sw.arm_follows = false;
  sw.wrench(5.0);
  sw.step(dt);
  EXPECT_FALSE(watchdogStatus(sw.run(4.0, dt, ServoStatus::CorrectionDrift)));
  ASSERT_TRUE(sw.s.requestPhase("press"));
  sw.wrench(7.0);
  EXPECT_FALSE(watchdogStatus(sw.run(10.0, dt, ServoStatus::CorrectionDrift)));
  // The same 2 N step within one phase is a drift.
  SensorLoop one(driftChecked(), 4.0, 0.0);
  one.arm_follows = false;
  one.wrench(5.0);
  one.step(dt);
  EXPECT_FALSE(watchdogStatus(one.run(4.0, dt, ServoStatus::CorrectionDrift)));
  one.wrench(7.0);
  EXPECT_EQ(one.run(10.0, dt, ServoStatus::CorrectionDrift), ServoStatus::CorrectionDrift);
  // Off, and without a correction: the ramp runs on.
  ServoParams off = driftChecked();
  off.watchdogs.drift_max_change_n = 0.0;
  ServoParams tactile_src = driftChecked();
  tactile_src.force_estimate.fused = false;
  for (const ServoParams& p : {off, tactile_src}) {
    SensorLoop l(p, 4.0, 0.0);
    l.arm_follows = false;
    l.wrench(5.0);
    l.step(dt);
    for (int k = 0; k < 1200 && !watchdogStatus(st); ++k) {
      l.wrench(5.0 + 2.0 * k / 1200.0);
      st = l.step(dt);
    }
    EXPECT_NE(st, ServoStatus::CorrectionDrift);
  }
}

TEST(ServoSensorChecks, ProgramKeysRead) {
  const std::string text =
      "watchdogs:\n"
      "  phantom_contact: {window_s: 0.02, tolerance_n: 1.5, tolerance_rel: 0.3}\n"
      "  unseen_load: {window_s: 0.2, max_n: 8}\n"
      "  correction_saturated: {window_s: 3, margin_n: 0.7}\n"
      "  correction_drift: {max_change_n: 1.2, tau_s: 0.5, settle_s: 3}\n"
      "  on_fault: retreat\n"
      "  retreat_m: 0.005\n"
      "phases:\n"
      "  - name: only\n"
      "    s_d: [0, 0, 0.002, 0, 0, 0]\n";
  ServoParams p;
  ConfigResult r = loadServoProgram(tactile::test::writeTempFile("sensor_checks.yaml", text), p);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_DOUBLE_EQ(p.watchdogs.phantom_window_s, 0.02);
  EXPECT_DOUBLE_EQ(p.watchdogs.phantom_tolerance_n, 1.5);
  EXPECT_DOUBLE_EQ(p.watchdogs.phantom_tolerance_rel, 0.3);
  EXPECT_DOUBLE_EQ(p.watchdogs.unseen_window_s, 0.2);
  EXPECT_DOUBLE_EQ(p.watchdogs.unseen_max_n, 8.0);
  EXPECT_DOUBLE_EQ(p.watchdogs.correction_window_s, 3.0);
  EXPECT_DOUBLE_EQ(p.watchdogs.correction_margin_n, 0.7);
  EXPECT_DOUBLE_EQ(p.watchdogs.drift_max_change_n, 1.2);
  EXPECT_DOUBLE_EQ(p.watchdogs.drift_tau_s, 0.5);
  EXPECT_DOUBLE_EQ(p.watchdogs.drift_settle_s, 3.0);
  EXPECT_TRUE(p.watchdogs.fault_retreat);
  EXPECT_DOUBLE_EQ(p.watchdogs.fault_retreat_m, 0.005);
  ServoParams q;
  r = loadServoProgram(tactile::test::writeTempFile("sensor_checks_bad.yaml", "watchdogs: {on_fault: flee}\n"), q);
  EXPECT_NE(r.message().find("watchdogs.on_fault: 'flee': must be one of hold, retreat"), std::string::npos) << r.message();
  r = loadServoProgram(tactile::test::writeTempFile("sensor_checks_old.yaml", "watchdogs: {force_mismatch: {no_contact_n: 5}}\n"), q);
  EXPECT_NE(r.message().find("no_contact_n"), std::string::npos) << r.message();
}
