// tactile::fri::KrcModel: the KRC side of FRI shared by the headless runner
// and the SimKrc test peer, driven here without a socket against the real
// tactile::fri::FriBridge, time passed in.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "alloc_counter.hpp"
#include "tactile_fri/bridge.hpp"
#include "tactile_fri/krc_model.hpp"

using namespace tactile;
using namespace tactile::fri;

namespace {

struct Loop {
  KrcModel krc;
  FriBridge bridge;
  PlantState plant;
  std::array<uint8_t, 2048> wire{};
  MsrPacket msr{};
  BridgeOutput out;

  explicit Loop(ControlStrategy control = ControlStrategy::CartImpedance) {
    KrcModelParams kp;
    kp.control = control;
    EXPECT_TRUE(krc.configure(kp).ok());
    BridgeParams bp;
    // The bridge's start gate (engage_max_*) is tested in test_bridge.cpp; here
    // the KRC model follows a command 1 cm away, so the gate is opened wide.
    bp.engage_max_trans = 0.1;  // the widest the bridge accepts
    bp.engage_max_rot = 0.5;
    EXPECT_TRUE(bridge.configure(bp).ok());
    plant.pose = KDL::Frame(KDL::Rotation::RPY(3.14159265358979, 0, 0), KDL::Vector(0.5, 0, 0.4));
    krc.reset(plant.pose);
  }
  /// One cycle at time t: the robot follows the set point exactly.
  ReplyResult cycle(double t, State s, const PoseCommand& desired) {
    krc.setState(s, Quality::Perfect, 0x7F);
    krc.holdUnlessCommanding(plant.pose);
    plant.pose = krc.setPoint();
    krc.buildMeasurement(plant, t, msr);
    std::size_t n = 0;
    EXPECT_EQ(encodeMeasurement(msr, wire.data(), wire.size(), n), PacketStatus::Ok);
    bridge.stepDatagram(wire.data(), n, desired, t, out);
    if (!out.reply) return ReplyResult::Malformed;
    EXPECT_EQ(encodeCommand(out.cmd, wire.data(), wire.size(), n), PacketStatus::Ok);
    return krc.handleReply(wire.data(), n);
  }
};

}  // namespace

TEST(KrcModel, MonEchoThenCmdFollowsTheRateLimitedCommand) {
  Loop l;
  PoseCommand desired;
  desired.pose = toPose(KDL::Frame(l.plant.pose.M, l.plant.pose.p + KDL::Vector(0, 0, -0.01)));
  desired.status = ServoStatus::Ok;
  for (int k = 0; k < 50; ++k) {  // MON: the bridge echoes, nothing moves
    desired.time_s = 0.001 * k;
    ASSERT_EQ(l.cycle(0.001 * k, State::Mon, desired), ReplyResult::Matched) << k;
    EXPECT_EQ(l.msr.head.send_seq, k + 1);
    EXPECT_EQ(l.msr.intf.timestamp, static_cast<uint32_t>(0.001 * k * 1000.0));
  }
  EXPECT_EQ(l.krc.stats().mon_echo_errors, 0u);
  EXPECT_EQ(l.krc.stats().applied, 0u);
  EXPECT_NEAR(l.plant.pose.p.z(), 0.4, 1e-6);
  {
    tactile::test::AllocationScope scope;
    for (int k = 50; k < 300; ++k) {  // CMD: the set point follows the rate-limited command
      desired.time_s = 0.001 * k;
      ASSERT_EQ(l.cycle(0.001 * k, State::Cmd, desired), ReplyResult::Matched) << k;
    }
    EXPECT_EQ(scope.count(), 0u);
  }
  const KrcModelStats& s = l.krc.stats();
  EXPECT_EQ(s.replies, 300u);
  EXPECT_EQ(s.applied, 250u);
  EXPECT_EQ(s.remote_seq_errors, 0u);
  EXPECT_EQ(s.flag_errors, 0u);
  EXPECT_LE(s.max_cmd_step_m, 0.05 * 0.001 + 2e-7) << "the bridge's 0.05 m/s limit at 1 kHz";
  EXPECT_LE(s.max_entry_offset_m, 0.05 * 0.001 + 2e-7) << "no jump on entering CMD: one limited step";
  EXPECT_NEAR(l.plant.pose.p.z(), 0.39, 1e-5) << "200 limited steps reach the command 1 cm below";
  // The next measurement's reflSeqCount is the last command taken.
  const uint16_t last = l.out.cmd.head.send_seq;
  l.krc.buildMeasurement(l.plant, 0.3, l.msr);
  EXPECT_EQ(l.msr.head.refl_seq, last);
}

TEST(KrcModel, StaleAndMalformedRepliesAreNotApplied) {
  Loop l;
  PoseCommand desired;
  desired.pose = toPose(l.plant.pose);
  desired.status = ServoStatus::Ok;
  ASSERT_EQ(l.cycle(0.0, State::Cmd, desired), ReplyResult::Matched);
  // A reply to the previous measurement arriving after a new one: stale, ignored.
  CmdPacket old = l.out.cmd;
  l.plant.pose = l.krc.setPoint();
  l.krc.buildMeasurement(l.plant, 0.001, l.msr);
  std::size_t n = 0;
  old.head.send_seq = static_cast<uint16_t>(old.head.send_seq + 1);
  ASSERT_EQ(encodeCommand(old, l.wire.data(), l.wire.size(), n), PacketStatus::Ok);
  EXPECT_EQ(l.krc.handleReply(l.wire.data(), n), ReplyResult::Stale);
  EXPECT_EQ(l.krc.stats().stale_replies, 1u);
  EXPECT_EQ(l.krc.handleReply(l.wire.data(), 10), ReplyResult::Malformed);
  EXPECT_EQ(l.krc.stats().malformed_replies, 1u);
  EXPECT_EQ(l.krc.stats().applied, 1u);
  // Leaving CMD after a command was applied (friStop): the KRC keeps its set
  // point, whatever the measured pose (a pressing contact keeps its force).
  l.krc.setState(State::Mon, Quality::Perfect, 0x7F);
  const KDL::Frame held = l.krc.setPoint();
  const KDL::Frame moved(l.plant.pose.M, l.plant.pose.p + KDL::Vector(0.01, 0, 0));
  l.krc.holdUnlessCommanding(moved);
  EXPECT_NEAR((l.krc.setPoint().p - held.p).Norm(), 0.0, 1e-12);
  // Before any command (a fresh start in MON) the set point is the measured pose.
  l.krc.reset(held);
  l.krc.holdUnlessCommanding(moved);
  EXPECT_NEAR((l.krc.setPoint().p - moved.p).Norm(), 0.0, 1e-12);
  KrcModelParams bad;
  bad.period_s = 0.0;
  const ConfigResult r = l.krc.configure(bad);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("krc.period_s"), std::string::npos) << r.message();
}

// A KRC under joint impedance: the remote's flags are chosen in MON and kept
// in CMD; the model refuses any change in CMD, as the KRC does (and leaves
// command mode).
TEST(KrcModel, JointImpedanceKrcGetsTheSameFlagsInMonitorAndCommand) {
  Loop l(ControlStrategy::JointImpedance);
  PoseCommand desired;
  desired.pose = toPose(l.plant.pose);
  desired.status = ServoStatus::Ok;
  for (int k = 0; k < 200; ++k) {
    desired.time_s = 0.001 * k;
    ASSERT_EQ(l.cycle(0.001 * k, k < 100 ? State::Mon : State::Cmd, desired), ReplyResult::Matched) << k;
    EXPECT_EQ(l.out.cmd.cmd.cmd_flags, flags::kJointPosition) << k;
  }
  EXPECT_EQ(l.krc.stats().flag_changes, 0u);
  EXPECT_EQ(l.krc.stats().flag_errors, 0u);
  EXPECT_FALSE(l.krc.refused());
  EXPECT_EQ(l.krc.state(), State::Cmd);
}

TEST(KrcModel, AFlagChangeInCommandModeIsRefusedAndTheKrcLeavesCommandMode) {
  Loop l;
  PoseCommand desired;
  desired.pose = toPose(l.plant.pose);
  desired.status = ServoStatus::Ok;
  for (int k = 0; k < 20; ++k) ASSERT_EQ(l.cycle(0.001 * k, k < 10 ? State::Mon : State::Cmd, desired), ReplyResult::Matched);
  ASSERT_EQ(l.krc.stats().applied, 10u);
  // A reply to the next measurement with other flags (the joint position flag).
  l.krc.setState(State::Cmd, Quality::Perfect, 0x7F);
  l.krc.buildMeasurement(l.plant, 0.02, l.msr);
  CmdPacket c = l.out.cmd;
  c.head.send_seq = static_cast<uint16_t>(c.head.send_seq + 1);
  c.head.refl_seq = l.msr.head.send_seq;
  c.cmd.cmd_flags = flags::kJointPosition;
  std::size_t n = 0;
  ASSERT_EQ(encodeCommand(c, l.wire.data(), l.wire.size(), n), PacketStatus::Ok);
  EXPECT_EQ(l.krc.handleReply(l.wire.data(), n), ReplyResult::Matched);
  EXPECT_EQ(l.krc.stats().flag_changes, 1u);
  EXPECT_EQ(l.krc.stats().flag_errors, 1u);
  EXPECT_EQ(l.krc.stats().applied, 10u) << "refused, not applied";
  EXPECT_TRUE(l.krc.refused());
  // The KRC stays in monitor mode, whatever its script says, until reset().
  l.krc.setState(State::Cmd, Quality::Perfect, 0x7F);
  EXPECT_EQ(l.krc.state(), State::Mon);
  l.krc.buildMeasurement(l.plant, 0.021, l.msr);
  EXPECT_EQ(l.msr.intf.state, static_cast<uint16_t>(State::Mon));
  l.krc.reset(l.plant.pose);
  EXPECT_FALSE(l.krc.refused());
}

// The PC -> KRC request channel end to end: the bridge asks the KRL program
// to stop ($FRI_FRM_INT[1] = 99); the simulated program honours it (friStop:
// monitor mode) and reports its step ($FRI_TO_INT[1]), which the bridge reads.
TEST(KrcModel, TheBridgesStopRequestEndsTheKrlProgram) {
  Loop l;
  PoseCommand desired;
  desired.pose = toPose(l.plant.pose);
  desired.status = ServoStatus::Ok;
  for (int k = 0; k < 20; ++k) {
    desired.time_s = 0.001 * k;
    ASSERT_EQ(l.cycle(0.001 * k, k < 10 ? State::Mon : State::Cmd, desired), ReplyResult::Matched);
    EXPECT_EQ(l.out.krl_program, k < 10 ? krl::kProgramMonitor : krl::kProgramCommand) << k;
    EXPECT_EQ(l.out.cmd.krl.int_data[0], 0) << "no request before requestStop()";
  }
  EXPECT_STREQ(krl::programStepName(l.out.krl_program), "commanding");
  l.bridge.requestStop();
  EXPECT_TRUE(l.bridge.stopRequested());
  l.bridge.reset();  // a reopened transport keeps the request
  int left_at = -1;
  for (int k = 20; k < 40; ++k) {
    desired.time_s = 0.001 * k;
    ASSERT_EQ(l.cycle(0.001 * k, State::Cmd, desired), ReplyResult::Matched);  // the script still says CMD
    EXPECT_EQ(l.out.cmd.krl.int_data[0], krl::kRequestStop) << k;
    EXPECT_TRUE(l.out.stop_requested);
    if (left_at < 0 && l.out.state == State::Mon) left_at = k;
  }
  EXPECT_TRUE(l.krc.stopRequested());
  EXPECT_EQ(left_at, 21) << "the KRC leaves command mode one cycle after the request";
  EXPECT_EQ(l.out.krl_program, krl::kProgramClosed);
  EXPECT_STREQ(krl::programStepName(l.out.krl_program), "closed");
  EXPECT_EQ(l.out.status, BridgeStatus::LeftCmd);
  EXPECT_FALSE(l.out.robot.commandable);
  EXPECT_EQ(l.krc.stats().mon_echo_errors, 0u);
  EXPECT_EQ(l.krc.stats().flag_errors, 0u);
  // configure() clears the request.
  BridgeParams bp;
  ASSERT_TRUE(l.bridge.configure(bp).ok());
  EXPECT_FALSE(l.bridge.stopRequested());
}
