// The servo's watchdogs (tactile_servo/watchdog.hpp): a phase that never
// ends, an arm that does not follow, a tactile force the estimated wrench
// contradicts. Each latches a named status and holds the command; each is
// checked against the case it must catch and the one it must let pass, at
// 100 Hz and 1 kHz, without allocation.
#include <set>
#include <string>

#include "alloc_counter.hpp"
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
    // No tactile contact, but the arm carries 20 N (the housing): mismatch; 5 N: fine.
    EXPECT_EQ(contactLoop(0.0, 20.0, false, true, dt), ServoStatus::ForceMismatch) << dt;
    EXPECT_NE(contactLoop(0.0, 5.0, false, true, dt), ServoStatus::ForceMismatch) << dt;
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
  const ServoStatus all[] = {ServoStatus::Ok,           ServoStatus::FreeMotion,      ServoStatus::Holding,
                             ServoStatus::ContactLost,  ServoStatus::Limited,         ServoStatus::Done,
                             ServoStatus::WaitingForPose, ServoStatus::Starting,      ServoStatus::WaitingForRobot,
                             ServoStatus::ForceCeiling, ServoStatus::InvalidInput,    ServoStatus::NotConfigured,
                             ServoStatus::PhaseTimeout, ServoStatus::ArmStalled,      ServoStatus::ForceMismatch,
                             ServoStatus::SurfaceTooCurved};
  std::set<std::string> seen;
  for (ServoStatus s : all) {
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
}
