// The simulated KRC's link quality from the answers' timing and its
// $STIFFNESS.MAXFORCE / CPMAXDELTA stop (tactile::fri::KrcModel), driven
// without a socket against the real tactile::fri::FriBridge, time passed in.
// Ground truth: the quality from an independent count of the missed / late
// answers over the window; the faults from the force and deviation we set.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "alloc_counter.hpp"
#include "tactile_fri/bridge.hpp"
#include "tactile_fri/krc_model.hpp"

using namespace tactile;
using namespace tactile::fri;

namespace {

constexpr double kT = 0.001;  // the KRC's cycle (s)

struct Loop {
  KrcModel krc;
  FriBridge bridge;
  PlantState plant;
  std::array<uint8_t, 2048> wire{};
  MsrPacket msr{};
  BridgeOutput out;
  PoseCommand desired;
  double t = 0.0;

  explicit Loop(const KrcModelParams& kp) {
    EXPECT_TRUE(krc.configure(kp).ok());
    BridgeParams bp;
    // The start gate (engage_max_*) is tested in test_bridge.cpp; here the
    // command lies 2 mm away, so the gate is opened wide.
    bp.engage_max_trans = 0.1;
    bp.engage_max_rot = 0.5;
    EXPECT_TRUE(bridge.configure(bp).ok());
    plant.pose = KDL::Frame(KDL::Rotation::RPY(3.14159265358979, 0, 0), KDL::Vector(0.5, 0, 0.4));
    krc.reset(plant.pose);
    desired.pose = toPose(plant.pose);
    desired.status = ServoStatus::Ok;
  }
  /// One cycle: the script's state, the robot following the set point unless
  /// `blocked`; the bridge answers unless `lost` (its reply never arrives),
  /// with `latency_s` reported to the KRC.
  void cycle(State script, bool lost = false, double latency_s = 0.0, bool blocked = false) {
    krc.setState(script, Quality::Perfect, 0x7F);
    krc.holdUnlessCommanding(plant.pose);
    if (!blocked) plant.pose = krc.setPoint();
    krc.buildMeasurement(plant, t, msr);
    std::size_t n = 0;
    EXPECT_EQ(encodeMeasurement(msr, wire.data(), wire.size(), n), PacketStatus::Ok);
    desired.time_s = t;
    bridge.stepDatagram(wire.data(), n, desired, t, out);
    bool matched = false;
    if (out.reply && !lost) {
      EXPECT_EQ(encodeCommand(out.cmd, wire.data(), wire.size(), n), PacketStatus::Ok);
      matched = krc.handleReply(wire.data(), n) == ReplyResult::Matched;
    }
    krc.noteAnswer(matched, latency_s);
    t += kT;
  }
};

KrcModelParams timed() {
  KrcModelParams kp;
  kp.period_s = kT;
  kp.quality_rule.enabled = true;
  return kp;
}

/// The quality the rule gives for `bad` missed/late answers in the window.
Quality expectedQuality(std::size_t bad, const KrcQualityRule& r) {
  const double share = static_cast<double>(bad) / static_cast<double>(r.window);
  if (share <= r.perfect_max) return Quality::Perfect;
  if (share <= r.ok_max) return Quality::Ok;
  if (share <= r.bad_max) return Quality::Bad;
  return Quality::Unacceptable;
}

}  // namespace

// Before the remote answers the KRC rates the link UNACCEPTABLE; the answers
// raise it to PERFECT once the window holds at most perfect_max misses, and
// the script's command mode is entered then; a burst of lost replies in
// command mode lowers it, the KRC leaves command mode below OK (the bridge
// holds and reports left_cmd), and enters it again at PERFECT (the bridge
// resumes from the KRC's set point: no jump).
TEST(KrcTiming, QualityFollowsTheMissedAnswersOverTheWindow) {
  Loop l(timed());
  const KrcQualityRule r = timed().quality_rule;
  l.desired.pose = toPose(KDL::Frame(l.plant.pose.M, l.plant.pose.p + KDL::Vector(0, 0, -0.002)));
  std::array<int, 100> window{};  // the independent count: nothing answered before the start
  window.fill(1);
  ASSERT_EQ(r.window, window.size());
  std::size_t bad = r.window;
  int entered_at = -1, left_at = -1, reentered_at = -1, first_perfect = -1, perfect_after_burst = -1, left_cmd = 0;
  bool was_cmd = false;
  tactile::test::AllocationScope scope;
  for (int k = 0; k < 600; ++k) {
    const bool lost = k >= 300 && k < 320;  // 20 replies lost: 20 % of the window
    l.cycle(State::Cmd, lost);
    int& oldest = window[static_cast<std::size_t>(k) % window.size()];
    bad = bad + static_cast<std::size_t>(lost) - static_cast<std::size_t>(oldest);
    oldest = lost ? 1 : 0;
    const Quality q = expectedQuality(bad, r);
    ASSERT_EQ(l.krc.timingQuality(), q) << "cycle " << k << ", " << bad << " missed in the window";
    if (first_perfect < 0 && q == Quality::Perfect) first_perfect = k;
    if (k > 320 && perfect_after_burst < 0 && q == Quality::Perfect) perfect_after_burst = k;
    const bool cmd = l.krc.state() == State::Cmd;
    if (!was_cmd && cmd) (entered_at < 0 ? entered_at : reentered_at) = k;
    if (was_cmd && !cmd) left_at = k;
    if (l.out.status == BridgeStatus::LeftCmd) ++left_cmd;
    was_cmd = cmd;
  }
  EXPECT_EQ(scope.count(), 0u) << "the rule allocates nothing per cycle";
  // 98 answers after a window of 100 misses leave 2 % (perfect_max).
  EXPECT_EQ(first_perfect, 97);
  EXPECT_EQ(entered_at, first_perfect) << "friStart at PERFECT, not before";
  // The 11th loss of the burst passes ok_max (10 %): BAD, command mode left.
  EXPECT_EQ(left_at, 310);
  EXPECT_EQ(l.krc.stats().quality_drops, 1u);
  // PERFECT again once 18 of the 20 losses have left the window.
  EXPECT_EQ(perfect_after_burst, 417);
  EXPECT_EQ(reentered_at, perfect_after_burst) << "friStart again at PERFECT";
  EXPECT_EQ(l.krc.stats().answers_missed, 20u);
  EXPECT_EQ(l.krc.stats().answers_late, 0u);
  EXPECT_GE(left_cmd, 100) << "the bridge reports the drop while the KRC is in MON";
  EXPECT_EQ(l.krc.state(), State::Cmd);
  EXPECT_EQ(l.krc.stats().mon_echo_errors, 0u);
  EXPECT_LE(l.krc.stats().max_entry_offset_m, 0.05 * kT + 2e-7) << "the re-entry starts at the KRC's set point";
  EXPECT_LE(l.krc.stats().max_cmd_step_m, 0.05 * kT + 2e-7);
  EXPECT_NEAR(l.plant.pose.p.z(), 0.398, 1e-5) << "the command is reached and held";
  EXPECT_EQ(l.out.status, BridgeStatus::Commanding);
  // The quality the measurements carried: each level while it fell and rose.
  const auto& qc = l.krc.stats().quality_cycles;
  EXPECT_GT(qc[0], 0u);
  EXPECT_GT(qc[1], 0u);
  EXPECT_GT(qc[2], 0u);
  EXPECT_EQ(qc[0] + qc[1] + qc[2] + qc[3], 600u);
}

// Latency relative to the cycle: an answer later than late_fraction (0.8) of
// the cycle counts as late, one at half the cycle does not.
TEST(KrcTiming, LateAnswersLowerTheQualityAsMissedOnesDo) {
  Loop l(timed());
  for (int k = 0; k < 200; ++k) l.cycle(State::Cmd, false, 0.5 * kT);
  EXPECT_EQ(l.krc.timingQuality(), Quality::Perfect);
  EXPECT_EQ(l.krc.stats().answers_late, 0u);
  ASSERT_EQ(l.krc.state(), State::Cmd);
  for (int k = 0; k < 15; ++k) l.cycle(State::Cmd, false, 0.9 * kT);
  EXPECT_EQ(l.krc.stats().answers_late, 15u);
  EXPECT_EQ(l.krc.stats().answers_missed, 0u);
  EXPECT_EQ(l.krc.timingQuality(), Quality::Bad) << "15 % late: above ok_max (10 %), below bad_max (30 %)";
  EXPECT_EQ(l.krc.state(), State::Mon) << "below OK the KRC leaves command mode";
  EXPECT_EQ(l.krc.quality(), Quality::Bad) << "the lower of the script's PERFECT and the timing's BAD";
}

// With the rule off (the default) the script alone decides, as before.
TEST(KrcTiming, WithoutTheRuleTheScriptAloneDecides) {
  KrcModelParams kp;
  Loop l(kp);
  for (int k = 0; k < 50; ++k) l.cycle(State::Cmd, k >= 10);
  EXPECT_EQ(l.krc.state(), State::Cmd);
  EXPECT_EQ(l.krc.quality(), Quality::Perfect);
  EXPECT_EQ(l.krc.stats().answers_missed, 40u);
  EXPECT_EQ(l.krc.stats().quality_drops, 0u);
}

TEST(KrcTiming, BadRuleOrLimitsAreClearErrors) {
  KrcModel krc;
  KrcModelParams kp = timed();
  kp.quality_rule.window = 0;
  ConfigResult r = krc.configure(kp);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("krc.quality_rule.window"), std::string::npos) << r.message();
  kp = timed();
  kp.quality_rule.ok_max = 0.01;  // below perfect_max
  r = krc.configure(kp);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("krc.quality_rule.ok_max"), std::string::npos) << r.message();
  kp = timed();
  kp.limits.max_force[2] = -1.0;
  r = krc.configure(kp);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("krc.limits.max_force Z"), std::string::npos) << r.message();
}

namespace {
KrcModelParams limited() {
  KrcModelParams kp;
  kp.period_s = kT;
  // krc/TactileServo.src's day-one values: MAXFORCE 20 N / 2 N m,
  // CPMAXDELTA 15 mm / 5 deg.
  kp.limits.max_force = {20.0, 20.0, 20.0, 2.0, 2.0, 2.0};
  const double deg = 3.14159265358979 / 180.0;
  kp.limits.cp_max_delta = {0.015, 0.015, 0.015, 5 * deg, 5 * deg, 5 * deg};
  return kp;
}
}  // namespace

// A press beyond MAXFORCE: the KRC stops the arm (drives braked, monitor
// mode) in the cycle the force passes the limit; the bridge names it
// krc_fault and keeps naming it while the script still says CMD.
TEST(KrcLimits, APressBeyondMaxForceStopsTheArm) {
  Loop l(limited());
  for (int k = 0; k < 20; ++k) l.cycle(State::Cmd);
  l.plant.wrench[2] = -19.9;  // just below the limit: nothing happens
  for (int k = 0; k < 20; ++k) l.cycle(State::Cmd);
  ASSERT_EQ(l.krc.fault(), KrcFault::None);
  ASSERT_EQ(l.out.status, BridgeStatus::Commanding);
  const uint64_t applied = l.krc.stats().applied;
  l.plant.wrench[2] = -20.5;  // beyond MAXFORCE Z
  l.cycle(State::Cmd);
  EXPECT_EQ(l.krc.fault(), KrcFault::MaxForce);
  EXPECT_STREQ(toString(l.krc.fault()), "maxforce");
  EXPECT_EQ(l.msr.intf.state, static_cast<uint16_t>(State::Mon));
  EXPECT_EQ(l.msr.robot.power, 0u);
  EXPECT_EQ(l.out.status, BridgeStatus::KrcFault);
  EXPECT_STREQ(toString(l.out.status), "krc_fault");
  l.plant.wrench[2] = 0.0;  // the press released: the fault stays until the operator acknowledges
  for (int k = 0; k < 20; ++k) {
    l.cycle(State::Cmd);
    EXPECT_EQ(l.out.status, BridgeStatus::KrcFault) << k;
    EXPECT_FALSE(l.out.robot.commandable);
  }
  EXPECT_EQ(l.krc.stats().applied, applied) << "no command taken after the stop";
  EXPECT_EQ(l.krc.stats().faults, 1u);
  EXPECT_EQ(l.krc.stats().mon_echo_errors, 0u);
  l.krc.reset(l.plant.pose);  // acknowledged, the program restarted (its counter too: the bridge resyncs)
  for (int k = 0; k < 20; ++k) l.cycle(State::Cmd);
  EXPECT_EQ(l.krc.fault(), KrcFault::None);
  EXPECT_EQ(l.out.status, BridgeStatus::Commanding) << "krc_fault clears in CMD with the drives on";
}

// MAXFORCE bounds estExtTcpFT's components as the KRC sends them: in the
// axes of $STIFFNESS.FRAMETYPE. With the flange pointing sideways (its x axis
// down) 15 N pressing down is 15 N along base z (within MAXFORCE Z 20 N) and
// 15 N along tool x (beyond a MAXFORCE X of 10 N): only the KRC that reports
// in tool axes stops the arm.
TEST(KrcLimits, MaxForceIsCheckedInTheAxesEstExtTcpFtIsSentIn) {
  const double pi = 3.14159265358979;
  const KDL::Frame sideways(KDL::Rotation::RPY(pi, pi / 2, 0.0), KDL::Vector(0.5, 0, 0.4));
  const KDL::Vector f_base(0, 0, -15.0);
  const KDL::Vector f_tool = sideways.M.Inverse() * f_base;  // the ground truth, independent of the model
  ASSERT_NEAR(std::fabs(f_tool.x()), 15.0, 1e-9) << "the flange's x axis points down";
  for (const WrenchFrame frame : {WrenchFrame::Base, WrenchFrame::Tool}) {
    KrcModelParams kp = limited();
    kp.limits.max_force = {10.0, 10.0, 20.0, 2.0, 2.0, 2.0};
    kp.wrench_frame = frame;
    Loop l(kp);
    l.plant.pose = sideways;
    l.krc.reset(sideways);
    l.desired.pose = toPose(sideways);
    for (int k = 0; k < 20; ++k) l.cycle(State::Cmd);
    ASSERT_EQ(l.out.status, BridgeStatus::Commanding) << toString(frame);
    l.plant.wrench[0] = f_base.x();
    l.plant.wrench[1] = f_base.y();
    l.plant.wrench[2] = f_base.z();
    l.cycle(State::Cmd);
    const std::array<double, 6> sent = toWrench(l.msr.data.est_ext_tcp_ft);
    if (frame == WrenchFrame::Base) {
      EXPECT_NEAR(sent[2], -15.0, 1e-4) << "float32";
      EXPECT_EQ(l.krc.fault(), KrcFault::None) << "15 N along base z: within MAXFORCE Z 20 N";
    } else {
      EXPECT_NEAR(sent[0], f_tool.x(), 1e-4) << "float32";
      EXPECT_EQ(l.krc.fault(), KrcFault::MaxForce) << "15 N along tool x: beyond MAXFORCE X 10 N";
    }
  }
}

// A command that jumps beyond CPMAXDELTA (a reply written by hand: the bridge
// itself never sends one, its rate limiter moves 50 um per cycle) while the
// arm cannot follow at once: the KRC stops the arm.
TEST(KrcLimits, ACommandJumpBeyondCpMaxDeltaStopsTheArm) {
  Loop l(limited());
  for (int k = 0; k < 20; ++k) l.cycle(State::Cmd);
  ASSERT_EQ(l.out.status, BridgeStatus::Commanding);
  const auto jump = [&](double dz) {
    l.krc.setState(State::Cmd, Quality::Perfect, 0x7F);
    l.krc.buildMeasurement(l.plant, l.t, l.msr);
    CmdPacket c = l.out.cmd;
    c.head.send_seq = static_cast<uint16_t>(c.head.send_seq + 1);
    c.head.refl_seq = l.msr.head.send_seq;
    fromFrame(KDL::Frame(l.plant.pose.M, l.plant.pose.p + KDL::Vector(0, 0, dz)), c.cmd.cart_pos);
    std::size_t n = 0;
    EXPECT_EQ(encodeCommand(c, l.wire.data(), l.wire.size(), n), PacketStatus::Ok);
    EXPECT_EQ(l.krc.handleReply(l.wire.data(), n), ReplyResult::Matched);
    l.out.cmd = c;
    l.t += kT;
  };
  const KDL::Frame at = l.plant.pose;
  jump(-0.014);  // within CPMAXDELTA Z (15 mm): the arm has not moved yet, no fault
  l.cycle(State::Cmd, false, 0.0, true);
  EXPECT_EQ(l.krc.fault(), KrcFault::None);
  l.plant.pose = at;
  jump(-0.016);  // beyond it
  l.cycle(State::Cmd, false, 0.0, true);
  EXPECT_EQ(l.krc.fault(), KrcFault::CpMaxDelta);
  EXPECT_STREQ(toString(l.krc.fault()), "cpmaxdelta");
  EXPECT_EQ(l.msr.intf.state, static_cast<uint16_t>(State::Mon));
  EXPECT_EQ(l.msr.robot.power, 0u);
  EXPECT_EQ(l.out.status, BridgeStatus::KrcFault);
  EXPECT_NEAR((l.krc.setPoint().p - at.p).Norm(), 0.0, 1e-9) << "braked where the arm stands";
}
