// FRI protocol core: byte layout (checked against hand-written offsets),
// decode/encode, status for every malformed case, pose/wrench conversions,
// sequence arithmetic, and a deterministic fuzz smoke run.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "fri_test_util.hpp"
#include "tactile_fri/bridge.hpp"
#include "tactile_fri/protocol.hpp"

using namespace tactile;
using namespace tactile::fri;
using namespace fri_test;

TEST(FriProtocol, SizesMatchTheProtocol) {
  EXPECT_EQ(sizeof(MsrPacket), 916u);
  EXPECT_EQ(sizeof(CmdPacket), 376u);
  EXPECT_EQ(kDatagramIdMsr, 0x2006);
  EXPECT_EQ(kDatagramIdCmd, 0x1005);
  EXPECT_EQ(kDefaultPort, 49938);
}

TEST(FriProtocol, DecodesFieldsAtHandWrittenOffsets) {
  std::vector<uint8_t> b = makeMsr(0xBEEF, State::Cmd, Quality::Ok, startPose(), 0x55);
  putU16(b, 2, 0x1234);  // reflSeqCount
  putU32(b, 8 + 64, static_cast<uint32_t>(-7));  // krl.intData[0]
  putF32(b, kOffMsrJnt + 8, 0.25f);               // msrJntPos[2]
  putF32(b, kOffExtFT + 12, 3.0f);                // Tz on the wire
  putF32(b, kOffExtFT + 20, 5.0f);                // Tx on the wire
  putF32(b, kOffGravity + 24, -9.5f);             // gravity[6], the last field
  MsrPacket m;
  ASSERT_EQ(decodeMeasurement(b.data(), b.size(), m), PacketStatus::Ok);
  EXPECT_EQ(m.head.send_seq, 0xBEEF);
  EXPECT_EQ(m.head.refl_seq, 0x1234);
  EXPECT_EQ(m.krl.int_data[0], -7);
  EXPECT_EQ(stateOf(m), State::Cmd);
  EXPECT_EQ(qualityOf(m), Quality::Ok);
  EXPECT_EQ(m.robot.power, 0x55);
  EXPECT_EQ(m.robot.control, static_cast<uint16_t>(ControlStrategy::CartImpedance));
  EXPECT_FLOAT_EQ(m.intf.desired_cmd_sample_time, 0.001f);
  EXPECT_FLOAT_EQ(m.data.msr_jnt_pos[2], 0.25f);
  EXPECT_FLOAT_EQ(m.data.gravity[6], -9.5f);
  EXPECT_FLOAT_EQ(m.data.msr_cart_pos[3], 0.5f);
  EXPECT_FLOAT_EQ(m.data.msr_cart_pos[7], -0.1f);
  EXPECT_FLOAT_EQ(m.data.msr_cart_pos[11], 0.4f);
  const std::array<double, 6> w = toWrench(m.data.est_ext_tcp_ft);  // [Fx Fy Fz Tx Ty Tz]
  EXPECT_DOUBLE_EQ(w[3], 5.0);
  EXPECT_DOUBLE_EQ(w[5], 3.0);
}

TEST(FriProtocol, EncodesCommandAtHandWrittenOffsets) {
  CmdPacket c{};
  c.head.send_seq = 7;
  c.head.refl_seq = 9;
  c.cmd.cmd_flags = flags::kCartPose | flags::kCartStiffness;
  fromFrame(startPose(), c.cmd.cart_pos);
  c.cmd.cart_damping[5] = 0.7f;
  uint8_t buf[400];
  std::size_t n = 0;
  ASSERT_EQ(encodeCommand(c, buf, sizeof buf, n), PacketStatus::Ok);
  ASSERT_EQ(n, 376u);
  EXPECT_EQ(getU16(buf, 0), 7);
  EXPECT_EQ(getU16(buf, 2), 9);
  EXPECT_EQ(getU16(buf, 4), 376);
  EXPECT_EQ(buf[6], 0x05);
  EXPECT_EQ(buf[7], 0x10);
  EXPECT_EQ(getU32(buf, kOffCmdFlags), 0x1100u);
  EXPECT_FLOAT_EQ(getF32(buf, kOffCmdCart + 12), 0.5f);
  EXPECT_FLOAT_EQ(getF32(buf, kOffCmdCart + 44), 0.4f);
  EXPECT_FLOAT_EQ(getF32(buf, 372), 0.7f);  // cartDamping[5] = the last 4 bytes
  CmdPacket back;
  ASSERT_EQ(decodeCommand(buf, n, back), PacketStatus::Ok);
  EXPECT_EQ(std::memcmp(back.cmd.cart_pos, c.cmd.cart_pos, sizeof c.cmd.cart_pos), 0);
  EXPECT_EQ(back.cmd.cmd_flags, c.cmd.cmd_flags);
  EXPECT_EQ(encodeCommand(c, buf, 375, n), PacketStatus::BufferTooSmall);
  EXPECT_EQ(n, 0u);
}

TEST(FriProtocol, EveryMalformedCaseHasItsStatus) {
  const std::vector<uint8_t> good = makeMsr(1, State::Mon, Quality::Perfect, startPose());
  MsrPacket m{};
  m.head.send_seq = 4242;  // sentinel: must stay untouched on failure
  EXPECT_EQ(decodeMeasurement(nullptr, 916, m), PacketStatus::NullBuffer);
  EXPECT_EQ(decodeMeasurement(good.data(), 0, m), PacketStatus::TooShort);
  EXPECT_EQ(decodeMeasurement(good.data(), 915, m), PacketStatus::TooShort);
  std::vector<uint8_t> longer = good;
  longer.push_back(0);
  EXPECT_EQ(decodeMeasurement(longer.data(), longer.size(), m), PacketStatus::TooLong);
  std::vector<uint8_t> b = good;
  putU16(b, 4, 915);
  EXPECT_EQ(decodeMeasurement(b.data(), b.size(), m), PacketStatus::SizeFieldMismatch);
  b = good;
  putU16(b, 6, 0x1005);
  EXPECT_EQ(decodeMeasurement(b.data(), b.size(), m), PacketStatus::WrongDatagramId);
  b = good;
  putU16(b, kOffState, 3);
  EXPECT_EQ(decodeMeasurement(b.data(), b.size(), m), PacketStatus::BadState);
  b = good;
  putU16(b, kOffQuality, 4);
  EXPECT_EQ(decodeMeasurement(b.data(), b.size(), m), PacketStatus::BadQuality);
  EXPECT_EQ(m.head.send_seq, 4242);
  // A command packet is not a measurement, and vice versa.
  CmdPacket c;
  EXPECT_EQ(decodeCommand(good.data(), good.size(), c), PacketStatus::TooLong);
  EXPECT_EQ(decodeMeasurement(good.data(), good.size(), m), PacketStatus::Ok);
  EXPECT_STREQ(toString(PacketStatus::WrongDatagramId), "wrong_datagram_id");
}

TEST(FriProtocol, PoseConversionsRoundTrip) {
  // Tolerance 1e-6: the wire carries 4-byte floats (relative precision 6e-8).
  const KDL::Frame f = startPose();
  float m[kCartFrameDim];
  fromFrame(f, m);
  EXPECT_TRUE(validFriPose(m));
  KDL::Frame g;
  toFrame(m, g);
  EXPECT_TRUE(KDL::Equal(f, g, 1e-6));
  Pose p;
  toPose(g, p);
  EXPECT_TRUE(validPose(p));
  KDL::Frame h;
  toFrame(p, h);
  // g's rotation is orthonormal only to float precision; the quaternion round
  // trip re-normalises it, so the same 1e-6 tolerance applies.
  EXPECT_TRUE(KDL::Equal(g, h, 1e-6));
  // Row-major: m[3], m[7], m[11] are the translation.
  EXPECT_FLOAT_EQ(m[3], 0.5f);
  EXPECT_FLOAT_EQ(m[1], float(f.M(0, 1)));
  EXPECT_FLOAT_EQ(m[4], float(f.M(1, 0)));
  // Invalid poses.
  float bad[kCartFrameDim];
  std::memcpy(bad, m, sizeof bad);
  bad[5] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(validFriPose(bad));
  std::memcpy(bad, m, sizeof bad);
  bad[0] *= 2.0f;
  EXPECT_FALSE(validFriPose(bad));
  std::memcpy(bad, m, sizeof bad);
  for (int c = 0; c < 3; ++c) bad[c] = -bad[c];  // reflection: det = -1
  EXPECT_FALSE(validFriPose(bad));
  Pose q;
  q.q = {0.0, 0.0, 0.0, 2.0};
  EXPECT_FALSE(validPose(q));
  q.q = {0.0, 0.0, 0.0, 1.0};
  q.p[1] = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(validPose(q));
}

TEST(FriProtocol, RotationAngleIsAccurateForSmallAngles) {
  KDL::Vector axis;
  const double a = rotationAngle(KDL::Rotation::Rot(KDL::Vector(1, 2, 3), 1e-5), axis);
  EXPECT_NEAR(a, 1e-5, 1e-12);  // KDL's GetRotAngle would report 0 here
  EXPECT_NEAR(axis.y(), 2.0 / std::sqrt(14.0), 1e-6);
  EXPECT_NEAR(rotationAngle(KDL::Rotation::RotZ(3.0), axis), 3.0, 1e-12);
  EXPECT_DOUBLE_EQ(rotationAngle(KDL::Rotation::Identity(), axis), 0.0);
}

TEST(FriProtocol, WrenchOrderConversionRoundTrips) {
  const std::array<double, 6> w{{1, 2, 3, 4, 5, 6}};
  float ft[6];
  fromWrench(w, ft);
  EXPECT_FLOAT_EQ(ft[3], 6.0f);  // Tz first on the wire
  EXPECT_FLOAT_EQ(ft[5], 4.0f);  // Tx last
  EXPECT_EQ(toWrench(ft), w);
}

TEST(FriProtocol, SequenceDeltaWrapsAround) {
  EXPECT_EQ(seqDelta(65535, 0), 1);
  EXPECT_EQ(seqDelta(65530, 4), 10);
  EXPECT_EQ(seqDelta(4, 65530), -10);
  EXPECT_EQ(seqDelta(100, 100), 0);
  EXPECT_EQ(seqDelta(0, 32767), 32767);
  EXPECT_EQ(seqDelta(0, 32768), -32768);
}

// Fuzz smoke: thousands of random and mutated datagrams (fixed seed) through
// the decoder AND the bridge: never a crash, always a status from the enum, no
// reply to anything malformed, every reply finite with a valid rotation; and a
// good packet still decodes and is answered afterwards.
TEST(FriProtocol, FuzzSmokeNeverCrashesAndRecovers) {
  std::mt19937 rng(20260101u);
  FriBridge bridge;
  ASSERT_TRUE(bridge.configure(BridgeParams{}).ok());
  PoseCommand desired;
  desired.status = ServoStatus::Ok;
  toPose(startPose(), desired.pose);
  const std::vector<uint8_t> good = makeMsr(1, State::Cmd, Quality::Perfect, startPose());
  std::vector<uint8_t> buf(1500);
  BridgeOutput out;
  int ok = 0, replies = 0, malformed = 0;
  const int kIterations = 20000;
  for (int i = 0; i < kIterations; ++i) {
    std::size_t n;
    const int mode = i % 4;
    if (mode == 0) {  // fully random bytes, random length
      n = rng() % 1200;
      for (std::size_t k = 0; k < n; ++k) buf[k] = static_cast<uint8_t>(rng());
    } else {  // mutate a good packet: bit flips, byte sets, truncation/extension
      n = good.size();
      std::copy(good.begin(), good.end(), buf.begin());
      const int flips = 1 + int(rng() % 8);
      for (int k = 0; k < flips; ++k) {
        const std::size_t at = rng() % n;
        if (mode == 1) buf[at] ^= static_cast<uint8_t>(1u << (rng() % 8));
        else buf[at] = static_cast<uint8_t>(rng());
      }
      if (mode == 3 && rng() % 2) n = rng() % 1000;
      if (rng() % 3 == 0) putU16(buf, 0, static_cast<uint16_t>(i));  // keep the sequence moving
    }
    MsrPacket m;
    const PacketStatus ps = decodeMeasurement(buf.data(), n, m);
    ASSERT_LE(static_cast<int>(ps), static_cast<int>(PacketStatus::BufferTooSmall));
    const BridgeStatus bs = bridge.stepDatagram(buf.data(), n, desired, 0.0, out);
    ASSERT_LE(static_cast<int>(bs), static_cast<int>(BridgeStatus::NotConfigured));
    EXPECT_EQ(out.packet_status, ps);
    if (ps != PacketStatus::Ok) {
      ++malformed;
      ASSERT_FALSE(out.reply);
      ASSERT_EQ(bs, BridgeStatus::Malformed);
    } else {
      ++ok;
    }
    if (out.reply) {
      ++replies;
      for (float v : out.cmd.cmd.cart_pos) ASSERT_TRUE(std::isfinite(v));
      ASSERT_TRUE(validFriPose(out.cmd.cmd.cart_pos));
    }
  }
  EXPECT_GT(ok, 1000);        // the mutations must exercise the accepted path...
  EXPECT_GT(malformed, 5000); // ...and the rejecting one
  EXPECT_GT(replies, 100);
  // Recovery: fresh good packets are decoded and answered (at most
  // resync_after packets are needed if the fuzz left the counter far ahead).
  const uint16_t base = static_cast<uint16_t>(bridge.lastMeasurement().head.send_seq + 1000);
  bool answered = false;
  for (int k = 0; k < BridgeParams{}.resync_after && !answered; ++k) {
    std::vector<uint8_t> again = makeMsr(static_cast<uint16_t>(base + k), State::Mon, Quality::Perfect, startPose());
    MsrPacket m;
    ASSERT_EQ(decodeMeasurement(again.data(), again.size(), m), PacketStatus::Ok);
    bridge.stepDatagram(again.data(), again.size(), desired, 0.0, out);
    answered = out.reply;
  }
  ASSERT_TRUE(answered);
  EXPECT_TRUE(KDL::Equal(cmdPose(reinterpret_cast<const uint8_t*>(&out.cmd)), startPose(), 1e-6));
}
