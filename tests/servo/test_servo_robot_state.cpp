// The servo while the arm cannot be commanded (TactileServo ROBOT STATE):
// the KRC in monitor mode (friOpen before friStart), friStop, a drop of the
// link quality. The servo holds at the measured pose with everything frozen,
// resumes from the measured pose without a jump, and a dry run steps as if
// the arm followed. Allocation-free on every new path.
#include "alloc_counter.hpp"
#include "servo_test_util.hpp"
#include "tactile_servo/servo_stage.hpp"

#include <limits>

using namespace tactile;
using namespace servo_test;

namespace {

// A contact phase regulating CoP_x with a PI (kp 2 /s, ki 1 /s^2) and a 3 s
// timeout to `slow`, then a terminal `done` reached on a 3 s timeout.
ServoParams piProgram() {
  PhaseParams a = identityPhase("press", 2.0, 1.0);
  a.requires_contact = false;
  TransitionParams t;
  t.on = TransitionEvent::Timeout;
  t.timeout_s = 3.0;
  t.to = "slow";
  a.transitions.push_back(t);
  PhaseParams b = identityPhase("slow", 2.0, 1.0);
  b.requires_contact = false;
  t.to = "done";
  b.transitions.push_back(t);
  PhaseParams c = identityPhase("done", 0.0, 0.0);
  c.terminal = true;
  c.requires_contact = false;
  ServoParams p;
  p.phases = {a, b, c};
  return p;
}

// A contact 2 mm off centre along x_s: the PI moves the sensor and integrates.
struct Loop : ServoLoop {
  explicit Loop(const ServoParams& p) : ServoLoop(p, makeFeatures(0, 0.002, 0, 0, 0.002, 0, 0, ContactType::Point)) {}
};

}  // namespace

TEST(ServoRobotState, HoldsAtTheMeasuredPoseWithEverythingFrozen) {
  Loop l(piProgram());
  for (int k = 0; k < 100; ++k) l.step();  // 1 s of servoing: the integrator and the phase time run
  ASSERT_EQ(l.s.phaseIndex(), 0);
  const Vec6 integral = l.s.controlLaw().integral();
  ASSERT_GT(integral.norm(), 0.0);
  const double in_phase = l.t - l.s.program().enteredAt();
  // friStop: the arm holds where it is; someone moves it 3 mm meanwhile (the
  // servo must take the measured pose as it is, not its own command).
  l.in.robot_ready = false;
  const KDL::Frame moved = toFrame(l.in.flange_measured) * KDL::Frame(KDL::Vector(0.003, 0.0, 0.0));
  l.in.flange_measured = toPose(moved);
  EXPECT_TRUE(l.s.requestPhase("slow"));  // a switch requested meanwhile stays pending
  for (int k = 0; k < 500; ++k) {          // 5 s: longer than the phase's 3 s timeout
    ASSERT_EQ(l.step(), ServoStatus::WaitingForRobot);
    ASSERT_TRUE(l.out.valid);
    EXPECT_LT(transDist(l.out.command.pose, l.in.flange_measured), 1e-12);
    EXPECT_LT(rotDist(l.out.command.pose, l.in.flange_measured), 1e-12);
    EXPECT_TRUE(l.s.waitingForRobot());
  }
  EXPECT_EQ(l.s.phaseIndex(), 0) << "the program advanced while the arm could not be commanded";
  EXPECT_TRUE((l.s.controlLaw().integral() - integral).isZero(0.0)) << "the integrator ran";
  EXPECT_NEAR(l.t - l.s.program().enteredAt(), in_phase, 1e-9) << "the time in the phase ran";
  EXPECT_NEAR(l.out.phase.time_s - l.out.phase.t_enter_s, in_phase - 0.01, 1e-9);
  // friStart: the servo goes on from the measured pose: the first command is
  // one limited step from it, the pending switch is taken, the integrator
  // goes on from where it stood.
  l.in.robot_ready = true;
  const Pose from = l.in.flange_measured;
  const ServoStatus st = l.step();
  EXPECT_TRUE(st == ServoStatus::Ok || st == ServoStatus::Limited) << toString(st);
  EXPECT_FALSE(l.s.waitingForRobot());
  EXPECT_EQ(l.s.phaseIndex(), 1);
  const double max_step = l.s.params().safety.max_trans_speed * 0.01;
  EXPECT_LE(transDist(l.out.command.pose, from), max_step + 1e-12);
  EXPECT_GT(transDist(l.out.command.pose, from), 0.0) << "it must move again";
}

TEST(ServoRobotState, HoldsTheKrcSetPointWhereItIsKnown) {
  // In a pressing contact the KRC's set point lies inside the object by
  // force / stiffness (here 2.5 mm along z), the measured pose does not: the
  // servo holds the set point, so the bridge's start gate passes on it and
  // the force is kept.
  Loop l(piProgram());
  for (int k = 0; k < 50; ++k) l.step();
  l.in.robot_ready = false;
  const KDL::Frame meas = toFrame(l.in.flange_measured);
  const KDL::Frame setpoint = meas * KDL::Frame(KDL::Vector(0.0, 0.0, 0.0025));
  l.in.robot_setpoint = toPose(setpoint);
  for (int k = 0; k < 20; ++k) {
    ASSERT_EQ(l.step(), ServoStatus::WaitingForRobot);
    EXPECT_LT(transDist(l.out.command.pose, l.in.robot_setpoint), 1e-12);
  }
  l.in.robot_ready = true;
  l.in.robot_setpoint = kNoPose;
  l.step();
  EXPECT_LE(transDist(l.out.command.pose, toPose(setpoint)), l.s.params().safety.max_trans_speed * 0.01 + 1e-12)
      << "resumed from the measured pose, not from the held set point";
}

TEST(ServoRobotState, TimeoutsCountOnlyCommandableTime) {
  // press -> slow after 3 s of commandable time, whatever the pauses between.
  Loop l(piProgram());
  double commandable = 0.0;
  int k = 0;
  while (l.s.phaseIndex() == 0 && k < 2000) {
    l.in.robot_ready = (k / 50) % 2 == 0;  // 0.5 s on, 0.5 s off
    const bool ready = l.in.robot_ready;
    l.step();
    if (ready && l.s.phaseIndex() == 0 && k > 0) commandable += 0.01;
    ++k;
  }
  ASSERT_EQ(l.s.phaseIndex(), 1);
  EXPECT_NEAR(commandable, 3.0, 0.015) << "the timeout fired after " << l.t << " s of wall time";
  EXPECT_GT(l.t, 5.5);
}

TEST(ServoRobotState, ALatchedWatchdogStaysLatched) {
  ServoParams p = piProgram();
  p.phases[0].max_duration_s = 0.5;
  Loop l(p);
  for (int k = 0; k < 60; ++k) l.step();
  ASSERT_EQ(l.step(), ServoStatus::PhaseTimeout);
  l.in.robot_ready = false;
  EXPECT_EQ(l.step(), ServoStatus::PhaseTimeout);
  l.in.robot_ready = true;
  EXPECT_EQ(l.step(), ServoStatus::PhaseTimeout);
}

TEST(ServoRobotState, ADryRunComputesAsIfTheArmFollowedWithoutTheStallWatchdog) {
  ServoParams p = piProgram();
  p.watchdogs.stall_window_s = 0.2;  // the arm does not follow: would latch ArmStalled after 0.2 s
  p.watchdogs.stall_min_distance = 0.0005;
  Loop dry(p), wet(p);
  dry.in.dry_run = true;
  dry.in.robot_ready = false;  // what the bridge says in a dry run
  dry.arm_follows = false;
  wet.arm_follows = false;
  ServoStatus sd = ServoStatus::NotConfigured, sw = ServoStatus::NotConfigured;
  for (int k = 0; k < 100; ++k) {
    sd = dry.step();
    sw = wet.step();
  }
  EXPECT_EQ(sw, ServoStatus::ArmStalled) << "control: without the dry run the stall watchdog must fire";
  EXPECT_TRUE(sd == ServoStatus::Ok || sd == ServoStatus::Limited) << toString(sd);
  EXPECT_FALSE(dry.s.waitingForRobot());
  // Its commands move away from the held arm (Eq. 15 integrates them).
  EXPECT_GT(transDist(dry.out.command.pose, dry.in.flange_measured), 0.003);
}

TEST(ServoRobotState, StageTakesTheRobotStatePort) {
  ServoStage stage;
  ASSERT_TRUE(stage.configure(piProgram(), 0.01).ok());
  stage.setMeasuredPose(toPose(KDL::Frame(KDL::Vector(0.5, 0.0, 0.3))));
  ContactFeatures f = makeFeatures(0, 0.002, 0, 0, 0.002, 0, 0, ContactType::Point);
  ServoOutput out;
  ServoStatus st = ServoStatus::NotConfigured;
  RobotState r;
  r.time_s = 0.0;
  r.commandable = false;
  EXPECT_TRUE(stage.setRobotState(r));
  f.time_s = 0.0;
  stage.step(0.0, f, out, st);
  EXPECT_EQ(st, ServoStatus::Starting);
  f.time_s = 0.01;
  stage.step(0.01, f, out, st);
  EXPECT_EQ(st, ServoStatus::WaitingForRobot);
  r.time_s = std::numeric_limits<double>::quiet_NaN();
  r.commandable = true;
  EXPECT_FALSE(stage.setRobotState(r)) << "a state with a NaN time must be ignored";
  f.time_s = 0.02;
  stage.step(0.02, f, out, st);
  EXPECT_EQ(st, ServoStatus::WaitingForRobot);
  r.time_s = 0.02;
  EXPECT_TRUE(stage.setRobotState(r));
  f.time_s = 0.03;
  stage.step(0.03, f, out, st);
  EXPECT_NE(st, ServoStatus::WaitingForRobot);
}

TEST(ServoRobotState, NoHeapAllocationWhileWaitingResumingOrDry) {
  Loop l(piProgram());
  l.step();
  tactile::test::AllocationScope scope;
  for (int k = 0; k < 300; ++k) {
    l.in.robot_ready = (k / 20) % 2 == 0;
    l.in.dry_run = (k / 100) == 1;
    l.step();
  }
  EXPECT_EQ(scope.count(), 0u);
}

// The measured joints (RobotState::q) reach the phase program through the
// servo stage, the path of the component and of the simulated loop: a
// joint_margin transition fires once a joint is within its angle of the LWR's
// limit (kArmJointLimit), whichever joint and sign; a state with a non-finite
// joint makes the joints unknown, and the event does not fire on them.
TEST(ServoRobotState, TheMeasuredJointsDriveTheJointMarginEvent) {
  PhaseParams a = identityPhase("press", 2.0, 1.0);
  a.requires_contact = false;
  TransitionParams t;
  t.on = TransitionEvent::JointMargin;
  t.angle_rad = 0.1;
  t.to = "done";
  a.transitions.push_back(t);
  PhaseParams c = identityPhase("done", 0.0, 0.0);
  c.terminal = true;
  c.requires_contact = false;
  ServoParams p;
  p.phases = {a, c};
  const ContactFeatures f = makeFeatures(0, 0.002, 0, 0, 0.002, 0, 0, ContactType::Point);
  for (int joint = 0; joint < kArmJoints; ++joint) {
    for (double sign : {-1.0, 1.0}) {
      ServoStage stage;
      ASSERT_TRUE(stage.configure(p, 0.01).ok());
      Pose pose;
      pose.p = {0.5, 0.0, 0.4};
      pose.q = {1.0, 0.0, 0.0, 0.0};
      RobotState rs;
      rs.commandable = true;
      rs.q = {0.1, -0.2, 0.3, 1.2, -0.4, 0.5, 0.6};  // at least 0.8 rad from every limit
      ServoOutput out;
      ServoStatus st = ServoStatus::Ok;
      double now = 0.0;
      auto cycle = [&](double q_j) {
        rs.q[static_cast<std::size_t>(joint)] = q_j;
        rs.time_s = now;
        ASSERT_TRUE(stage.setRobotState(rs));
        ASSERT_TRUE(stage.setMeasuredPose(pose));
        ASSERT_TRUE(stage.step(now, f, out, st));
        now += 0.01;
      };
      const double lim = kArmJointLimit[static_cast<std::size_t>(joint)];
      cycle(0.0);
      cycle(sign * (lim - 0.11));
      ASSERT_STREQ(out.phase.name.data(), "press") << joint;
      const auto other = static_cast<std::size_t>((joint + 1) % kArmJoints);
      const double q_other = rs.q[other];
      rs.q[other] = std::nan("");  // unknown joints: no event, however close the others
      cycle(sign * (lim - 0.01));
      ASSERT_STREQ(out.phase.name.data(), "press") << joint;
      rs.q[other] = q_other;
      cycle(sign * (lim - 0.09));
      cycle(sign * (lim - 0.09));  // the transition fired on the last cycle; the phase is entered on this one
      EXPECT_STREQ(out.phase.name.data(), "done") << joint << " " << sign;
    }
  }
}
