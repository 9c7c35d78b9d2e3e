// YAML parameter files for the FRI bridge: values land in the structs, and
// every error names the file, the key and the valid range.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include "tactile_fri/params_io.hpp"

using namespace tactile;
using namespace tactile::fri;

namespace {
ConfigResult loadString(const std::string& text, BridgeParams& bp, UdpParams& up) {
  const YAML::Node root = YAML::Load(text);
  return loadBridgeParams(root["fri"], config::Where{"test.yaml", "fri"}, bp, up);
}
}  // namespace

TEST(FriParams, ShippedFileLoadsAndMatchesDefaults) {
  BridgeParams bp;
  UdpParams up;
  up.port = 1;
  const ConfigResult r = loadBridgeParamsFile(FRI_PARAMS_FILE, bp, up);
  ASSERT_TRUE(r.ok()) << r.message();
  const BridgeParams d;
  // The rate limits of the shipped file cover the robot programs' speeds
  // (params/fri.yaml; scripts/tools/check_robot_limits.py checks each
  // program against them); the struct keeps the tighter bring-up defaults.
  EXPECT_DOUBLE_EQ(bp.max_lin_speed, 0.15);
  EXPECT_DOUBLE_EQ(bp.max_rot_speed, 1.0);
  EXPECT_LT(d.max_lin_speed, bp.max_lin_speed);
  EXPECT_LT(d.max_rot_speed, bp.max_rot_speed);
  EXPECT_EQ(bp.resync_after, d.resync_after);
  EXPECT_EQ(bp.cart_stiffness, d.cart_stiffness);
  EXPECT_EQ(up.port, kDefaultPort);
  EXPECT_EQ(up.bind_address, "0.0.0.0");
}

TEST(FriParams, ValuesAreRead) {
  BridgeParams bp;
  UdpParams up;
  const ConfigResult r = loadString(
      "fri: {max_lin_speed: 0.02, rewind_on_refl: false, cart_damping: [0.5, 0.5, 0.5, 0.6, 0.6, 0.6],"
      " udp: {bind_address: 127.0.0.1, port: 0}}",
      bp, up);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_DOUBLE_EQ(bp.max_lin_speed, 0.02);
  EXPECT_FALSE(bp.rewind_on_refl);
  EXPECT_DOUBLE_EQ(bp.cart_damping[3], 0.6);
  EXPECT_EQ(up.port, 0);
  EXPECT_EQ(up.bind_address, "127.0.0.1");
}

TEST(FriParams, ErrorsNameFileKeyAndRange) {
  BridgeParams bp;
  UdpParams up;
  ConfigResult r = loadString("fri: {max_lin_sped: 0.1}", bp, up);  // typo
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.message().find("max_lin_sped"), std::string::npos) << r.message();
  r = loadString("fri: {max_rot_speed: 7}", bp, up);
  EXPECT_NE(r.message().find("test.yaml: fri.max_rot_speed = 7: must be in (0, 3] (rad/s)"), std::string::npos)
      << r.message();
  bp = BridgeParams{};
  r = loadString("fri: {cart_stiffness: [1, 2, 3]}", bp, up);
  EXPECT_NE(r.message().find("cart_stiffness (length)"), std::string::npos) << r.message();
  r = loadString("fri: {udp: {port: 70000}}", bp, up);
  EXPECT_NE(r.message().find("test.yaml: fri.udp.port = 70000: must be in [0, 65535]"), std::string::npos)
      << r.message();
  r = loadString("fri: {resync_after: many}", bp, up);
  EXPECT_NE(r.message().find("fri.resync_after"), std::string::npos) << r.message();
  r = loadBridgeParamsFile("/nonexistent/fri.yaml", bp, up);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.message().find("/nonexistent/fri.yaml"), std::string::npos) << r.message();
}

TEST(FriParams, WrenchFrameIsReadAndOtherWordsAreNamed) {
  BridgeParams bp;
  UdpParams up;
  EXPECT_EQ(bp.wrench_frame, WrenchFrame::Base);  // the shipped fri.yaml's, and the default
  ConfigResult r = loadString("fri: {wrench_frame: tool}", bp, up);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(bp.wrench_frame, WrenchFrame::Tool);
  r = loadString("fri: {wrench_frame: flange}", bp, up);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("fri.wrench_frame: 'flange' is not base or tool"), std::string::npos) << r.message();
  EXPECT_NE(r.message().find("$STIFFNESS.FRAMETYPE"), std::string::npos) << r.message();
}
