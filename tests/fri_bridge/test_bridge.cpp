// FRI bridge core without the network: state/quality handling, sequence
// checks, hold-on-loss, rate limiter, leaving CMD, invalid inputs, and zero
// heap allocation per cycle.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "alloc_counter.hpp"
#include "fri_test_util.hpp"
#include "tactile_fri/bridge.hpp"

using namespace tactile;
using namespace tactile::fri;
using namespace fri_test;

namespace {

constexpr double kT = 0.001;  // command period carried by the packets
// Tolerance on per-step distances: the wire carries floats; a coordinate near
// 0.5 m is quantised to 3e-8 m, so the difference of two can be off by 1e-7 m.
constexpr double kPosTol = 2e-7;
constexpr double kRotTol = 2e-6;  // rad, float rotation matrices (entries to 6e-8)

struct Harness {
  FriBridge bridge;
  BridgeOutput out;
  PoseCommand desired;
  uint16_t seq = 100;
  double now = 10.0;
  KDL::Frame measured = startPose();

  explicit Harness(BridgeParams p = BridgeParams{}) {
    EXPECT_TRUE(bridge.configure(p).ok());
    desired.status = ServoStatus::Ok;
    setDesired(measured);
  }
  void setDesired(const KDL::Frame& f) {
    toPose(f, desired.pose);
    desired.time_s = now;
  }
  BridgeStatus send(State st, Quality q, uint16_t power = 0x7F) { return sendSeq(++seq, st, q, power); }
  /// A session as the servo starts it: MON, then CMD with the desired pose at
  /// the measured one (the servo's first command): the start gate opens.
  void engage() {
    EXPECT_EQ(send(State::Mon, Quality::Perfect), BridgeStatus::Monitor);
    setDesired(measured);
    EXPECT_EQ(send(State::Cmd, Quality::Perfect), BridgeStatus::Commanding);
  }
  BridgeStatus sendSeq(uint16_t s, State st, Quality q, uint16_t power = 0x7F) {
    now += kT;
    desired.time_s = now;
    const std::vector<uint8_t> b = makeMsr(s, st, q, measured, power, float(kT));
    return bridge.stepDatagram(b.data(), b.size(), desired, now, out);
  }
  KDL::Frame commanded() const { return cmdPose(reinterpret_cast<const uint8_t*>(&out.cmd)); }
};

double dist(const KDL::Frame& a, const KDL::Frame& b) { return (a.p - b.p).Norm(); }
double angle(const KDL::Frame& a, const KDL::Frame& b) {
  KDL::Vector axis;
  return rotationAngle(a.M.Inverse() * b.M, axis);
}

}  // namespace

TEST(FriBridge, ConfigureNamesParameterAndRange) {
  FriBridge b;
  BridgeParams p;
  p.max_lin_speed = -1.0;
  ConfigResult r = b.configure(p);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.message().find("fri.max_lin_speed"), std::string::npos) << r.message();
  EXPECT_NE(r.message().find("(0, 2]"), std::string::npos) << r.message();
  p = BridgeParams{};
  p.cart_damping[4] = 2.0;
  r = b.configure(p);
  EXPECT_NE(r.message().find("fri.cart_damping[4]"), std::string::npos) << r.message();
  p = BridgeParams{};
  p.cycle_time_s = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(b.configure(p).ok());
  EXPECT_FALSE(b.configured());
  BridgeOutput out;
  const std::vector<uint8_t> pk = makeMsr(1, State::Mon, Quality::Perfect, startPose());
  EXPECT_EQ(b.stepDatagram(pk.data(), pk.size(), PoseCommand{}, 0.0, out), BridgeStatus::NotConfigured);
  EXPECT_FALSE(out.reply);
}

TEST(FriBridge, MonitorEchoesMeasuredPoseAndReflectsSequence) {
  Harness h;
  h.setDesired(KDL::Frame(KDL::Vector(1.0, 1.0, 1.0)));  // far away: must be ignored in MON
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(h.send(State::Mon, Quality::Perfect), BridgeStatus::Monitor);
    ASSERT_TRUE(h.out.reply);
    EXPECT_EQ(h.out.cmd.head.refl_seq, h.seq);
    EXPECT_EQ(h.out.cmd.head.send_seq, i + 1);
    EXPECT_EQ(h.out.cmd.head.packet_size, 376);
    EXPECT_EQ(h.out.cmd.head.datagram_id, 0x1005);
    EXPECT_EQ(h.out.cmd.cmd.cmd_flags, flags::kCartPose);
    EXPECT_TRUE(KDL::Equal(h.commanded(), h.measured, 1e-6));
    EXPECT_EQ(h.out.state_changed, i == 0);
  }
  // OFF state echoes too.
  EXPECT_EQ(h.send(State::Off, Quality::Bad), BridgeStatus::Monitor);
  EXPECT_TRUE(h.out.state_changed);
  EXPECT_TRUE(KDL::Equal(h.commanded(), h.measured, 1e-6));
}

TEST(FriBridge, CommandIsRateLimitedTowardsDesired) {
  BridgeParams p;
  p.max_lin_speed = 0.1;
  p.max_rot_speed = 0.5;
  Harness h(p);
  h.engage();
  const KDL::Frame target(KDL::Rotation::RotZ(0.05) * h.measured.M, h.measured.p + KDL::Vector(0.01, 0.0, -0.005));
  h.setDesired(target);
  KDL::Frame prev = h.measured;
  int limited = 0, steps = 0;
  while (h.send(State::Cmd, Quality::Perfect) == BridgeStatus::Limited) {
    ++limited;
    ASSERT_LT(++steps, 1000);
    EXPECT_LE(dist(prev, h.commanded()), p.max_lin_speed * kT + kPosTol);
    EXPECT_LE(angle(prev, h.commanded()), p.max_rot_speed * kT + kRotTol);
    prev = h.commanded();
  }
  EXPECT_EQ(h.out.status, BridgeStatus::Commanding);
  // 0.0112 m at 0.1 m/s = 112 steps; 0.05 rad at 0.5 rad/s = 100 steps.
  EXPECT_NEAR(limited, 112, 2);
  EXPECT_TRUE(KDL::Equal(h.commanded(), target, 1e-6));
  EXPECT_EQ(h.bridge.stats().limited, static_cast<uint64_t>(limited + 1) - 1);
}

TEST(FriBridge, DuplicatesAndOutOfOrderAreDroppedWithoutReply) {
  Harness h;
  h.sendSeq(500, State::Mon, Quality::Perfect);
  ASSERT_TRUE(h.out.reply);
  EXPECT_EQ(h.sendSeq(500, State::Mon, Quality::Perfect), BridgeStatus::DroppedDuplicate);
  EXPECT_FALSE(h.out.reply);
  EXPECT_EQ(h.sendSeq(499, State::Mon, Quality::Perfect), BridgeStatus::DroppedOutOfOrder);
  EXPECT_FALSE(h.out.reply);
  EXPECT_EQ(h.sendSeq(503, State::Mon, Quality::Perfect), BridgeStatus::Monitor);
  EXPECT_EQ(h.out.lost_before, 2);
  EXPECT_EQ(h.sendSeq(502, State::Mon, Quality::Perfect), BridgeStatus::DroppedOutOfOrder);
  const BridgeStats& s = h.bridge.stats();
  EXPECT_EQ(s.duplicates, 1u);
  EXPECT_EQ(s.out_of_order, 2u);
  EXPECT_EQ(s.lost, 2u);
  EXPECT_EQ(s.replies, 2u);
}

TEST(FriBridge, SequenceWrapsAroundAndResyncsAfterRestart) {
  Harness h;
  h.sendSeq(65534, State::Mon, Quality::Perfect);
  EXPECT_EQ(h.sendSeq(65535, State::Mon, Quality::Perfect), BridgeStatus::Monitor);
  EXPECT_EQ(h.sendSeq(0, State::Mon, Quality::Perfect), BridgeStatus::Monitor);
  EXPECT_EQ(h.sendSeq(2, State::Mon, Quality::Perfect), BridgeStatus::Monitor);
  EXPECT_EQ(h.out.lost_before, 1);
  // KRC restarted: the counter jumps backwards (40000 is 25538 behind 2 on the
  // 16-bit circle); accepted after resync_after packets.
  BridgeParams p;
  int dropped = 0;
  const uint16_t restart = 40000;
  for (uint16_t s = restart; s < restart + p.resync_after; ++s) {
    if (h.sendSeq(s, State::Mon, Quality::Perfect) == BridgeStatus::DroppedOutOfOrder) ++dropped;
  }
  EXPECT_EQ(dropped, p.resync_after - 1);
  EXPECT_TRUE(h.out.reply);
  EXPECT_EQ(h.bridge.stats().resyncs, 1u);
  EXPECT_EQ(h.sendSeq(static_cast<uint16_t>(restart + p.resync_after), State::Mon, Quality::Perfect),
            BridgeStatus::Monitor);
  EXPECT_EQ(h.out.lost_before, 0);
}

TEST(FriBridge, PacketLossHoldsAndNeverCatchesUp) {
  // Hold policy: after a gap of 200 packets the next command is within one
  // limited step of the last one sent (no extrapolation, no catch-up).
  BridgeParams p;
  p.max_lin_speed = 0.05;
  Harness h(p);
  h.engage();
  h.setDesired(KDL::Frame(h.measured.M, h.measured.p + KDL::Vector(0.0, 0.1, 0.0)));
  for (int i = 0; i < 20; ++i) h.send(State::Cmd, Quality::Perfect);
  const KDL::Frame before = h.commanded();
  h.seq = static_cast<uint16_t>(h.seq + 200);  // 200 packets lost
  h.now += 0.2;
  EXPECT_EQ(h.send(State::Cmd, Quality::Perfect), BridgeStatus::Limited);
  EXPECT_EQ(h.out.lost_before, 200);
  EXPECT_NEAR(dist(before, h.commanded()), p.max_lin_speed * kT, kPosTol);
}

TEST(FriBridge, RewindsToTheCommandTheKrcReflects) {
  // Our reply k was lost: the next measurement reflects k-1. The new command
  // is one limited step from command k-1 (what the KRC holds), not from k.
  Harness h;
  h.engage();
  h.setDesired(KDL::Frame(h.measured.M, h.measured.p + KDL::Vector(0.05, 0.0, 0.0)));
  auto sendRefl = [&h](uint16_t refl) {
    std::vector<uint8_t> b = makeMsr(++h.seq, State::Cmd, Quality::Perfect, h.measured);
    putU16(b, 2, refl);
    h.now += kT;
    h.desired.time_s = h.now;
    return h.bridge.stepDatagram(b.data(), b.size(), h.desired, h.now, h.out);
  };
  for (int i = 0; i < 5; ++i) sendRefl(h.out.cmd.head.send_seq);  // KRC got every command
  const uint16_t held_seq = h.out.cmd.head.send_seq;
  const KDL::Frame held = h.commanded();
  sendRefl(held_seq);  // this reply will be "lost"
  const KDL::Frame lost = h.commanded();
  EXPECT_NEAR(dist(held, lost), 0.05 * kT, kPosTol);
  sendRefl(held_seq);  // the KRC still reflects held_seq
  EXPECT_EQ(h.bridge.stats().rewinds, 1u);
  EXPECT_NEAR(dist(held, h.commanded()), 0.05 * kT, kPosTol);
  EXPECT_NEAR(dist(lost, h.commanded()), 0.0, kPosTol);
  // A reflected seq that we never sent (or too old) is ignored: hold/continue.
  sendRefl(static_cast<uint16_t>(h.out.cmd.head.send_seq - 1000));
  EXPECT_EQ(h.bridge.stats().rewinds, 1u);
  // Without rewinding, the step from the KRC's held command would be two steps.
  BridgeParams p;
  p.rewind_on_refl = false;
  Harness g(p);
  g.engage();
  g.setDesired(KDL::Frame(g.measured.M, g.measured.p + KDL::Vector(0.05, 0.0, 0.0)));
  g.send(State::Cmd, Quality::Perfect);
  const KDL::Frame g_held = g.commanded();
  g.send(State::Cmd, Quality::Perfect);  // "lost"
  g.send(State::Cmd, Quality::Perfect);
  EXPECT_NEAR(dist(g_held, g.commanded()), 2 * 0.05 * kT, kPosTol);
  EXPECT_EQ(g.bridge.stats().rewinds, 0u);
}

TEST(FriBridge, QualityBelowOkHoldsLastCommand) {
  Harness h;
  h.engage();
  h.setDesired(KDL::Frame(h.measured.M, h.measured.p + KDL::Vector(0.05, 0.0, 0.0)));
  for (int i = 0; i < 10; ++i) h.send(State::Cmd, Quality::Ok);
  const KDL::Frame held = h.commanded();
  for (Quality q : {Quality::Bad, Quality::Unacceptable, Quality::Bad}) {
    EXPECT_EQ(h.send(State::Cmd, q), BridgeStatus::QualityLow);
    ASSERT_TRUE(h.out.reply);
    EXPECT_TRUE(KDL::Equal(h.commanded(), held, 1e-9));
  }
  EXPECT_EQ(h.bridge.stats().holds, 3u);
  // Back at quality >= OK: the start gate again (the servo held meanwhile at
  // the measured pose): a desired pose 50 mm away is not followed...
  EXPECT_EQ(h.send(State::Cmd, Quality::Perfect), BridgeStatus::DesiredFar);
  EXPECT_TRUE(KDL::Equal(h.commanded(), held, 1e-9));
  // ...one within a step of the held command is, one limited step at a time.
  h.setDesired(KDL::Frame(held.M, held.p + KDL::Vector(0.0004, 0.0, 0.0)));
  EXPECT_EQ(h.send(State::Cmd, Quality::Perfect), BridgeStatus::Limited);
  EXPECT_NEAR(dist(held, h.commanded()), 0.05 * kT, kPosTol);
}

TEST(FriBridge, LeavingCmdGivesClearStatusAndReentryStartsAtMeasured) {
  Harness h;
  h.engage();
  h.setDesired(KDL::Frame(h.measured.M, h.measured.p + KDL::Vector(0.0, 0.0, 0.05)));
  for (int i = 0; i < 10; ++i) h.send(State::Cmd, Quality::Perfect);
  // KRC drops to MON; meanwhile the robot was pushed elsewhere.
  h.measured.p = h.measured.p + KDL::Vector(0.02, 0.0, 0.0);
  EXPECT_EQ(h.send(State::Mon, Quality::Perfect), BridgeStatus::LeftCmd);
  EXPECT_TRUE(h.out.state_changed);
  EXPECT_TRUE(KDL::Equal(h.commanded(), h.measured, 1e-6));
  EXPECT_EQ(h.send(State::Mon, Quality::Perfect), BridgeStatus::LeftCmd);  // sticky while out of CMD
  // Back to CMD: the command stays at the MEASURED pose while the desired
  // pose is far from it (start gate)...
  for (int i = 0; i < 100; ++i) {
    EXPECT_EQ(h.send(State::Cmd, Quality::Perfect), BridgeStatus::DesiredFar);
    EXPECT_TRUE(KDL::Equal(h.commanded(), h.measured, 1e-6));
  }
  // ...and follows from there once the desired pose starts at it.
  h.setDesired(KDL::Frame(h.measured.M, h.measured.p + KDL::Vector(0.0, 0.0, 0.0004)));
  EXPECT_EQ(h.send(State::Cmd, Quality::Perfect), BridgeStatus::Limited);
  EXPECT_NEAR(dist(h.commanded(), h.measured), 0.05 * kT, kPosTol);
}

TEST(FriBridge, PowerOffEchoesMeasuredEvenInCmd) {
  Harness h;
  h.send(State::Mon, Quality::Perfect);
  h.setDesired(KDL::Frame(h.measured.M, h.measured.p + KDL::Vector(0.0, 0.05, 0.0)));
  EXPECT_EQ(h.send(State::Cmd, Quality::Perfect, 0), BridgeStatus::PowerOff);
  EXPECT_TRUE(KDL::Equal(h.commanded(), h.measured, 1e-6));
}

TEST(FriBridge, InvalidOrStaleDesiredHolds) {
  Harness h;
  h.engage();
  h.setDesired(KDL::Frame(h.measured.M, h.measured.p + KDL::Vector(0.0, 0.05, 0.0)));
  for (int i = 0; i < 5; ++i) h.send(State::Cmd, Quality::Perfect);
  const KDL::Frame held = h.commanded();
  ASSERT_GT(dist(held, h.measured), 4 * 0.05 * kT);
  h.desired.pose.p[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(h.send(State::Cmd, Quality::Perfect), BridgeStatus::DesiredInvalid);
  EXPECT_TRUE(KDL::Equal(h.commanded(), held, 1e-9));
  h.setDesired(held);
  h.desired.pose.q = {0.0, 0.0, 0.0, 0.0};  // not a rotation
  EXPECT_EQ(h.send(State::Cmd, Quality::Perfect), BridgeStatus::DesiredInvalid);
  h.setDesired(KDL::Frame(h.measured.M, h.measured.p + KDL::Vector(0.0, 0.05, 0.0)));
  h.desired.status = ServoStatus::NotConfigured;  // no desired pose yet
  EXPECT_EQ(h.send(State::Cmd, Quality::Perfect), BridgeStatus::DesiredInvalid);
  h.desired.status = ServoStatus::Ok;
  // Stale: the desired pose is older than max_desired_age_s.
  const std::vector<uint8_t> b = makeMsr(++h.seq, State::Cmd, Quality::Perfect, h.measured);
  h.bridge.stepDatagram(b.data(), b.size(), h.desired, h.now + 1.0, h.out);
  EXPECT_EQ(h.out.status, BridgeStatus::DesiredStale);
  EXPECT_TRUE(KDL::Equal(h.commanded(), held, 1e-9));
  for (float v : h.out.cmd.cmd.cart_pos) EXPECT_TRUE(std::isfinite(v));
  // After an invalid or stale desired pose the start gate closes again: a
  // fresh desired pose far from the held command is not followed.
  h.setDesired(KDL::Frame(h.measured.M, h.measured.p + KDL::Vector(0.0, 0.05, 0.0)));
  EXPECT_EQ(h.send(State::Cmd, Quality::Perfect), BridgeStatus::DesiredFar);
  EXPECT_TRUE(KDL::Equal(h.commanded(), held, 1e-9));
  h.setDesired(held);
  EXPECT_EQ(h.send(State::Cmd, Quality::Perfect), BridgeStatus::Commanding);
}

// The robot incident: the KRC came up after the deployer and the servo's first
// command was the default pose, (0, 0, 0.019) m, identity rotation; the rate
// limiter then moved the arm 0.2 m and 64 deg towards it within 4.5 s. With the
// start gate the bridge holds the measured pose, whatever the KRC's first state.
TEST(FriBridge, FirstCommandFarFromTheMeasuredPoseIsNeverFollowed) {
  for (State first : {State::Mon, State::Cmd}) {
    Harness h;
    toPose(KDL::Frame(KDL::Vector(0.0, 0.0, 0.019)), h.desired.pose);
    const int mon = first == State::Mon ? 50 : 0;
    for (int i = 0; i < mon; ++i) EXPECT_EQ(h.send(State::Mon, Quality::Perfect), BridgeStatus::Monitor);
    for (int i = 0; i < 4500; ++i) {  // 4.5 s at 1 kHz
      ASSERT_EQ(h.send(State::Cmd, Quality::Perfect), BridgeStatus::DesiredFar) << i;
      ASSERT_TRUE(h.out.reply);
      ASSERT_TRUE(KDL::Equal(h.commanded(), h.measured, 1e-6)) << i;
    }
    EXPECT_EQ(h.bridge.stats().limited, 0u);
    // The servo (re)starts and commands the measured pose: followed from there.
    h.setDesired(h.measured);
    EXPECT_EQ(h.send(State::Cmd, Quality::Perfect), BridgeStatus::Commanding);
    EXPECT_TRUE(KDL::Equal(h.commanded(), h.measured, 1e-6));
  }
}

// The gate is one program step: translation engage_max_trans, rotation
// engage_max_rot, each on its own; inside it the first command moves at most
// that far (and at most one rate-limited step).
TEST(FriBridge, StartGateIsOneProgramStep) {
  BridgeParams p;
  p.engage_max_trans = 0.0005;
  p.engage_max_rot = 0.5 * 3.14159265358979323846 / 180.0;
  struct Case { KDL::Vector dp; double rz; bool follows; };
  const Case cases[] = {{KDL::Vector(0.0004, 0.0, 0.0), 0.0, true},
                        {KDL::Vector(0.0, 0.0006, 0.0), 0.0, false},
                        {KDL::Vector(0.0003, 0.0003, 0.0003), 0.0, false},  // 0.52 mm
                        {KDL::Vector(0.0, 0.0, 0.0), 0.008, true},
                        {KDL::Vector(0.0, 0.0, 0.0), 0.0095, false},
                        {KDL::Vector(0.0004, 0.0, 0.0), 0.008, true}};
  for (const Case& c : cases) {
    Harness h(p);
    h.send(State::Mon, Quality::Perfect);
    h.setDesired(KDL::Frame(h.measured.M * KDL::Rotation::RotZ(c.rz), h.measured.p + c.dp));
    const BridgeStatus st = h.send(State::Cmd, Quality::Perfect);
    if (c.follows) {
      EXPECT_TRUE(st == BridgeStatus::Commanding || st == BridgeStatus::Limited) << toString(st);
      EXPECT_LE(dist(h.commanded(), h.measured), std::min(p.engage_max_trans, p.max_lin_speed * kT) + kPosTol);
      EXPECT_LE(angle(h.commanded(), h.measured), std::min(p.engage_max_rot, p.max_rot_speed * kT) + kRotTol);
    } else {
      EXPECT_EQ(st, BridgeStatus::DesiredFar);
      EXPECT_TRUE(KDL::Equal(h.commanded(), h.measured, 1e-6));
    }
  }
  // Parameters are checked.
  FriBridge b;
  p.engage_max_trans = 0.0;
  ConfigResult r = b.configure(p);
  EXPECT_NE(r.message().find("fri.engage_max_trans"), std::string::npos) << r.message();
  p.engage_max_trans = 0.0005;
  p.engage_max_rot = std::numeric_limits<double>::quiet_NaN();
  r = b.configure(p);
  EXPECT_NE(r.message().find("fri.engage_max_rot"), std::string::npos) << r.message();
}

TEST(FriBridge, SlightlyNonUnitDesiredQuaternionStillGivesARotation) {
  // Regression (fuzz_fri_decode crash-7969...): |q| = 1.00098 is accepted by
  // validPose (tolerance 1e-3) and must still command a proper rotation.
  Harness h;
  h.send(State::Mon, Quality::Perfect);
  toPose(h.measured, h.desired.pose);
  for (double& v : h.desired.pose.q) v *= 1.0009775;
  EXPECT_EQ(h.send(State::Cmd, Quality::Perfect), BridgeStatus::Commanding);
  ASSERT_TRUE(h.out.reply);
  EXPECT_TRUE(validFriPose(h.out.cmd.cmd.cart_pos, 1e-5));
}

TEST(FriBridge, NonCartesianStrategyInCmdRepliesAJointHold) {
  Harness h;
  std::vector<uint8_t> m = makeMsr(++h.seq, State::Mon, Quality::Perfect, h.measured);
  putU16(m, kOffControl, static_cast<uint16_t>(ControlStrategy::Position));
  EXPECT_EQ(h.bridge.stepDatagram(m.data(), m.size(), h.desired, h.now, h.out), BridgeStatus::WrongStrategy);
  EXPECT_EQ(h.out.cmd.cmd.cmd_flags, flags::kJointPosition);  // chosen in MON
  h.setDesired(KDL::Frame(h.measured.M, h.measured.p + KDL::Vector(0.05, 0.0, 0.0)));
  std::vector<uint8_t> b = makeMsr(++h.seq, State::Cmd, Quality::Perfect, h.measured);
  putU16(b, kOffControl, static_cast<uint16_t>(ControlStrategy::Position));
  for (int j = 0; j < 7; ++j) {
    putF32(b, kOffMsrJnt + 76 + 4 * std::size_t(j), 0.1f * float(j));   // cmdJntPos
    putF32(b, kOffMsrJnt + 104 + 4 * std::size_t(j), 0.01f);            // cmdJntPosFriOffset
  }
  EXPECT_EQ(h.bridge.stepDatagram(b.data(), b.size(), h.desired, h.now, h.out), BridgeStatus::WrongStrategy);
  ASSERT_TRUE(h.out.reply);
  EXPECT_EQ(h.out.cmd.cmd.cmd_flags, flags::kJointPosition);
  for (int j = 0; j < 7; ++j) EXPECT_FLOAT_EQ(h.out.cmd.cmd.jnt_pos[j], 0.1f * float(j) + 0.01f);
  EXPECT_TRUE(KDL::Equal(h.commanded(), h.measured, 1e-6));
}

TEST(FriBridge, InvalidMeasuredPoseNeverBecomesACommand) {
  Harness h;
  h.measured.p = KDL::Vector(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0);
  EXPECT_EQ(h.send(State::Mon, Quality::Perfect), BridgeStatus::MeasurementInvalid);
  EXPECT_FALSE(h.out.reply);
  EXPECT_EQ(h.send(State::Cmd, Quality::Perfect), BridgeStatus::MeasurementInvalid);
  EXPECT_FALSE(h.out.reply);  // nothing to hold yet
  h.measured = startPose();
  h.send(State::Cmd, Quality::Perfect);
  const KDL::Frame held = h.commanded();
  h.measured.M = KDL::Rotation(2, 0, 0, 0, 1, 0, 0, 0, 1);  // not a rotation
  EXPECT_EQ(h.send(State::Cmd, Quality::Perfect), BridgeStatus::MeasurementInvalid);
  ASSERT_TRUE(h.out.reply);  // in CMD: hold the last command
  EXPECT_TRUE(KDL::Equal(h.commanded(), held, 1e-9));
}

TEST(FriBridge, AKrcAtAnotherCycleIsRefusedInMonitorAndCommand) {
  // fri.yaml expects 1 ms (friOpen(1)); this KRC runs at 2 ms, then reports
  // an invalid sample time: named in MON, held in CMD, never followed.
  Harness h;
  for (const float krc_T : {0.002f, std::numeric_limits<float>::infinity()}) {
    h.bridge.reset();
    h.setDesired(h.measured);
    std::vector<uint8_t> b = makeMsr(++h.seq, State::Mon, Quality::Perfect, h.measured, 0x7F, krc_T);
    EXPECT_EQ(h.bridge.stepDatagram(b.data(), b.size(), h.desired, h.now, h.out), BridgeStatus::CycleMismatch);
    EXPECT_TRUE(h.out.reply);  // the MON echo still goes out
    EXPECT_TRUE(KDL::Equal(h.commanded(), h.measured, 1e-6));
    EXPECT_EQ(h.out.mismatch, mismatch::kCycle);
    EXPECT_FALSE(h.out.robot.config_ok);
    EXPECT_FALSE(h.out.robot.commandable);
    h.setDesired(KDL::Frame(h.measured.M, h.measured.p + KDL::Vector(0.0002, 0.0, 0.0)));  // within the gate
    b = makeMsr(++h.seq, State::Cmd, Quality::Perfect, h.measured, 0x7F, krc_T);
    EXPECT_EQ(h.bridge.stepDatagram(b.data(), b.size(), h.desired, h.now, h.out), BridgeStatus::CycleMismatch);
    ASSERT_TRUE(h.out.reply);
    EXPECT_TRUE(KDL::Equal(h.commanded(), h.measured, 1e-6)) << "followed a desired pose at a foreign cycle";
    EXPECT_EQ(h.out.robot.mode, RobotMode::Command);
    EXPECT_FALSE(h.out.robot.commandable);
  }
  // The same KRC at the configured cycle: commandable, and it follows.
  h.bridge.reset();
  h.engage();
  EXPECT_EQ(h.out.mismatch, 0);
  EXPECT_TRUE(h.out.robot.config_ok);
  EXPECT_TRUE(h.out.robot.commandable);
}

TEST(FriBridge, AKrcSendingFromAnotherPortIsRefused) {
  BridgeParams p;
  p.krc_port = 49938;
  Harness h(p);
  h.bridge.notePeerPort(49938);
  h.engage();  // the expected port: follows
  EXPECT_TRUE(h.out.robot.commandable);
  h.bridge.notePeerPort(50001);
  EXPECT_EQ(h.send(State::Cmd, Quality::Perfect), BridgeStatus::PortMismatch);
  EXPECT_EQ(h.out.mismatch, mismatch::kPort);
  EXPECT_FALSE(h.out.robot.commandable);
  EXPECT_EQ(h.send(State::Mon, Quality::Perfect), BridgeStatus::PortMismatch);  // named in MON too
  // krc_port 0 checks nothing.
  Harness any;
  any.bridge.notePeerPort(50001);
  any.engage();
  EXPECT_EQ(any.out.mismatch, 0);
}

TEST(FriBridge, AnotherControlStrategyIsNamedInMonitor) {
  Harness h;
  std::vector<uint8_t> b = makeMsr(++h.seq, State::Mon, Quality::Perfect, h.measured);
  putU16(b, kOffControl, 1);  // position control
  EXPECT_EQ(h.bridge.stepDatagram(b.data(), b.size(), h.desired, h.now, h.out), BridgeStatus::WrongStrategy);
  EXPECT_EQ(h.out.mismatch, mismatch::kControl);
  EXPECT_FALSE(h.out.robot.cartesian_impedance);
  EXPECT_TRUE(KDL::Equal(h.commanded(), h.measured, 1e-6));  // MON: the echo
}

TEST(FriBridge, DryRunHoldsThePoseWhereCommandWasEntered) {
  Harness h;
  h.bridge.setDryRun(true);
  EXPECT_EQ(h.send(State::Mon, Quality::Perfect), BridgeStatus::Monitor);
  EXPECT_TRUE(h.out.robot.dry_run);
  const KDL::Frame entry = h.measured;
  for (int k = 0; k < 50; ++k) {
    h.setDesired(KDL::Frame(h.measured.M, h.measured.p + KDL::Vector(0.0001 * k, 0.0, 0.0)));
    EXPECT_EQ(h.send(State::Cmd, Quality::Perfect), BridgeStatus::DryRun);
    ASSERT_TRUE(h.out.reply);
    EXPECT_TRUE(KDL::Equal(h.commanded(), entry, 1e-6));
    EXPECT_FALSE(h.out.robot.commandable);
    EXPECT_TRUE(h.out.robot.dry_run);
  }
  // The dry run ends: the gate again (the desired pose is 4.9 mm away: refused).
  h.bridge.setDryRun(false);
  EXPECT_EQ(h.send(State::Cmd, Quality::Perfect), BridgeStatus::DesiredFar);
  EXPECT_TRUE(h.out.robot.commandable);
  h.setDesired(h.measured);
  EXPECT_EQ(h.send(State::Cmd, Quality::Perfect), BridgeStatus::Commanding);
}

TEST(FriBridge, RobotStateCarriesModeQualityAndJoints) {
  Harness h;
  std::vector<uint8_t> b = makeMsr(++h.seq, State::Mon, Quality::Ok, h.measured);
  for (int j = 0; j < kNumJoints; ++j) putF32(b, kOffMsrJnt + 4 * std::size_t(j), 0.1f * float(j + 1));
  h.bridge.stepDatagram(b.data(), b.size(), h.desired, h.now, h.out);
  EXPECT_EQ(h.out.robot.mode, RobotMode::Monitor);
  EXPECT_EQ(h.out.robot.quality, static_cast<int>(Quality::Ok));
  EXPECT_TRUE(h.out.robot.power_on);
  EXPECT_FALSE(h.out.robot.commandable);
  EXPECT_EQ(h.out.robot.link_status, static_cast<int>(BridgeStatus::Monitor));
  EXPECT_DOUBLE_EQ(h.out.robot.time_s, h.now);
  for (int j = 0; j < kNumJoints; ++j) EXPECT_NEAR(h.out.robot.q[std::size_t(j)], 0.1 * (j + 1), 1e-7);
  EXPECT_EQ(h.send(State::Cmd, Quality::Bad), BridgeStatus::QualityLow);
  EXPECT_FALSE(h.out.robot.commandable);
  EXPECT_EQ(h.send(State::Cmd, Quality::Ok), BridgeStatus::Commanding);
  EXPECT_TRUE(h.out.robot.commandable);
  EXPECT_EQ(h.send(State::Cmd, Quality::Perfect, 0), BridgeStatus::PowerOff);
  EXPECT_FALSE(h.out.robot.commandable);
}

TEST(FriBridge, AQualityDropPassesTheStartGateAgain) {
  // The servo holds the measured pose while the quality is low; the last
  // command may lie a step away. After the drop the bridge follows only a
  // desired pose within one step of what it holds.
  Harness h;
  h.engage();
  const auto following = [](BridgeStatus st) { return st == BridgeStatus::Commanding || st == BridgeStatus::Limited; };
  h.setDesired(KDL::Frame(h.measured.M, h.measured.p + KDL::Vector(0.0003, 0.0, 0.0)));
  EXPECT_TRUE(following(h.send(State::Cmd, Quality::Perfect)));
  EXPECT_EQ(h.send(State::Cmd, Quality::Bad), BridgeStatus::QualityLow);
  h.setDesired(KDL::Frame(h.measured.M, h.measured.p + KDL::Vector(0.01, 0.0, 0.0)));  // far
  EXPECT_EQ(h.send(State::Cmd, Quality::Perfect), BridgeStatus::DesiredFar);
  h.setDesired(h.measured);
  EXPECT_TRUE(following(h.send(State::Cmd, Quality::Perfect)));
}

TEST(FriBridge, NoHeapAllocationPerCycle) {
  Harness h;
  std::vector<std::vector<uint8_t>> packets;
  // Within the start gate: the bridge follows (rate-limited) after each CMD entry.
  const KDL::Frame target(h.measured.M, h.measured.p + KDL::Vector(0.0004, 0.0, 0.0));
  for (int i = 0; i < 3000; ++i) {
    const State st = i < 100 ? State::Mon : (i < 2800 ? State::Cmd : State::Mon);
    const Quality q = (i > 1000 && i < 1100) ? Quality::Bad : Quality::Perfect;
    uint16_t seq = static_cast<uint16_t>(i + 1);
    if (i % 50 == 7) seq = static_cast<uint16_t>(i - 3);  // out of order
    // A KRC at another cycle (1500-1599) and under position control (1600-1699).
    packets.push_back(makeMsr(seq, st, q, h.measured, 0x7F, (i >= 1500 && i < 1600) ? 0.002f : float(kT)));
    if (i >= 1600 && i < 1700) putU16(packets.back(), kOffControl, 1);
  }
  packets.push_back(std::vector<uint8_t>(100, 0xAB));  // malformed
  h.setDesired(target);
  uint8_t wire[kCmdPacketSize];
  std::size_t replies = 0;
  tactile::test::AllocationScope scope;
  std::size_t k = 0;
  for (const auto& b : packets) {
    h.bridge.setDryRun(k >= 2000 && k < 2200);  // the dry run's path too
    h.bridge.notePeerPort(static_cast<uint16_t>(49938 + (k++ % 2)));
    h.bridge.stepDatagram(b.data(), b.size(), h.desired, h.now, h.out);
    if (h.out.reply) {
      std::size_t n = 0;
      encodeCommand(h.out.cmd, wire, sizeof wire, n);
      replies += n;
    }
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_GT(replies, 2900u * kCmdPacketSize);
}

// FRI allows the remote to change cmdFlags in monitor mode only. The bridge
// chooses them there from the strategy the KRC reports and keeps them while
// the KRC stays in CMD, whatever the packets in CMD report.
TEST(FriBridge, CommandFlagsAreChosenInMonitorAndNeverChangeInCommand) {
  const auto packet = [](Harness& h, State st, ControlStrategy c) {
    std::vector<uint8_t> b = makeMsr(++h.seq, st, Quality::Perfect, h.measured);
    putU16(b, kOffControl, static_cast<uint16_t>(c));
    h.now += kT;
    h.desired.time_s = h.now;
    return h.bridge.stepDatagram(b.data(), b.size(), h.desired, h.now, h.out);
  };
  {  // a KRC in joint impedance: FRI_CMD_JNTPOS in MON and in CMD
    Harness h;
    for (int i = 0; i < 5; ++i) {
      EXPECT_EQ(packet(h, State::Mon, ControlStrategy::JointImpedance), BridgeStatus::WrongStrategy);
      EXPECT_EQ(h.out.cmd.cmd.cmd_flags, flags::kJointPosition);
    }
    for (int i = 0; i < 5; ++i) {
      EXPECT_EQ(packet(h, State::Cmd, ControlStrategy::JointImpedance), BridgeStatus::WrongStrategy);
      EXPECT_EQ(h.out.cmd.cmd.cmd_flags, flags::kJointPosition);
      EXPECT_FALSE(h.out.robot.commandable);
    }
  }
  {  // Cartesian impedance in MON, another strategy reported in CMD: the flags stay
    BridgeParams p;
    p.command_impedance = true;
    Harness h(p);
    const uint32_t cart = flags::kCartPose | flags::kCartStiffness | flags::kCartDamping;
    EXPECT_EQ(packet(h, State::Mon, ControlStrategy::CartImpedance), BridgeStatus::Monitor);
    EXPECT_EQ(h.out.cmd.cmd.cmd_flags, cart);
    h.setDesired(h.measured);
    EXPECT_EQ(packet(h, State::Cmd, ControlStrategy::CartImpedance), BridgeStatus::Commanding);
    const KDL::Frame last = h.commanded();
    h.setDesired(KDL::Frame(h.measured.M, h.measured.p + KDL::Vector(0.0003, 0.0, 0.0)));
    for (ControlStrategy c : {ControlStrategy::JointImpedance, ControlStrategy::Position, ControlStrategy::Other}) {
      EXPECT_EQ(packet(h, State::Cmd, c), BridgeStatus::WrongStrategy);
      EXPECT_EQ(h.out.cmd.cmd.cmd_flags, cart) << "flags changed in CMD";
      EXPECT_TRUE(KDL::Equal(h.commanded(), last, 1e-9)) << "held, nothing followed";
      EXPECT_FALSE(h.out.robot.commandable);
    }
    // Back in MON under joint impedance: the flags change there, and stay in CMD.
    EXPECT_EQ(packet(h, State::Mon, ControlStrategy::JointImpedance), BridgeStatus::WrongStrategy);
    EXPECT_EQ(h.out.cmd.cmd.cmd_flags, flags::kJointPosition);
    EXPECT_EQ(packet(h, State::Cmd, ControlStrategy::CartImpedance), BridgeStatus::WrongStrategy);
    EXPECT_EQ(h.out.cmd.cmd.cmd_flags, flags::kJointPosition);
    EXPECT_FALSE(h.out.robot.commandable) << "Cartesian poses cannot be applied with joint flags";
  }
  {  // a session whose first packet is in CMD chooses its flags there, once
    Harness h;
    EXPECT_EQ(packet(h, State::Cmd, ControlStrategy::Position), BridgeStatus::WrongStrategy);
    EXPECT_EQ(h.out.cmd.cmd.cmd_flags, flags::kJointPosition);
    EXPECT_EQ(packet(h, State::Cmd, ControlStrategy::CartImpedance), BridgeStatus::WrongStrategy);
    EXPECT_EQ(h.out.cmd.cmd.cmd_flags, flags::kJointPosition);
  }
}

// A clipped command is never silent: the status says limited, the output
// names the limit (the fri.yaml key), and each limit has its counter.
TEST(FriBridge, EveryClippedCommandNamesItsLimit) {
  BridgeParams p;
  p.max_lin_speed = 0.1;
  p.max_rot_speed = 0.5;
  Harness h(p);
  h.engage();
  EXPECT_EQ(h.out.limits, 0);
  EXPECT_STREQ(limitNames(h.out.limits), "");
  struct Case { KDL::Vector dp; double rz; uint8_t bits; const char* name; };
  const Case cases[] = {
      {KDL::Vector(0.0004, 0.0, 0.0), 0.0, limit::kMaxLinSpeed, "max_lin_speed"},        // 0.4 mm > 0.1 mm
      {KDL::Vector(0.0, 0.0, 0.0), 0.004, limit::kMaxRotSpeed, "max_rot_speed"},         // 4 mrad > 0.5 mrad
      {KDL::Vector(0.0, 0.0003, 0.0), 0.003, limit::kMaxLinSpeed | limit::kMaxRotSpeed,
       "max_lin_speed+max_rot_speed"},
      {KDL::Vector(0.00005, 0.0, 0.0), 0.0002, 0, ""}};  // within one step: not clipped
  uint64_t lin = 0, rot = 0;
  for (const Case& c : cases) {
    const KDL::Frame from = h.commanded();
    h.setDesired(KDL::Frame(from.M * KDL::Rotation::RotZ(c.rz), from.p + c.dp));
    const BridgeStatus st = h.send(State::Cmd, Quality::Perfect);
    EXPECT_EQ(st, c.bits ? BridgeStatus::Limited : BridgeStatus::Commanding) << c.name;
    EXPECT_EQ(h.out.limits, c.bits) << c.name;
    EXPECT_STREQ(limitNames(h.out.limits), c.name);
    lin += (c.bits & limit::kMaxLinSpeed) ? 1 : 0;
    rot += (c.bits & limit::kMaxRotSpeed) ? 1 : 0;
    EXPECT_EQ(h.bridge.stats().limited_lin_speed, lin) << c.name;
    EXPECT_EQ(h.bridge.stats().limited_rot_speed, rot) << c.name;
    h.setDesired(h.commanded());  // settle: the next case starts where this one was commanded
    EXPECT_EQ(h.send(State::Cmd, Quality::Perfect), BridgeStatus::Commanding);
    EXPECT_EQ(h.out.limits, 0);
  }
  // Outside CMD nothing is limited (echo), and the bits are cleared.
  EXPECT_EQ(h.send(State::Mon, Quality::Perfect), BridgeStatus::LeftCmd);
  EXPECT_EQ(h.out.limits, 0);
}

// A latched servo fault (a watchdog status on the desired pose) asks the KRL
// program to end (stop_krc_on_servo_fault): the same reply and every later
// one carry $FRI_FRM_INT[1] = 99; other servo statuses do not; off, nothing.
TEST(FriBridge, AServoWatchdogStatusRequestsTheKrcStop) {
  for (ServoStatus fault : {ServoStatus::PhaseTimeout, ServoStatus::ArmStalled, ServoStatus::ForceMismatch,
                            ServoStatus::SurfaceTooCurved, ServoStatus::PhantomContact, ServoStatus::UnseenLoad,
                            ServoStatus::CorrectionSaturated}) {
    Harness h;
    h.engage();
    for (ServoStatus s : {ServoStatus::Holding, ServoStatus::ContactLost, ServoStatus::ForceCeiling,
                          ServoStatus::WaitingForRobot, ServoStatus::Done, ServoStatus::InvalidInput}) {
      h.desired.status = s;
      h.send(State::Cmd, Quality::Perfect);
      EXPECT_FALSE(h.out.stop_requested) << toString(s);
      EXPECT_EQ(h.out.cmd.krl.int_data[0], 0) << toString(s);
    }
    EXPECT_EQ(h.bridge.stopCause(), ServoStatus::Ok);
    h.desired.status = fault;
    h.send(State::Cmd, Quality::Perfect);
    EXPECT_TRUE(h.out.stop_requested) << toString(fault);
    EXPECT_EQ(h.out.cmd.krl.int_data[0], krl::kRequestStop) << "the reply to the fault's packet";
    EXPECT_EQ(h.bridge.stopCause(), fault);
    h.desired.status = ServoStatus::Ok;  // latched: a later status does not withdraw it
    h.send(State::Mon, Quality::Perfect);
    EXPECT_EQ(h.out.cmd.krl.int_data[0], krl::kRequestStop);
    EXPECT_TRUE(h.bridge.stopRequested());
  }
  BridgeParams off;
  off.stop_krc_on_servo_fault = false;
  Harness h(off);
  h.engage();
  h.desired.status = ServoStatus::PhantomContact;
  h.send(State::Cmd, Quality::Perfect);
  EXPECT_FALSE(h.out.stop_requested);
  EXPECT_EQ(h.out.cmd.krl.int_data[0], 0);
  // requestStop() alone names no cause; configure() clears both.
  h.bridge.requestStop();
  EXPECT_EQ(h.bridge.stopCause(), ServoStatus::Ok);
  ASSERT_TRUE(h.bridge.configure(BridgeParams{}).ok());
  EXPECT_FALSE(h.bridge.stopRequested());
}
