// The robot swap (rtt_lwr style): tactile::LwrSimComponent and
// tactile::FriBridgeComponent expose the same robot-side ports (names, types,
// directions), estimated_wrench included, so ServoComponent connects to either
// BY NAME, as a deployment script does; and the simulated sensor
// (tactile::WtsSimComponent) and the WTS reader (tactile::WtsComponent) offer
// the same raw_frame port the FeatureComponent takes.
#include <gtest/gtest.h>

#include <rtt/TaskContext.hpp>
#include <rtt/base/InputPortInterface.hpp>
#include <rtt/base/OutputPortInterface.hpp>
#include <rtt/extras/SlaveActivity.hpp>
#include <rtt/os/TimeService.hpp>
#include <rtt/os/main.h>

#include <fstream>
#include <memory>
#include <string>

#include "tactile_features_rtt/feature_component.hpp"
#include "tactile_fri_rtt/fri_bridge_component.hpp"
#include "tactile_servo_rtt/servo_component.hpp"
#include "tactile_sim_rtt/lwr_sim_component.hpp"
#include "tactile_sim_rtt/wts_sim_component.hpp"
#include "tactile_wts_rtt/wts_component.hpp"
#include "support/rtt_environment.hpp"

namespace {

const auto* const env =
    ::testing::AddGlobalTestEnvironment(new tactile::test::RttEnvironment(tactile::test::Clock::System));

bool isInput(RTT::base::PortInterface* p) { return dynamic_cast<RTT::base::InputPortInterface*>(p) != nullptr; }

// connect("Robot.<port>", "Servo.<port>") as the deployer does: by name, checking types.
bool connectByName(RTT::TaskContext& from, const std::string& out_name, RTT::TaskContext& to,
                   const std::string& in_name) {
  RTT::base::PortInterface* out = from.ports()->getPort(out_name);
  RTT::base::PortInterface* in = to.ports()->getPort(in_name);
  if (!out || !in || isInput(out) || !isInput(in)) return false;
  if (out->getTypeInfo() != in->getTypeInfo()) return false;
  return out->connectTo(in);
}

// Runs the same wiring code against either robot component.
void wireServoTo(RTT::TaskContext& robot) {
  SCOPED_TRACE(robot.getName());
  tactile::ServoComponent servo("servo");
  EXPECT_TRUE(connectByName(servo, "pose_command", robot, "pose_command"));
  EXPECT_TRUE(connectByName(robot, "flange_pose", servo, "flange_pose"));
  EXPECT_TRUE(robot.ports()->getPort("pose_command")->connected());
  EXPECT_TRUE(robot.ports()->getPort("flange_pose")->connected());
  // and nothing connects the wrong way round
  EXPECT_FALSE(connectByName(robot, "pose_command", servo, "flange_pose"));
  robot.ports()->getPort("pose_command")->disconnect();
  robot.ports()->getPort("flange_pose")->disconnect();
}

TEST(RobotSwap, SimAndFriExposeTheSameRobotPorts) {
  tactile::LwrSimComponent sim("Robot");
  tactile::FriBridgeComponent fri("Robot");
  for (const char* name : {"pose_command", "flange_pose", "estimated_wrench", "robot_state"}) {
    RTT::base::PortInterface* a = sim.ports()->getPort(name);
    RTT::base::PortInterface* b = fri.ports()->getPort(name);
    ASSERT_NE(a, nullptr) << name;
    ASSERT_NE(b, nullptr) << name;
    EXPECT_EQ(a->getTypeInfo(), b->getTypeInfo()) << name;
    EXPECT_EQ(a->getTypeInfo()->getTypeName(), b->getTypeInfo()->getTypeName()) << name;
    EXPECT_EQ(isInput(a), isInput(b)) << name;
  }
  EXPECT_TRUE(isInput(sim.ports()->getPort("pose_command")));
  EXPECT_FALSE(isInput(sim.ports()->getPort("flange_pose")));
  EXPECT_FALSE(isInput(sim.ports()->getPort("estimated_wrench")));
}

TEST(RobotSwap, ServoConnectsToEitherByName) {
  tactile::LwrSimComponent sim("sim");
  wireServoTo(sim);
  tactile::FriBridgeComponent fri("fri");
  wireServoTo(fri);
}

TEST(RobotSwap, SimulatedAndRealSensorFeedTheFeatureComponentByName) {
  tactile::WtsSimComponent sim("Sensor");
  tactile::WtsComponent wts("Sensor");
  tactile::FeatureComponent features("features");
  for (RTT::TaskContext* sensor : std::initializer_list<RTT::TaskContext*>{&sim, &wts}) {
    EXPECT_TRUE(connectByName(*sensor, "raw_frame", features, "raw_frame"));
    EXPECT_TRUE(features.ports()->getPort("raw_frame")->connected());
    sensor->ports()->getPort("raw_frame")->disconnect();
  }
  EXPECT_EQ(sim.ports()->getPort("raw_frame")->getTypeInfo(), wts.ports()->getPort("raw_frame")->getTypeInfo());
}

}  // namespace
