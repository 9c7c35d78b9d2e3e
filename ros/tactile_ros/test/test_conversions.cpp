// The conversions of tactile_ros/conversions.hpp, without RTT and without a
// ROS master: each message field against the port sample it came from.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "tactile_ros/conversions.hpp"

namespace {

using tactile_ros::contactPose;
using tactile_ros::inContact;

tactile::Pose rotZ(double a, std::array<double, 3> p) {
  tactile::Pose pose;
  pose.p = p;
  pose.q = {0.0, 0.0, std::sin(a / 2), std::cos(a / 2)};
  return pose;
}

TEST(RosConversions, StampIsTimePlusOffsetAndRejectsNonFinite) {
  ros::Time t;
  EXPECT_TRUE(tactile_ros::toStamp(1.25, 1000.0, t));
  EXPECT_EQ(t.sec, 1001u);
  EXPECT_EQ(t.nsec, 250000000u);
  EXPECT_FALSE(tactile_ros::toStamp(std::nan(""), 0.0, t));
  EXPECT_TRUE(t.isZero());
  EXPECT_FALSE(tactile_ros::toStamp(-2.0, 1.0, t));
  EXPECT_TRUE(t.isZero());
}

TEST(RosConversions, ImageIsRowMajor32FC1Newtons) {
  tactile::TactileFrame f;
  f.seq = 7;
  for (int r = 0; r < f.rows; ++r)
    for (int c = 0; c < f.cols; ++c) f.at(r, c) = 0.5 * r + 0.01 * c;
  sensor_msgs::Image img;
  ASSERT_TRUE(tactile_ros::toImage(f, ros::Time(3.0), "wts0614", img));
  EXPECT_EQ(img.encoding, "32FC1");
  EXPECT_EQ(img.height, 6u);
  EXPECT_EQ(img.width, 14u);
  EXPECT_EQ(img.step, 14u * 4u);
  EXPECT_EQ(img.is_bigendian, 0);
  EXPECT_EQ(img.header.frame_id, "wts0614");
  EXPECT_EQ(img.header.seq, 7u);
  EXPECT_DOUBLE_EQ(img.header.stamp.toSec(), 3.0);
  ASSERT_EQ(img.data.size(), 6u * 14u * 4u);
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 14; ++c) {
      float v;
      std::memcpy(&v, &img.data[static_cast<std::size_t>(r * img.step + c * 4)], 4);
      EXPECT_FLOAT_EQ(v, static_cast<float>(0.5 * r + 0.01 * c)) << r << "," << c;
    }
}

TEST(RosConversions, ImageOfABadSizeIsEmptyAndFalse) {
  tactile::TactileFrame f;
  f.rows = tactile::kMaxRows + 1;
  sensor_msgs::Image img;
  EXPECT_FALSE(tactile_ros::toImage(f, ros::Time(1.0), "s", img));
  EXPECT_TRUE(img.data.empty());
  EXPECT_EQ(img.height, 0u);
  f.rows = 0;
  EXPECT_FALSE(tactile_ros::toImage(f, ros::Time(1.0), "s", img));
}

TEST(RosConversions, FeaturesFieldByField) {
  tactile::ContactFeatures f;
  f.seq = 11;
  f.cop_x = 0.001; f.cop_y = -0.002;
  f.coc_x = 0.003; f.coc_y = -0.004;
  f.dzmp_x = 0.005; f.dzmp_y = -0.006;
  f.alpha_z = 0.3; f.alpha_defined = true;
  f.force = 4.5; f.d_z = 1e-4;
  f.lambda1 = 2e-5; f.lambda2 = 1e-6; f.curvature = 3.5;
  f.max_taxel = 0.8; f.area = 9;
  f.contact = tactile::ContactType::Edge;
  f.status = tactile::FeatureStatus::Saturated;
  tactile_msgs::ContactFeatures m;
  tactile_ros::toFeatures(f, ros::Time(2.0), "wts0614", m);
  EXPECT_EQ(m.header.frame_id, "wts0614");
  EXPECT_EQ(m.seq, 11u);
  EXPECT_DOUBLE_EQ(m.cop_x, 0.001); EXPECT_DOUBLE_EQ(m.cop_y, -0.002);
  EXPECT_DOUBLE_EQ(m.coc_x, 0.003); EXPECT_DOUBLE_EQ(m.coc_y, -0.004);
  EXPECT_DOUBLE_EQ(m.dzmp_x, 0.005); EXPECT_DOUBLE_EQ(m.dzmp_y, -0.006);
  EXPECT_DOUBLE_EQ(m.alpha_z, 0.3); EXPECT_TRUE(m.alpha_defined);
  EXPECT_DOUBLE_EQ(m.force, 4.5); EXPECT_DOUBLE_EQ(m.d_z, 1e-4);
  EXPECT_DOUBLE_EQ(m.lambda1, 2e-5); EXPECT_DOUBLE_EQ(m.lambda2, 1e-6);
  EXPECT_DOUBLE_EQ(m.curvature, 3.5);
  EXPECT_DOUBLE_EQ(m.max_taxel, 0.8);
  EXPECT_EQ(m.area, 9);
  EXPECT_EQ(m.contact, tactile_msgs::ContactFeatures::CONTACT_EDGE);
  EXPECT_EQ(m.status, tactile_msgs::ContactFeatures::STATUS_SATURATED);
}

TEST(RosConversions, MessageConstantsMatchTheProjectEnums) {
  EXPECT_EQ(tactile_msgs::ContactFeatures::CONTACT_MULTIPLE, static_cast<uint8_t>(tactile::ContactType::Multiple));
  EXPECT_EQ(tactile_msgs::ContactFeatures::STATUS_TARE_REJECTED, static_cast<uint8_t>(tactile::FeatureStatus::TareRejected));
  EXPECT_EQ(tactile_msgs::ContactFeatures::STATUS_OUT_OF_RANGE, static_cast<uint8_t>(tactile::kLastFeatureStatus));
}

TEST(RosConversions, PoseAndTransform) {
  const tactile::Pose p = rotZ(0.5, {0.4, -0.1, 0.3});
  geometry_msgs::PoseStamped ps;
  tactile_ros::toPose(p, ros::Time(1.5), "lwr_base", ps);
  EXPECT_EQ(ps.header.frame_id, "lwr_base");
  EXPECT_DOUBLE_EQ(ps.pose.position.x, 0.4);
  EXPECT_DOUBLE_EQ(ps.pose.position.y, -0.1);
  EXPECT_DOUBLE_EQ(ps.pose.position.z, 0.3);
  EXPECT_DOUBLE_EQ(ps.pose.orientation.z, std::sin(0.25));
  EXPECT_DOUBLE_EQ(ps.pose.orientation.w, std::cos(0.25));
  geometry_msgs::TransformStamped ts;
  tactile_ros::toTransform(p, ros::Time(1.5), "lwr_base", "lwr_flange", ts);
  EXPECT_EQ(ts.header.frame_id, "lwr_base");
  EXPECT_EQ(ts.child_frame_id, "lwr_flange");
  EXPECT_DOUBLE_EQ(ts.transform.translation.x, 0.4);
  EXPECT_DOUBLE_EQ(ts.transform.rotation.z, std::sin(0.25));
  EXPECT_DOUBLE_EQ(ts.transform.rotation.w, std::cos(0.25));
}

TEST(RosConversions, WrenchIsExpressedInTheFlangeFrame) {
  tactile::Wrench w;
  w.w = {1.0, 2.0, -5.0, 0.1, 0.2, 0.3};
  // Flange rotated by 90 deg about z_g: x_e = y_g, y_e = -x_g.
  const tactile::Pose flange = rotZ(M_PI / 2, {0.5, 0.0, 0.4});
  geometry_msgs::WrenchStamped m;
  EXPECT_TRUE(tactile_ros::toWrench(w, flange, ros::Time(1.0), "lwr_base", "lwr_flange", m));
  EXPECT_EQ(m.header.frame_id, "lwr_flange");
  EXPECT_NEAR(m.wrench.force.x, 2.0, 1e-12);
  EXPECT_NEAR(m.wrench.force.y, -1.0, 1e-12);
  EXPECT_NEAR(m.wrench.force.z, -5.0, 1e-12);
  EXPECT_NEAR(m.wrench.torque.x, 0.2, 1e-12);
  EXPECT_NEAR(m.wrench.torque.y, -0.1, 1e-12);
  EXPECT_NEAR(m.wrench.torque.z, 0.3, 1e-12);
  // Flange upside down (180 deg about x_g): z_e = -z_g.
  tactile::Pose down;
  down.q = {1.0, 0.0, 0.0, 0.0};
  EXPECT_TRUE(tactile_ros::toWrench(w, down, ros::Time(1.0), "lwr_base", "lwr_flange", m));
  EXPECT_NEAR(m.wrench.force.z, 5.0, 1e-12);
  EXPECT_NEAR(m.wrench.force.y, -2.0, 1e-12);
}

TEST(RosConversions, WrenchWithoutAValidPoseStaysInTheBaseFrame) {
  tactile::Wrench w;
  w.w = {1.0, 2.0, -5.0, 0.1, 0.2, 0.3};
  geometry_msgs::WrenchStamped m;
  EXPECT_FALSE(tactile_ros::toWrench(w, tactile::kNoPose, ros::Time(1.0), "lwr_base", "lwr_flange", m));
  EXPECT_EQ(m.header.frame_id, "lwr_base");
  EXPECT_DOUBLE_EQ(m.wrench.force.y, 2.0);
  EXPECT_DOUBLE_EQ(m.wrench.torque.z, 0.3);
}

TEST(RosConversions, PhaseNameAndStatus) {
  tactile::PhaseState p;
  p.index = 2;
  p.t_enter_s = 4.5;
  const char name[] = "follow_edge";
  std::memcpy(p.name.data(), name, sizeof(name));
  p.status = tactile::ServoStatus::ContactLost;
  tactile_msgs::Phase m;
  tactile_ros::toPhase(p, ros::Time(5.0), m);
  EXPECT_EQ(m.index, 2);
  EXPECT_EQ(m.name, "follow_edge");
  EXPECT_DOUBLE_EQ(m.t_enter, 4.5);
  EXPECT_EQ(m.status, 3);
  EXPECT_EQ(m.status_name, tactile::toString(tactile::ServoStatus::ContactLost));
  // A name that fills the whole array (no NUL) is cut at the array's end.
  p.name.fill('a');
  tactile_ros::toPhase(p, ros::Time(5.0), m);
  EXPECT_EQ(m.name.size(), static_cast<std::size_t>(tactile::kPhaseNameLen));
}

TEST(RosConversions, ContactFrameAtTheCopRotatedByAlpha) {
  tactile::ContactFeatures f;
  f.status = tactile::FeatureStatus::Ok;
  f.contact = tactile::ContactType::Edge;
  f.cop_x = 0.004;
  f.cop_y = -0.003;
  f.alpha_z = 0.6;
  f.alpha_defined = true;
  EXPECT_TRUE(inContact(f));
  tactile::Pose c = contactPose(f);
  EXPECT_DOUBLE_EQ(c.p[0], 0.004);
  EXPECT_DOUBLE_EQ(c.p[1], -0.003);
  EXPECT_DOUBLE_EQ(c.p[2], 0.0);
  EXPECT_DOUBLE_EQ(c.q[2], std::sin(0.3));
  EXPECT_DOUBLE_EQ(c.q[3], std::cos(0.3));
  f.alpha_defined = false;  // a held angle does not rotate the frame
  c = contactPose(f);
  EXPECT_DOUBLE_EQ(c.q[2], 0.0);
  EXPECT_DOUBLE_EQ(c.q[3], 1.0);
  f.contact = tactile::ContactType::None;
  EXPECT_FALSE(inContact(f));
  f.contact = tactile::ContactType::Point;
  f.status = tactile::FeatureStatus::InvalidInput;
  EXPECT_FALSE(inContact(f));
}

TEST(RosConversions, PoseFromVector) {
  tactile::Pose p;
  EXPECT_TRUE(tactile_ros::poseFromVector({0.0, 0.0, 0.03, 0.0, 0.0, 0.0, 1.0}, p));
  EXPECT_DOUBLE_EQ(p.p[2], 0.03);
  EXPECT_FALSE(tactile_ros::poseFromVector({0.0, 0.0, 0.03}, p));
  EXPECT_FALSE(tactile_ros::poseFromVector({0.0, 0.0, 0.03, 0.0, 0.0, 0.0, 2.0}, p));
  EXPECT_DOUBLE_EQ(p.p[2], 0.03);  // unchanged on failure
}

std::vector<std::string> lwrNames() {
  return {tactile_ros::kLwrJointNames.begin(), tactile_ros::kLwrJointNames.end()};
}

TEST(RosConversions, JointStateNamesAndPositions) {
  sensor_msgs::JointState js;
  EXPECT_FALSE(tactile_ros::initJointState({"a", "b"}, js));
  EXPECT_TRUE(js.name.empty());
  ASSERT_TRUE(tactile_ros::initJointState(lwrNames(), js));
  ASSERT_EQ(js.name.size(), 7u);
  for (int i = 0; i < 7; ++i) EXPECT_EQ(js.name[static_cast<std::size_t>(i)], "lwr_a" + std::to_string(i + 1) + "_joint");
  EXPECT_EQ(js.position.size(), 7u);
  EXPECT_TRUE(js.velocity.empty());
  EXPECT_TRUE(js.effort.empty());
  tactile::RobotState s;
  s.q = {0.1, -0.6, 0.3, 1.4, -0.5, -1.1416, 2.9};
  const double* before = js.position.data();
  ASSERT_TRUE(tactile_ros::toJointState(s, ros::Time(2.5), js));
  EXPECT_EQ(js.position.data(), before);  // written in place, never resized
  EXPECT_DOUBLE_EQ(js.header.stamp.toSec(), 2.5);
  for (std::size_t i = 0; i < 7; ++i) EXPECT_EQ(js.position[i], s.q[i]) << i;
  // A joint that is not finite: nothing written.
  s.q[3] = std::nan("");
  EXPECT_FALSE(tactile_ros::toJointState(s, ros::Time(3.0), js));
  EXPECT_DOUBLE_EQ(js.header.stamp.toSec(), 2.5);
  EXPECT_EQ(js.position[3], 1.4);
  // A message not sized by initJointState: refused, not resized.
  sensor_msgs::JointState empty;
  s.q[3] = 1.4;
  EXPECT_FALSE(tactile_ros::toJointState(s, ros::Time(3.0), empty));
  EXPECT_TRUE(empty.position.empty());
}

TEST(RosConversions, RobotStateFieldByField) {
  tactile::RobotState s;
  s.mode = tactile::RobotMode::Command;
  s.quality = 3;
  s.power_on = true;
  s.cartesian_impedance = true;
  s.config_ok = false;
  s.dry_run = true;
  s.commandable = false;
  s.link_status = 4;
  tactile_msgs::RobotState m;
  tactile_ros::toRobotStateMsg(s, ros::Time(7.0), m);
  EXPECT_DOUBLE_EQ(m.header.stamp.toSec(), 7.0);
  EXPECT_EQ(m.mode, tactile_msgs::RobotState::MODE_COMMAND);
  EXPECT_EQ(m.mode_name, "command");
  EXPECT_EQ(m.quality, 3);
  EXPECT_TRUE(m.power_on);
  EXPECT_TRUE(m.cartesian_impedance);
  EXPECT_FALSE(m.config_ok);
  EXPECT_TRUE(m.dry_run);
  EXPECT_FALSE(m.commandable);
  EXPECT_EQ(m.link_status, 4);
  s.mode = tactile::RobotMode::Monitor;
  tactile_ros::toRobotStateMsg(s, ros::Time(7.0), m);
  EXPECT_EQ(m.mode, tactile_msgs::RobotState::MODE_MONITOR);
  EXPECT_EQ(m.mode_name, "monitor");
  EXPECT_EQ(static_cast<int>(tactile::RobotMode::Off), tactile_msgs::RobotState::MODE_OFF);
}

TEST(RosConversions, KrcStateComparisonIgnoresTimeAndJoints) {
  tactile::RobotState a, b;
  b.time_s = 5.0;
  b.q[2] = 1.0;
  EXPECT_TRUE(tactile_ros::sameKrcState(a, b));
  auto differs = [&](auto change) {
    tactile::RobotState c = a;
    change(c);
    return !tactile_ros::sameKrcState(a, c);
  };
  EXPECT_TRUE(differs([](tactile::RobotState& c) { c.mode = tactile::RobotMode::Command; }));
  EXPECT_TRUE(differs([](tactile::RobotState& c) { c.quality = 2; }));
  EXPECT_TRUE(differs([](tactile::RobotState& c) { c.power_on = true; }));
  EXPECT_TRUE(differs([](tactile::RobotState& c) { c.cartesian_impedance = true; }));
  EXPECT_TRUE(differs([](tactile::RobotState& c) { c.config_ok = false; }));
  EXPECT_TRUE(differs([](tactile::RobotState& c) { c.dry_run = true; }));
  EXPECT_TRUE(differs([](tactile::RobotState& c) { c.commandable = true; }));
  EXPECT_TRUE(differs([](tactile::RobotState& c) { c.link_status = 1; }));
}

TEST(RosConversions, DecimatorKeepsEveryTenthSampleOfAOneKilohertzStream) {
  // The simulated arm's time accumulates dt (rounding grows); the KRC's is
  // k * 0.001 s: both must give exactly every tenth sample at 0.01 s.
  tactile_ros::Decimator by_sum(0.01), by_index(0.01);
  double t = 0.0;
  int due_sum = 0, due_index = 0;
  for (int k = 0; k < 100000; ++k) {
    const bool a = by_sum.due(t), b = by_index.due(k * 0.001);
    EXPECT_EQ(a, k % 10 == 0) << "accumulated time, sample " << k << " t = " << t;
    EXPECT_EQ(b, k % 10 == 0) << "indexed time, sample " << k;
    due_sum += a;
    due_index += b;
    if (::testing::Test::HasFailure()) break;
    t += 0.001;
  }
  EXPECT_EQ(due_sum, 10000);
  EXPECT_EQ(due_index, 10000);
}

TEST(RosConversions, DecimatorKeepsTheRateOfAJitteryStream) {
  // A 1 kHz stream stamped on arrival: +-0.3 ms of jitter (a fixed
  // pseudo-random sequence). 100 s of it must give 100 Hz: 10000 samples,
  // within one (the last slot), none two closer than a period less the jitter.
  tactile_ros::Decimator d(0.01);
  uint32_t lcg = 12345u;
  int due = 0;
  double last = -1.0, min_gap = 1.0;
  for (int k = 0; k < 100000; ++k) {
    lcg = lcg * 1664525u + 1013904223u;
    const double t = 0.001 * k + 0.0003 * (2.0 * (lcg >> 8) / 16777216.0 - 1.0);
    if (d.due(t)) {
      ++due;
      if (last >= 0.0) min_gap = std::min(min_gap, t - last);
      last = t;
    }
  }
  EXPECT_GE(due, 9999);
  EXPECT_LE(due, 10001);
  EXPECT_GE(min_gap, 0.01 - 0.0006 - 0.001);  // a slot's sample may come up to jitter + one sample late, the next early
  // The same stream re-anchored after a 50 ms gap: the next sample is due, then every 10 ms again.
  tactile_ros::Decimator g(0.01);
  EXPECT_TRUE(g.due(0.0));
  EXPECT_TRUE(g.due(0.06));
  EXPECT_FALSE(g.due(0.065));
  EXPECT_TRUE(g.due(0.07));
}

TEST(RosConversions, DecimatorRestartsAndPassesAllWithoutAPeriod) {
  tactile_ros::Decimator d(0.01);
  EXPECT_TRUE(d.due(5.0));
  EXPECT_FALSE(d.due(5.004));
  EXPECT_TRUE(d.due(1.0));  // the time restarted
  EXPECT_FALSE(d.due(1.009));
  EXPECT_TRUE(d.due(1.01));
  d.reset();
  EXPECT_TRUE(d.due(1.011));
  tactile_ros::Decimator all(0.0);
  for (int k = 0; k < 5; ++k) EXPECT_TRUE(all.due(0.001 * k));
  EXPECT_TRUE(all.due(0.004));  // the same time again
}

}  // namespace
