// fri.cart_offset: how the bridge reads the KRC's set point from cmdCartPos
// and cmdCartPosFriOffset (none | composed | elementwise), against the
// simulated KRC (KrcModel) sending each form. The resume after a quality drop
// and after the drives went off: no jump, no hold in desired_far; a KRC
// sending another form than the bridge reads: offset_mismatch and a hold.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "tactile_fri/bridge.hpp"
#include "tactile_fri/krc_model.hpp"
#include "tactile_fri/params_io.hpp"

using namespace tactile;
using namespace tactile::fri;

namespace {

constexpr double kT = 0.001;
constexpr double kPosTol = 2e-7;  // float wire quantisation of a step (m)
constexpr double kRotTol = 2e-6;  // rad

const KDL::Frame kStart(KDL::Rotation::RPY(3.14159265358979, 0.1, -0.2), KDL::Vector(0.5, 0.1, 0.4));

double dist(const KDL::Frame& a, const KDL::Frame& b) { return (a.p - b.p).Norm(); }
double angle(const KDL::Frame& a, const KDL::Frame& b) {
  KDL::Vector axis;
  return rotationAngle(a.M.Inverse() * b.M, axis);
}

/// The KRC, the bridge and a servo as the real one behaves towards the
/// bridge: while the robot state is not commandable its command is the
/// measured pose; otherwise it moves on from its last command at a constant
/// twist (0.02 m/s along x, 0.05 rad/s about the flange z).
struct Loop {
  KrcModel krc;
  FriBridge bridge;
  PlantState plant;
  std::array<uint8_t, 2048> wire{};
  MsrPacket msr{};
  BridgeOutput out;
  PoseCommand desired;
  KDL::Frame servo = kStart;
  bool commandable = false;
  // what the run saw
  int desired_far = 0, desired_far_run = 0, max_desired_far_run = 0;
  int offset_mismatch = 0;
  double first_mismatch_t = -1.0;

  Loop(CartOffset krc_form, CartOffset bridge_form) {
    KrcModelParams kp;
    kp.cart_offset = krc_form;
    EXPECT_TRUE(krc.configure(kp).ok());
    BridgeParams bp;
    bp.cart_offset = bridge_form;
    bp.max_lin_speed = 0.05;
    bp.max_rot_speed = 0.25;
    EXPECT_TRUE(bridge.configure(bp).ok());
    plant.pose = kStart;
    krc.reset(plant.pose);
    desired.status = ServoStatus::Ok;
  }
  void cycle(double t, State s, Quality q, uint16_t power) {
    krc.setState(s, q, power);
    krc.holdUnlessCommanding(plant.pose);
    plant.pose = krc.setPoint();  // the arm follows the set point exactly (free space)
    krc.buildMeasurement(plant, t, msr);
    // the servo, from the previous robot state
    if (!commandable) {
      servo = plant.pose;
    } else {
      servo.p = servo.p + KDL::Vector(0.02 * kT, 0.0, 0.0);
      servo.M = servo.M * KDL::Rotation::RotZ(0.05 * kT);
    }
    toPose(servo, desired.pose);
    desired.time_s = t;
    std::size_t n = 0;
    ASSERT_EQ(encodeMeasurement(msr, wire.data(), wire.size(), n), PacketStatus::Ok);
    bridge.stepDatagram(wire.data(), n, desired, t, out);
    commandable = out.robot.commandable;
    if (out.status == BridgeStatus::DesiredFar) {
      ++desired_far;
      max_desired_far_run = std::max(max_desired_far_run, ++desired_far_run);
    } else {
      desired_far_run = 0;
    }
    if (out.status == BridgeStatus::OffsetMismatch) {
      if (offset_mismatch++ == 0) first_mismatch_t = t;
    }
    ASSERT_TRUE(out.reply) << toString(out.status);
    ASSERT_EQ(encodeCommand(out.cmd, wire.data(), wire.size(), n), PacketStatus::Ok);
    ASSERT_EQ(krc.handleReply(wire.data(), n), ReplyResult::Matched);
  }
  /// MON 0.05 s, CMD; quality BAD over [2.0, 2.3) s; drives off over
  /// [3.0, 3.3) s; until 4.5 s. Returns the set point before the quality drop.
  KDL::Frame run() {
    KDL::Frame before_drop;
    for (int k = 0; k < 4500; ++k) {
      const double t = kT * k;
      const State s = t < 0.05 ? State::Mon : State::Cmd;
      const Quality q = (t >= 2.0 && t < 2.3) ? Quality::Bad : Quality::Perfect;
      const uint16_t power = (t >= 3.0 && t < 3.3) ? 0 : 0x7F;
      if (k == 2000) before_drop = krc.setPoint();
      cycle(t, s, q, power);
      if (::testing::Test::HasFatalFailure()) break;
    }
    return before_drop;
  }
};

struct Form {
  CartOffset krc, bridge;
};
std::string name(const ::testing::TestParamInfo<Form>& i) {
  return std::string("krc_") + toString(i.param.krc) + "_bridge_" + toString(i.param.bridge);
}

}  // namespace

TEST(CartOffset, EachFormRoundTripsAndTheOthersDoNotReadIt) {
  const KDL::Frame krl = kStart;
  const KDL::Frame sp(kStart.M * KDL::Rotation::RotZ(0.2), kStart.p + KDL::Vector(0.04, -0.01, 0.02));
  for (CartOffset sent : {CartOffset::None, CartOffset::Composed, CartOffset::Elementwise}) {
    float c[kCartFrameDim], o[kCartFrameDim];
    writeSetPoint(krl, sp, sent, c, o);
    for (CartOffset read : {CartOffset::None, CartOffset::Composed, CartOffset::Elementwise}) {
      KDL::Frame got = KDL::Frame::Identity();
      const bool ok = readSetPoint(c, o, read, got);
      const bool right = ok && dist(got, sp) < 1e-6 && angle(got, sp) < 1e-5;
      const std::string what = std::string("sent ") + toString(sent) + ", read " + toString(read);
      if (sent == read || sent == CartOffset::None) {
        EXPECT_TRUE(right) << what;  // a zero offset reads the same in every form
      } else if (read == CartOffset::None) {
        EXPECT_TRUE(ok) << what;  // cmdCartPos alone: the KRL program's pose, not the set point
        EXPECT_NEAR(dist(got, krl), 0.0, 1e-6) << what;
      } else {
        EXPECT_FALSE(ok) << what << ": the other form's offset is no frame / the sum no rotation";
      }
    }
  }
  CartOffset f = CartOffset::None;
  EXPECT_TRUE(parseCartOffset("elementwise", f));
  EXPECT_EQ(f, CartOffset::Elementwise);
  EXPECT_FALSE(parseCartOffset("additive", f));
  EXPECT_EQ(f, CartOffset::Elementwise);
}

TEST(CartOffset, FriYamlKeyIsReadAndAWrongWordNamesTheKey) {
  BridgeParams bp;
  UdpParams up;
  YAML::Node n = YAML::Load("{cart_offset: elementwise, setpoint_max_dev: 0.02, setpoint_max_dev_rot: 0.1}");
  ASSERT_TRUE(loadBridgeParams(n, config::Where{"fri.yaml", "fri"}, bp, up).ok());
  EXPECT_EQ(bp.cart_offset, CartOffset::Elementwise);
  EXPECT_DOUBLE_EQ(bp.setpoint_max_dev, 0.02);
  EXPECT_DOUBLE_EQ(bp.setpoint_max_dev_rot, 0.1);
  n = YAML::Load("{cart_offset: additive}");
  const ConfigResult r = loadBridgeParams(n, config::Where{"fri.yaml", "fri"}, bp, up);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("fri.cart_offset"), std::string::npos) << r.message();
  EXPECT_NE(r.message().find("elementwise"), std::string::npos) << r.message();
  n = YAML::Load("{setpoint_max_dev: 0}");
  EXPECT_FALSE(loadBridgeParams(n, config::Where{"fri.yaml", "fri"}, bp, up).ok());
}

// The KRC sends the form the bridge reads: the resume after a quality drop and
// after the drives went off is one limited step at most, and the bridge
// follows again at once (the servo's measured pose is the bridge's held pose).
class CartOffsetMatched : public ::testing::TestWithParam<Form> {};

TEST_P(CartOffsetMatched, ResumesAfterQualityDropAndDrivesOffWithoutJumpOrDesiredFar) {
  Loop l(GetParam().krc, GetParam().bridge);
  const KDL::Frame before_drop = l.run();
  ASSERT_FALSE(HasFatalFailure());
  const KrcModelStats& s = l.krc.stats();
  EXPECT_LE(s.max_cmd_step_m, 0.05 * kT + kPosTol) << "every applied step within max_lin_speed";
  EXPECT_LE(s.max_cmd_step_rad, 0.25 * kT + kRotTol) << "every applied step within max_rot_speed";
  EXPECT_LE(s.max_entry_offset_m, 0.05 * kT + kPosTol) << "no jump on resuming";
  EXPECT_LE(s.max_entry_offset_rad, 0.25 * kT + kRotTol);
  EXPECT_EQ(s.mon_echo_errors, 0u) << "drives off: the echo is the KRC's set point";
  EXPECT_EQ(s.flag_errors, 0u);
  EXPECT_EQ(l.offset_mismatch, 0);
  EXPECT_LE(l.max_desired_far_run, 2) << "never stuck in desired_far";
  EXPECT_EQ(l.out.status, BridgeStatus::Commanding);
  EXPECT_TRUE(l.out.robot.commandable);
  // 4.5 s less 0.05 s MON, 0.6 s held: 3.85 s at 0.02 m/s (the offset is far from zero)
  EXPECT_NEAR(l.krc.setPoint().p.x() - kStart.p.x(), 0.02 * 3.85, 2e-3);
  EXPECT_GT(dist(l.krc.setPoint(), before_drop), 0.03) << "it moved on after both resumes";
  if (GetParam().krc != CartOffset::None) {
    KDL::Frame c;
    toFrame(l.msr.data.cmd_cart_pos, c);
    EXPECT_GT(dist(c, l.krc.setPoint()), 0.05) << "cmdCartPos alone is far from the set point";
  }
}

INSTANTIATE_TEST_SUITE_P(Forms, CartOffsetMatched,
                         ::testing::Values(Form{CartOffset::None, CartOffset::None},
                                           Form{CartOffset::None, CartOffset::Composed},
                                           Form{CartOffset::None, CartOffset::Elementwise},
                                           Form{CartOffset::Composed, CartOffset::Composed},
                                           Form{CartOffset::Elementwise, CartOffset::Elementwise}),
                         name);

// The KRC sends another form than the bridge reads. Read as fri.yaml says, the
// set point would be the KRL program's pose (centimetres away: a jump, or a
// hold in desired_far for good) or no pose at all. The bridge names it
// (offset_mismatch, the robot state not commandable) and holds: every applied
// command within one limited step of the KRC's set point, nothing followed.
class CartOffsetMismatched : public ::testing::TestWithParam<Form> {};

TEST_P(CartOffsetMismatched, IsNamedAndHeldNeverAJump) {
  Loop l(GetParam().krc, GetParam().bridge);
  l.run();
  ASSERT_FALSE(HasFatalFailure());
  const KrcModelStats& s = l.krc.stats();
  EXPECT_GT(l.offset_mismatch, 0);
  EXPECT_EQ(l.out.status, BridgeStatus::OffsetMismatch) << toString(l.out.status);
  EXPECT_STREQ(toString(l.out.status), "offset_mismatch");
  EXPECT_TRUE(l.out.mismatch & mismatch::kOffset);
  EXPECT_FALSE(l.out.robot.commandable);
  EXPECT_FALSE(l.out.robot.config_ok);
  EXPECT_LE(s.max_cmd_step_m, 0.05 * kT + kPosTol);
  EXPECT_LE(s.max_cmd_step_rad, 0.25 * kT + kRotTol);
  EXPECT_LE(s.max_entry_offset_m, 0.05 * kT + kPosTol) << "no jump on resuming";
  EXPECT_LE(s.max_entry_offset_rad, 0.25 * kT + kRotTol);
  // Held from the detection on: the set point stays where it was then.
  const double moved = l.krc.setPoint().p.x() - kStart.p.x();
  EXPECT_LE(moved, 0.02 * std::max(0.0, l.first_mismatch_t - 0.05) + 1e-4) << "nothing followed after the detection";
  // What reading it as fri.yaml says would have given.
  KDL::Frame read;
  const bool readable = readSetPoint(l.msr.data.cmd_cart_pos, l.msr.data.cmd_cart_pos_fri_offset,
                                     GetParam().bridge, read);
  if (readable) {
    EXPECT_GT(dist(read, l.krc.setPoint()), 0.01) << "the wrong reading is centimetres off";
  }
}

INSTANTIATE_TEST_SUITE_P(Forms, CartOffsetMismatched,
                         ::testing::Values(Form{CartOffset::Elementwise, CartOffset::Composed},
                                           Form{CartOffset::Composed, CartOffset::Elementwise},
                                           Form{CartOffset::Composed, CartOffset::None},
                                           Form{CartOffset::Elementwise, CartOffset::None}),
                         name);
