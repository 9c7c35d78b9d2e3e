// tactile::PhaseProgram alone: transitions on every event in listed order,
// `for_s` streaks (the same held time at every servo rate), requests, reset, configuration errors, no allocation.
#include "alloc_counter.hpp"
#include "servo_test_util.hpp"
#include "tactile_servo/phase_program.hpp"

using namespace tactile;
using namespace servo_test;

namespace {

/// `cycles`: the condition must hold for that many cycles of kTestPeriod (for_s).
PhaseParams phaseOn(const std::string& n, TransitionEvent on, const std::string& to, int cycles = 1) {
  PhaseParams ph = identityPhase(n, 0.0, 0.0);
  TransitionParams t;
  t.on = on;
  t.to = to;
  t.for_s = cycles * kTestPeriod;
  ph.transitions.push_back(t);
  return ph;
}

ServoParams chain() {
  ServoParams p;
  p.phases.push_back(phaseOn("a", TransitionEvent::Contact, "b"));
  p.phases.push_back(phaseOn("b", TransitionEvent::Edge, "c"));
  p.phases.push_back(phaseOn("c", TransitionEvent::Aligned, "d", 3));
  p.phases[2].transitions[0].tolerance[kTolAlphaZ] = 0.01;
  p.phases[2].transitions[0].tolerance[kTolForce] = 0.5;
  p.phases.push_back(phaseOn("d", TransitionEvent::ForceAbove, "e"));
  p.phases[3].transitions[0].force_n = 8.0;
  p.phases.push_back(phaseOn("e", TransitionEvent::Timeout, "f"));
  p.phases[4].transitions[0].timeout_s = 0.1;
  p.phases.push_back(phaseOn("f", TransitionEvent::ContactLost, "g", 2));
  p.phases.push_back(phaseOn("g", TransitionEvent::Point, "a"));
  p.phases[6].P = Mat6::Zero();
  p.phases[6].terminal = true;
  return p;
}

// One evaluation; enters the target like TactileServo does.
int stepOnce(PhaseProgram& prog, const ContactFeatures& f, const Vec6& e, double now, double dt = kTestPeriod) {
  int target = -1;
  if (prog.evaluate(f, e, now, dt, 1.0 / 1800.0, target)) prog.enter(target, now);
  return prog.current();
}

}  // namespace

TEST(PhaseProgram, EveryEventFiresInOrderWithStreaks) {
  PhaseProgram prog;
  ASSERT_TRUE(prog.configure(chain()).ok());
  EXPECT_EQ(prog.current(), 0);
  EXPECT_FALSE(prog.entered());
  prog.enter(prog.current(), 0.0);
  const Vec6 zero = Vec6::Zero();
  const ContactFeatures none = makeFeatures(0, 0, 0, 0, 0, 0, 0, ContactType::None);
  EXPECT_EQ(stepOnce(prog, none, zero, 0.0), prog.indexOf("a"));
  EXPECT_EQ(stepOnce(prog, makeFeatures(0, 0, 0, 0.002, 0, 0, 0.2, ContactType::Point), zero, 0.01), prog.indexOf("b"));
  EXPECT_EQ(stepOnce(prog, makeFeatures(0, 0, 0, 0.002, 0, 0, 0.2, ContactType::Point), zero, 0.02), prog.indexOf("b"));
  EXPECT_EQ(stepOnce(prog, makeFeatures(0, 0, 0, 0.002, 0, 0, 0.2, ContactType::Edge), zero, 0.03), prog.indexOf("c"));
  // aligned: |Δα_z| <= 0.01 and |Δd_z| / c_z <= 0.5 N, three in a row; a miss restarts the streak.
  const Vec6 ok = Vec6::Zero();  // |Δα_z| = 0, |Δd_z| / c_z = 0 N
  const ContactFeatures edge = makeFeatures(0, 0, 0, 0.0002, 0, 0, 0.005, ContactType::Edge);
  Vec6 bad = ok;
  bad(kWZ) = 0.02;
  EXPECT_EQ(stepOnce(prog, edge, ok, 0.04), prog.indexOf("c"));
  EXPECT_EQ(stepOnce(prog, edge, ok, 0.05), prog.indexOf("c"));
  EXPECT_EQ(stepOnce(prog, edge, bad, 0.06), prog.indexOf("c"));
  EXPECT_EQ(stepOnce(prog, edge, ok, 0.07), prog.indexOf("c"));
  EXPECT_EQ(stepOnce(prog, edge, ok, 0.08), prog.indexOf("c"));
  EXPECT_EQ(stepOnce(prog, edge, ok, 0.09), prog.indexOf("d"));
  ContactFeatures heavy = edge;
  heavy.force = 9.0;
  EXPECT_EQ(stepOnce(prog, heavy, zero, 0.10), prog.indexOf("e"));
  EXPECT_DOUBLE_EQ(prog.enteredAt(), 0.10);
  EXPECT_EQ(stepOnce(prog, edge, zero, 0.19), prog.indexOf("e"));
  EXPECT_EQ(stepOnce(prog, edge, zero, 0.20), prog.indexOf("f"));  // 0.1 s in e
  EXPECT_EQ(stepOnce(prog, none, zero, 0.21), prog.indexOf("f"));
  EXPECT_EQ(stepOnce(prog, none, zero, 0.22), prog.indexOf("g"));
  EXPECT_TRUE(prog.terminal(prog.current()));
  EXPECT_TRUE(prog.freeMotion(prog.current()));
  EXPECT_FALSE(prog.freeMotion(prog.indexOf("a")));
}

// `for_s` is a time: a condition that must hold 0.2 s fires after 0.2 s of
// cycles at 50 Hz, 100 Hz and 1 kHz alike (at 100 Hz: the old 20 cycles).
TEST(PhaseProgram, ForSHoldsTheSameTimeAtEveryServoRate) {
  for (double dt : {0.02, 0.01, 0.002, 0.001}) {
    ServoParams p;
    p.phases.push_back(phaseOn("a", TransitionEvent::Edge, "b"));
    p.phases[0].transitions[0].for_s = 0.2;
    p.phases.push_back(identityPhase("b", 0, 0));
    PhaseProgram prog;
    ASSERT_TRUE(prog.configure(p).ok());
    prog.enter(0, 0.0);
    const ContactFeatures edge = makeFeatures(0, 0, 0, 0.002, 0, 0, 0, ContactType::Edge);
    const ContactFeatures point = makeFeatures(0, 0, 0, 0.002, 0, 0, 0, ContactType::Point);
    const int n = static_cast<int>(std::lround(0.2 / dt));
    double t = 0.0;
    // A streak broken just before the end restarts the count.
    for (int k = 0; k < n - 1; ++k) ASSERT_EQ(stepOnce(prog, edge, Vec6::Zero(), t += dt, dt), 0) << dt;
    ASSERT_EQ(stepOnce(prog, point, Vec6::Zero(), t += dt, dt), 0) << dt;
    for (int k = 0; k < n - 1; ++k) ASSERT_EQ(stepOnce(prog, edge, Vec6::Zero(), t += dt, dt), 0) << dt << " " << k;
    EXPECT_EQ(stepOnce(prog, edge, Vec6::Zero(), t += dt, dt), 1) << dt;  // held 0.2 s
  }
}

TEST(PhaseProgram, FirstListedTransitionWins) {
  ServoParams p;
  p.phases.push_back(phaseOn("a", TransitionEvent::Contact, "b"));
  TransitionParams t;
  t.on = TransitionEvent::Edge;
  t.to = "c";
  p.phases[0].transitions.push_back(t);
  p.phases.push_back(identityPhase("b", 0, 0));
  p.phases.push_back(identityPhase("c", 0, 0));
  PhaseProgram prog;
  ASSERT_TRUE(prog.configure(p).ok());
  prog.enter(0, 0.0);
  EXPECT_EQ(stepOnce(prog, makeFeatures(0, 0, 0, 0.002, 0, 0, 0, ContactType::Edge), Vec6::Zero(), 0.0), 1);
}

TEST(PhaseProgram, RequestsResetAndNames) {
  PhaseProgram prog;
  EXPECT_FALSE(prog.request(0));  // not configured
  ServoParams p = chain();
  p.initial_phase = "c";  // every phase stays reachable: g -> a -> b
  ASSERT_TRUE(prog.configure(p).ok());
  EXPECT_EQ(prog.current(), prog.indexOf("c"));
  EXPECT_EQ(prog.initial(), prog.indexOf("c"));
  EXPECT_STREQ(prog.name(prog.indexOf("e")).data(), "e");
  EXPECT_EQ(prog.indexOf("nope"), -1);
  EXPECT_EQ(prog.indexOf(nullptr), -1);
  EXPECT_FALSE(prog.request(7));
  EXPECT_FALSE(prog.request(-1));
  EXPECT_EQ(prog.pending(), -1);
  EXPECT_TRUE(prog.request(prog.indexOf("e")));
  EXPECT_EQ(prog.pending(), prog.indexOf("e"));
  prog.enter(prog.pending(), 1.0);
  prog.clearPending();
  EXPECT_EQ(prog.current(), prog.indexOf("e"));
  EXPECT_TRUE(prog.entered());
  prog.reset();
  EXPECT_EQ(prog.current(), prog.indexOf("c"));
  EXPECT_FALSE(prog.entered());
  EXPECT_EQ(prog.pending(), -1);
}

TEST(PhaseProgram, ConfigurationErrorsNameTheKey) {
  PhaseProgram prog;
  ServoParams p;
  p.source = "prog.yaml";
  EXPECT_NE(prog.configure(p).message().find("at least one phase"), std::string::npos);
  p = chain();
  p.source = "prog.yaml";
  ServoParams q = p;
  q.phases[1].transitions[0].to = "zz";
  EXPECT_NE(prog.configure(q).message().find("prog.yaml: phases.b.transitions[0].to"), std::string::npos);
  q = p;
  q.phases[3].transitions[0].force_n = 0.0;
  EXPECT_NE(prog.configure(q).message().find("force_n"), std::string::npos);
  q = p;
  q.phases[2].transitions[0].tolerance.fill(-1.0);
  EXPECT_NE(prog.configure(q).message().find("needs at least one tolerance"), std::string::npos);
  q = p;
  q.phases[6].transitions.clear();
  q.phases.push_back(identityPhase("orphan", 0, 0));
  EXPECT_NE(prog.configure(q).message().find("phases.orphan.transitions: phase unreachable"), std::string::npos);
  q = p;
  q.phases.push_back(identityPhase("b", 0, 0));
  EXPECT_NE(prog.configure(q).message().find("duplicate phase name"), std::string::npos);
  q = p;
  q.initial_phase = "zz";
  EXPECT_NE(prog.configure(q).message().find("initial_phase"), std::string::npos);
  EXPECT_FALSE(prog.configured());
}

TEST(PhaseProgram, NoAllocationPerCycle) {
  PhaseProgram prog;
  ASSERT_TRUE(prog.configure(loadShipped("edge_exploration.yaml")).ok());
  prog.enter(prog.current(), 0.0);
  tactile::test::AllocationScope scope;
  int changes = 0;
  for (int k = 0; k < 3000; ++k) {
    const ContactType c = k % 3 == 0 ? ContactType::None : (k % 3 == 1 ? ContactType::Point : ContactType::Edge);
    const int before = prog.current();
    if (stepOnce(prog, makeFeatures(0, 0, 0, 0.002, 0, 0, 0, c), Vec6::Zero(), 0.01 * k) != before) ++changes;
    if (k % 500 == 499) prog.request(0);
    if (prog.pending() >= 0) {
      prog.enter(prog.pending(), 0.01 * k);
      prog.clearPending();
    }
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_GT(changes, 0);
}

TEST(PhaseProgram, UndefinedAlphaIsNotAlignedAndMultipleIsNeitherEdgeNorPoint) {
  ServoParams p;
  p.phases.push_back(phaseOn("c", TransitionEvent::Aligned, "d"));
  p.phases[0].transitions[0].tolerance[kTolAlphaZ] = 0.01;
  p.phases.push_back(phaseOn("d", TransitionEvent::Edge, "e"));
  TransitionParams t;
  t.on = TransitionEvent::Point;
  t.to = "e";
  p.phases[1].transitions.push_back(t);
  p.phases.push_back(identityPhase("e", 0, 0));
  PhaseProgram prog;
  ASSERT_TRUE(prog.configure(p).ok());
  prog.enter(prog.current(), 0.0);
  ContactFeatures f = makeFeatures(0, 0, 0, 0.0002, 0, 0, 0.0, ContactType::Point);
  f.alpha_defined = false;  // the row's error is 0 then: it must not read as "aligned"
  for (int k = 1; k <= 10; ++k) EXPECT_EQ(stepOnce(prog, f, Vec6::Zero(), 0.01 * k), prog.indexOf("c"));
  f.alpha_defined = true;
  EXPECT_EQ(stepOnce(prog, f, Vec6::Zero(), 0.2), prog.indexOf("d"));
  f.contact = ContactType::Multiple;
  f.alpha_defined = false;
  for (int k = 1; k <= 10; ++k) EXPECT_EQ(stepOnce(prog, f, Vec6::Zero(), 0.2 + 0.01 * k), prog.indexOf("d"));
  EXPECT_TRUE(PhaseProgram::hasContact(f)) << "two contacts are still contact";
}

// `filter_s` on an `aligned` transition: the tolerances test a first-order
// low-pass of the signed errors. A flicker of ±0.03 rad about a true 0 (taxels
// crossing the firing threshold; tolerance 0.02 rad) never holds raw and holds
// filtered; a steady offset above the tolerance holds neither way; and the
// filter is exact for held inputs, so the moment it fires does not depend on
// the servo rate.
TEST(PhaseProgram, FilteredAlignedIgnoresFlickerNotOffsetsAtEveryRate) {
  auto firesAt = [](double filter_s, double dt, double offset, double flicker) {
    ServoParams p;
    p.phases.push_back(phaseOn("c", TransitionEvent::Aligned, "d"));
    TransitionParams& t = p.phases[0].transitions[0];
    t.tolerance[kTolAlphaZ] = 0.02;
    t.for_s = 0.2;
    t.filter_s = filter_s;
    p.phases.push_back(identityPhase("d", 0, 0));
    PhaseProgram prog;
    EXPECT_TRUE(prog.configure(p).ok());
    prog.enter(0, 0.0);
    const ContactFeatures edge = makeFeatures(0, 0, 0, 0.002, 0, 0, 0.005, ContactType::Edge);
    const int n = static_cast<int>(std::lround(5.0 / dt));
    for (int k = 1; k <= n; ++k) {
      const double now = k * dt;
      Vec6 e = Vec6::Zero();
      // A square wave of period 0.1 s at every rate (the same signal, sampled).
      e(kWZ) = offset + (std::fmod(now, 0.1) < 0.05 ? flicker : -flicker);
      if (stepOnce(prog, edge, e, now, dt) == 1) return now;
    }
    return -1.0;
  };
  EXPECT_LT(firesAt(0.0, 0.01, 0.0, 0.03), 0.0) << "raw: the flicker breaks every streak";
  const double t100 = firesAt(0.1, 0.01, 0.0, 0.03);
  EXPECT_GT(t100, 0.2);
  EXPECT_LT(t100, 1.0);
  EXPECT_LT(firesAt(0.1, 0.01, 0.025, 0.0), 0.0) << "a steady 0.025 rad is not aligned, filtered or not";
  for (double dt : {0.02, 0.005, 0.001}) {
    const double t = firesAt(0.1, dt, 0.0, 0.03);
    EXPECT_NEAR(t, t100, 0.021) << "dt " << dt << ": within one 50 Hz sample of the 100 Hz time";
  }
}

TEST(PhaseProgram, FilterIsOnlyForAlignedAndInRange) {
  ServoParams p = chain();
  p.phases[2].transitions[0].filter_s = -0.1;
  PhaseProgram prog;
  const ConfigResult r = prog.configure(p);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.message().find("filter_s"), std::string::npos) << r.message();
  EXPECT_NE(r.message().find("[0, 60]"), std::string::npos) << r.message();
}

// The wrist: wrist_wound fires on |accumulated yaw| >= angle (either sign),
// wrist_unwound once the yaw has come back by >= angle since the phase was
// entered (not from zero), loop_closed once the contact point went further
// than leave_m from its anchor and is back within radius_m; the anchor is the
// first contact point seen by a loop_closed transition and survives phase
// changes until reset().
TEST(PhaseProgram, WristAndLoopEventsReadTheObservedPose) {
  ServoParams p;
  p.phases.push_back(phaseOn("explore", TransitionEvent::LoopClosed, "done"));
  p.phases[0].transitions[0].radius_m = 0.005;
  p.phases[0].transitions[0].leave_m = 0.03;
  TransitionParams w;
  w.on = TransitionEvent::WristWound;
  w.to = "unwind";
  w.angle_rad = 2.6;
  p.phases[0].transitions.push_back(w);
  p.phases.push_back(phaseOn("unwind", TransitionEvent::WristUnwound, "explore"));
  p.phases[1].transitions[0].angle_rad = 3.0;
  p.phases.push_back(identityPhase("done", 0, 0));
  p.phases[2].terminal = true;
  PhaseProgram prog;
  ASSERT_TRUE(prog.configure(p).ok());
  const ContactFeatures edge = makeFeatures(0, 0, 0, 0.002, 0, 0, 0, ContactType::Edge);
  auto at = [&](double yaw, double x, double y, bool point = true) {
    ProgramSignals s;
    s.wrist_yaw = yaw;
    s.have_point = point;
    s.point[0] = x, s.point[1] = y, s.point[2] = 0.3;
    prog.observe(s);
  };
  at(0.0, 0.5, 0.0);
  prog.enter(0, 0.0);
  double t = 0.0;
  const int explore = prog.indexOf("explore"), unwind = prog.indexOf("unwind"), done = prog.indexOf("done");
  EXPECT_EQ(stepOnce(prog, edge, Vec6::Zero(), t += 0.01), explore);  // anchors at (0.5, 0)
  at(-2.5, 0.51, 0.0);
  EXPECT_EQ(stepOnce(prog, edge, Vec6::Zero(), t += 0.01), explore);  // within the range, not left yet
  at(-2.61, 0.54, 0.0);
  EXPECT_EQ(stepOnce(prog, edge, Vec6::Zero(), t += 0.01), unwind);   // |yaw| >= 2.6 (negative side)
  EXPECT_DOUBLE_EQ(prog.yawAtEnter(), -2.61);
  at(-0.5, 0.54, 0.0, false);
  EXPECT_EQ(stepOnce(prog, edge, Vec6::Zero(), t += 0.01), unwind);   // back by 2.11 < 3.0
  at(0.39, 0.54, 0.0, false);
  EXPECT_EQ(stepOnce(prog, edge, Vec6::Zero(), t += 0.01), explore);  // back by 3.0
  at(0.39, 0.506, 0.0);
  EXPECT_EQ(stepOnce(prog, edge, Vec6::Zero(), t += 0.01), explore);  // 6 mm from the anchor
  at(0.39, 0.5, 0.004, false);
  EXPECT_EQ(stepOnce(prog, edge, Vec6::Zero(), t += 0.01), explore);  // no contact point: no closure
  at(0.39, 0.5, 0.004);
  EXPECT_EQ(stepOnce(prog, edge, Vec6::Zero(), t += 0.01), done);     // 4 mm, after leaving by 40 mm
  double a[3];
  ASSERT_TRUE(prog.loopAnchor(a));
  EXPECT_DOUBLE_EQ(a[0], 0.5);
  // After reset: no anchor; the first point anchors, and coming back to it
  // without having left does not close the loop.
  prog.reset();
  EXPECT_FALSE(prog.loopAnchor(a));
  at(0.0, 0.6, 0.0);
  prog.enter(0, 0.0);
  EXPECT_EQ(stepOnce(prog, edge, Vec6::Zero(), 0.01), explore);
  at(0.0, 0.601, 0.0);
  EXPECT_EQ(stepOnce(prog, edge, Vec6::Zero(), 0.02), explore);
}

TEST(PhaseProgram, WristAndLoopParametersAreChecked) {
  ServoParams p;
  p.phases.push_back(phaseOn("a", TransitionEvent::LoopClosed, "b"));
  p.phases[0].transitions[0].radius_m = 0.005;
  p.phases[0].transitions[0].leave_m = 0.004;  // must exceed radius_m
  p.phases.push_back(phaseOn("b", TransitionEvent::WristWound, "a"));
  p.phases[1].transitions[0].angle_rad = 2.0;
  PhaseProgram prog;
  ConfigResult r = prog.configure(p);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("leave_m"), std::string::npos) << r.message();
  p.phases[0].transitions[0].leave_m = 0.03;
  p.phases[1].transitions[0].angle_rad = 0.0;  // must be > 0
  r = prog.configure(p);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("angle_deg"), std::string::npos) << r.message();
  p.phases[1].transitions[0].angle_rad = 2.0;
  EXPECT_TRUE(prog.configure(p).ok());
}

// joint_margin: fires once the measured joint closest to its limit is within
// the transition's angle of it (ProgramSignals::joint_margin, which
// TactileServo takes from ServoInput::q); never while the joints are unknown
// (the default +inf); and its angle is checked at configuration.
TEST(PhaseProgram, JointMarginFiresWithinItsAngleOfALimit) {
  ServoParams p;
  p.phases.push_back(phaseOn("check", TransitionEvent::JointMargin, "done"));
  p.phases[0].transitions[0].angle_rad = 0.1;
  p.phases.push_back(identityPhase("done", 0, 0));
  p.phases[1].terminal = true;
  PhaseProgram prog;
  ASSERT_TRUE(prog.configure(p).ok());
  const ContactFeatures point = makeFeatures(0, 0, 0, 0.002, 0, 0, 0, ContactType::Point);
  const int check = prog.indexOf("check"), done = prog.indexOf("done");
  prog.observe(ProgramSignals{});  // joints unknown
  prog.enter(check, 0.0);
  EXPECT_EQ(stepOnce(prog, point, Vec6::Zero(), 0.01), check);
  ProgramSignals s;
  s.joint_margin = 0.1001;
  prog.observe(s);
  EXPECT_EQ(stepOnce(prog, point, Vec6::Zero(), 0.02), check);
  s.joint_margin = 0.1;
  prog.observe(s);
  EXPECT_EQ(stepOnce(prog, point, Vec6::Zero(), 0.03), done);
  // Out of contact too: the arm's room does not depend on the image.
  prog.reset();
  prog.enter(check, 0.0);
  s.joint_margin = 0.05;
  prog.observe(s);
  EXPECT_EQ(stepOnce(prog, makeFeatures(0, 0, 0, 0, 0, 0, 0, ContactType::None), Vec6::Zero(), 0.01), done);
  for (double bad : {0.0, -0.1, 0.53, std::nan("")}) {  // (0, 30] deg
    p.phases[0].transitions[0].angle_rad = bad;
    const ConfigResult r = prog.configure(p);
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_NE(r.message().find("angle_deg"), std::string::npos) << r.message();
    EXPECT_NE(r.message().find("(0, 30] deg"), std::string::npos) << r.message();
  }
}

// `multiple`: contact in two or more separate regions (a gap in the edge
// under the pad, closed_contour.yaml's cross_gap). It holds for its for_s of
// Multiple contacts, an edge or a point in between restarts the streak, and
// neither an edge, a point nor no contact fires it.
TEST(PhaseProgram, MultipleFiresOnTwoRegionsOnly) {
  ServoParams p;
  p.phases.push_back(phaseOn("explore", TransitionEvent::Multiple, "cross_gap", 3));
  p.phases.push_back(identityPhase("cross_gap", 0, 0));
  PhaseProgram prog;
  ASSERT_TRUE(prog.configure(p).ok());
  prog.enter(prog.current(), 0.0);
  const int explore = prog.indexOf("explore");
  double t = 0.0;
  ContactFeatures f = makeFeatures(0, 0, 0, 0.0002, 0, 0, 0.0, ContactType::Edge);
  for (ContactType c : {ContactType::Edge, ContactType::Point, ContactType::None}) {
    f.contact = c;
    for (int k = 0; k < 10; ++k) EXPECT_EQ(stepOnce(prog, f, Vec6::Zero(), t += kTestPeriod), explore) << static_cast<int>(c);
  }
  // Two Multiple cycles, an edge: the streak restarts.
  f.contact = ContactType::Multiple;
  EXPECT_EQ(stepOnce(prog, f, Vec6::Zero(), t += kTestPeriod), explore);
  EXPECT_EQ(stepOnce(prog, f, Vec6::Zero(), t += kTestPeriod), explore);
  f.contact = ContactType::Edge;
  EXPECT_EQ(stepOnce(prog, f, Vec6::Zero(), t += kTestPeriod), explore);
  f.contact = ContactType::Multiple;  // the third in a row fires (as every for_s streak)
  EXPECT_EQ(stepOnce(prog, f, Vec6::Zero(), t += kTestPeriod), explore);
  EXPECT_EQ(stepOnce(prog, f, Vec6::Zero(), t += kTestPeriod), explore);
  EXPECT_EQ(stepOnce(prog, f, Vec6::Zero(), t += kTestPeriod), prog.indexOf("cross_gap"));
  EXPECT_STREQ(toString(TransitionEvent::Multiple), "multiple");
}
