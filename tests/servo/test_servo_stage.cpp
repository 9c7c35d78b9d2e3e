// tactile::ServoStage: the loop's servo stage (runner and ServoComponent). It
// holds (no command, core not stepped) until a valid measured pose arrived,
// then steps the core with dt = nominal period on the first cycle and the
// time difference afterwards; an invalid pose after a valid one reaches the
// core (InvalidInput, finite command).
#include <gtest/gtest.h>

#include <cmath>

#include "alloc_counter.hpp"
#include "servo_test_util.hpp"
#include "tactile_servo/servo_stage.hpp"

using namespace servo_test;

namespace {

Pose startPose() {
  Pose p;
  p.p = {0.5, 0.0, 0.4};
  p.q = {1.0, 0.0, 0.0, 0.0};  // sensor facing down
  return p;
}

ContactFeatures noContact(double t) {
  ContactFeatures f;
  f.time_s = t;
  f.status = FeatureStatus::NoContact;
  return f;
}

}  // namespace

TEST(ServoStage, HoldsUntilAValidPoseThenMatchesTheCore) {
  const ServoParams p = loadShipped("edge_exploration.yaml");
  ServoStage stage;
  ASSERT_TRUE(stage.configure(p, 0.01).ok());
  ServoOutput out;
  ServoStatus st = ServoStatus::Ok;
  // No pose: hold, no command.
  EXPECT_FALSE(stage.step(0.0, noContact(0.0), out, st));
  EXPECT_EQ(st, ServoStatus::WaitingForPose);
  EXPECT_FALSE(out.valid);
  // A default-constructed or NaN pose does not open the gate.
  Pose zero;
  zero.q = {0.0, 0.0, 0.0, 0.0};
  EXPECT_FALSE(stage.setMeasuredPose(zero));
  Pose nan = startPose();
  nan.p[0] = std::nan("");
  EXPECT_FALSE(stage.setMeasuredPose(nan));
  EXPECT_FALSE(stage.step(0.01, noContact(0.01), out, st));
  EXPECT_EQ(st, ServoStatus::WaitingForPose);
  // A valid pose: the core steps, the first dt is the nominal period.
  TactileServo core;
  ASSERT_TRUE(core.configure(p).ok());
  ServoInput in;
  ServoOutput want;
  Pose pose = startPose();
  double t_prev = 0.0;
  for (int k = 0; k < 30; ++k) {
    const double t = 0.02 + 0.01 * k;
    ASSERT_TRUE(stage.setMeasuredPose(pose));
    ASSERT_TRUE(stage.step(t, noContact(t), out, st));
    in.time_s = t;
    in.features = noContact(t);
    in.flange_measured = pose;
    core.step(in, k == 0 ? 0.01 : t - t_prev, want);
    t_prev = t;
    ASSERT_EQ(out.command.pose.p, want.command.pose.p) << k;
    ASSERT_EQ(out.command.pose.q, want.command.pose.q) << k;
    EXPECT_EQ(st, want.command.status);
    pose = out.command.pose;
  }
  // The start pose seeded the command: free motion moved it 0.3 mm down, not from the origin.
  EXPECT_NEAR(pose.p[0], 0.5, 1e-9);
  EXPECT_LT(pose.p[2], 0.4);
  EXPECT_GT(pose.p[2], 0.39);
  // After a valid pose, a NaN one reaches the core: InvalidInput, the command stays finite.
  stage.setMeasuredPose(nan);
  ASSERT_TRUE(stage.step(0.4, noContact(0.4), out, st));
  EXPECT_EQ(st, ServoStatus::InvalidInput);
  for (double v : out.command.pose.p) EXPECT_TRUE(std::isfinite(v));
  // reset(): the gate closes again.
  stage.reset();
  EXPECT_FALSE(stage.step(0.5, noContact(0.5), out, st));
  EXPECT_EQ(st, ServoStatus::WaitingForPose);
}

TEST(ServoStage, RejectsABadPeriodAndDoesNotAllocatePerCycle) {
  ServoStage stage;
  const ServoParams p = loadShipped("edge_exploration.yaml");
  const ConfigResult r = stage.configure(p, 0.0);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("servo period"), std::string::npos) << r.message();
  ASSERT_TRUE(stage.configure(p, 0.01).ok());
  ServoOutput out;
  ServoStatus st;
  Pose pose = startPose();
  tactile::test::AllocationScope scope;
  for (int k = 0; k < 200; ++k) {
    stage.setMeasuredPose(pose);
    if (stage.step(0.01 * k, noContact(0.01 * k), out, st)) pose = out.command.pose;
  }
  EXPECT_EQ(scope.count(), 0u);
}
