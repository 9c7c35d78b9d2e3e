// tactile::LwrSimComponent in-process: SlaveActivity, update() by hand, outputs
// compared with tactile::sim::World driven directly from the same scene.
#include <gtest/gtest.h>

#include <rtt/InputPort.hpp>
#include <rtt/OutputPort.hpp>
#include <rtt/TaskContext.hpp>
#include <rtt/extras/SlaveActivity.hpp>
#include <rtt/os/TimeService.hpp>
#include <rtt/os/main.h>

#include <cmath>
#include <fstream>
#include <string>

#include "alloc_counter.hpp"
#include "tactile_features/calibration.hpp"
#include "tactile_sim/scene.hpp"
#include "tactile_sim/world.hpp"
#include "tactile_sim_rtt/lwr_sim_component.hpp"
#include "support/rtt_environment.hpp"
#include "temp_file.hpp"

namespace {

using tactile::Pose;
using tactile::PoseCommand;
using tactile::RawTactileFrame;
using tactile::TactileFrame;

const auto* const env =
    ::testing::AddGlobalTestEnvironment(new tactile::test::RttEnvironment(tactile::test::Clock::Manual));

const std::string kScene = TACTILE_SCENE_DIR "/edge_exploration.yaml";

struct Rig {
  tactile::LwrSimComponent comp{"sim"};
  RTT::OutputPort<PoseCommand> command_out{"command_out"};
  RTT::InputPort<Pose> pose_in{"pose_in"};
  RTT::InputPort<RawTactileFrame> raw_in{"raw_in"};
  RTT::InputPort<TactileFrame> frame_in{"frame_in"};
  RTT::TaskContext io{"io"};  // declared last: destroyed before the ports it holds

  explicit Rig(const std::string& scene) {
    comp.setActivity(new RTT::extras::SlaveActivity(0.001));
    io.ports()->addPort(command_out);
    io.ports()->addPort(pose_in);
    io.ports()->addPort(raw_in);
    io.ports()->addPort(frame_in);
    comp.properties()->getPropertyType<std::string>("scene_file")->set(scene);
    EXPECT_TRUE(command_out.connectTo(comp.ports()->getPort("pose_command")));
    EXPECT_TRUE(comp.ports()->getPort("flange_pose")->connectTo(&pose_in));
    EXPECT_TRUE(comp.ports()->getPort("raw_frame")->connectTo(&raw_in));
    EXPECT_TRUE(comp.ports()->getPort("frame")->connectTo(&frame_in));
    command_out.setDataSample(PoseCommand());
  }
  template <typename T>
  T attr(const char* name) {
    return RTT::Attribute<T>(comp.provides()->getAttribute(name)).get();
  }
};

std::string writeTemp(const std::string& name, const std::string& text) {
  return tactile::test::writeTempFile(name, text);
}

TEST(LwrSimComponent, InterfaceIsDeclaredAndDocumented) {
  tactile::LwrSimComponent c("s");
  for (const char* port : {"pose_command", "flange_pose", "raw_frame", "frame"}) {
    ASSERT_NE(c.ports()->getPort(port), nullptr) << port;
    EXPECT_FALSE(c.ports()->getPort(port)->getDescription().empty()) << port;
  }
  for (const char* prop : {"scene_file", "wts_period"}) {
    ASSERT_NE(c.properties()->getProperty(prop), nullptr) << prop;
    EXPECT_FALSE(c.properties()->getProperty(prop)->getDescription().empty()) << prop;
  }
  for (const char* a : {"sim_period", "sim_time", "sim_status", "frames"})
    EXPECT_NE(c.provides()->getAttribute(a), nullptr) << a;
  for (const char* op : {"lastError", "statusName"}) {
    EXPECT_TRUE(c.provides()->hasOperation(op)) << op;
    EXPECT_FALSE(c.provides()->getDescription(op).empty()) << op;
  }
}

TEST(LwrSimComponent, ConfigureErrorsNameTheProblem) {
  {
    tactile::LwrSimComponent c("s");
    EXPECT_FALSE(c.configure());
    EXPECT_NE(c.lastError().find("scene_file"), std::string::npos) << c.lastError();
  }
  {
    tactile::LwrSimComponent c("s");
    c.properties()->getPropertyType<std::string>("scene_file")->set("/nonexistent/scene.yaml");
    EXPECT_FALSE(c.configure());
    EXPECT_NE(c.lastError().find("/nonexistent/scene.yaml"), std::string::npos) << c.lastError();
  }
  {
    tactile::LwrSimComponent c("s");
    c.properties()->getPropertyType<std::string>("scene_file")->set(kScene);
    c.properties()->getPropertyType<double>("wts_period")->set(-0.01);
    EXPECT_FALSE(c.configure());
    EXPECT_NE(c.lastError().find("wts_period"), std::string::npos) << c.lastError();
    EXPECT_NE(c.lastError().find("(0, 1]"), std::string::npos) << c.lastError();
    EXPECT_FALSE(c.start());
  }
  {
    // An invalid scene value: the scene loader's message (file and field) comes through.
    const std::string bad = writeTemp("bad_scene.yaml",
                                      "name: bad\nprogram: " TACTILE_PROGRAM_DIR "/edge_exploration.yaml\n"
                                      "rates: {sim: -5}\n");
    tactile::LwrSimComponent c("s");
    c.properties()->getPropertyType<std::string>("scene_file")->set(bad);
    EXPECT_FALSE(c.configure());
    EXPECT_NE(c.lastError().find("rates.sim"), std::string::npos) << c.lastError();
  }
}

// The component is World::step + World::acquire + Calibration, nothing else:
// drive a World from the same scene with the same commands and compare.
TEST(LwrSimComponent, OutputsMatchTheWorldDrivenDirectly) {
  Rig rig(kScene);
  ASSERT_TRUE(rig.comp.configure()) << rig.comp.lastError();
  ASSERT_TRUE(rig.comp.start());
  EXPECT_DOUBLE_EQ(rig.attr<double>("sim_period"), 0.001);

  tactile::sim::Scene scene;
  ASSERT_TRUE(tactile::sim::loadScene(kScene, scene).ok());
  tactile::sim::WorldParams wp = scene.world;
  wp.seed = scene.seed;
  tactile::sim::World world;
  ASSERT_TRUE(world.configure(wp).ok());
  tactile::Calibration cal;
  ASSERT_TRUE(cal.configure(world.calibration()).ok());
  tactile::sim::SimState st = world.state();
  tactile::sim::SensorTruth truth;
  RawTactileFrame raw_want;
  TactileFrame frame_want;

  const Pose start = st.flange_g;
  Pose cmd = start;
  double next_acq = 0.0;
  int frames = 0, with_contact = 0;
  const int steps = 3000;
  for (int k = 0; k < steps; ++k) {
    RTT::os::TimeService::Instance()->secondsChange(0.001);
    // Hold the start pose for 0.2 s, then lower the flange 4 mm per 100 ms
    // (a slow ramp into the bar below, as a servo would).
    if (k >= 200 && k % 100 == 0) {
      cmd.p[2] -= 0.004;
      PoseCommand pc;
      pc.pose = cmd;
      rig.command_out.write(pc);
    }
    ASSERT_TRUE(rig.comp.update());
    world.step(cmd, 0.001, st);
    Pose got;
    ASSERT_EQ(rig.pose_in.read(got), RTT::NewData) << k;
    // Same code, same inputs: bit-identical (tolerance 0).
    ASSERT_EQ(got.p, st.flange_g.p) << k;
    ASSERT_EQ(got.q, st.flange_g.q) << k;
    if (st.time_s + 0.25e-3 >= next_acq) {
      next_acq += 1.0 / 140.0;
      world.acquire(raw_want, truth);
      cal.step(raw_want, frame_want);
      RawTactileFrame raw;
      TactileFrame frame;
      ASSERT_EQ(rig.raw_in.read(raw), RTT::NewData) << k;
      ASSERT_EQ(rig.frame_in.read(frame), RTT::NewData) << k;
      ++frames;
      EXPECT_EQ(raw.seq, raw_want.seq);
      EXPECT_EQ(raw.counts, raw_want.counts) << k;
      EXPECT_EQ(frame.force, frame_want.force) << k;
      // Stamped with RTT's TimeService (the servo's clock), not the world time.
      EXPECT_DOUBLE_EQ(raw.time_s, RTT::os::TimeService::Instance()->secondsSince(0));
      EXPECT_EQ(frame.time_s, raw.time_s);
      if (truth.in_contact) ++with_contact;
    } else {
      RawTactileFrame raw;
      EXPECT_NE(rig.raw_in.read(raw), RTT::NewData) << "no acquisition due at step " << k;
    }
  }
  // 3 s at 140 Hz: 420 or 421 acquisitions.
  EXPECT_NEAR(frames, 420, 1);
  EXPECT_EQ(rig.attr<int>("frames"), frames);
  EXPECT_NEAR(rig.attr<double>("sim_time"), 3.0, 1e-9);
  // The ramp ends 11.2 cm lower: the sensor must have reached the bar.
  EXPECT_GT(with_contact, 10);
  EXPECT_LT(st.flange_g.p[2], start.p[2] - 0.02);
}

TEST(LwrSimComponent, HoldsTheStartPoseWithoutCommandsAndRejectsNaN) {
  Rig rig(kScene);
  ASSERT_TRUE(rig.comp.configure());
  ASSERT_TRUE(rig.comp.start());
  const Pose start = rig.comp.world().state().flange_g;
  for (int k = 0; k < 100; ++k) ASSERT_TRUE(rig.comp.update());
  Pose got;
  ASSERT_EQ(rig.pose_in.read(got), RTT::NewData);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(got.p[i], start.p[i], 1e-9);  // no command: stays (quasi-static, no load)
  PoseCommand bad;
  bad.pose = start;
  bad.pose.p[0] = std::nan("");
  rig.command_out.write(bad);
  ASSERT_TRUE(rig.comp.update());
  EXPECT_EQ(rig.attr<int>("sim_status"), static_cast<int>(tactile::sim::SimStatus::InvalidCommand));
  ASSERT_EQ(rig.pose_in.read(got), RTT::NewData);
  for (int i = 0; i < 3; ++i) {
    EXPECT_TRUE(std::isfinite(got.p[i]));
    EXPECT_NEAR(got.p[i], start.p[i], 1e-9);  // the last valid command (the start pose) held
  }
  // restart: back to the scene's initial state
  ASSERT_TRUE(rig.comp.stop());
  ASSERT_TRUE(rig.comp.start());
  EXPECT_EQ(rig.attr<double>("sim_time"), 0.0);
  EXPECT_EQ(rig.attr<int>("frames"), 0);
}

TEST(LwrSimComponent, UpdateDoesNotAllocate) {
  Rig rig(kScene);
  ASSERT_TRUE(rig.comp.configure());
  ASSERT_TRUE(rig.comp.start());
  Pose cmd = rig.comp.world().state().flange_g;
  PoseCommand pc;
  RawTactileFrame raw;
  TactileFrame frame;
  Pose pose;
  auto cycle = [&] {  // command in, one update, every output read
    pc.pose = cmd;
    rig.command_out.write(pc);
    rig.comp.update();
    rig.pose_in.read(pose);
    rig.raw_in.read(raw);
    rig.frame_in.read(frame);
  };
  for (int k = 0; k < 50; ++k) cycle();  // warm-up: every port carried a sample once
  tactile::test::AllocationScope scope;
  for (int k = 0; k < 2000; ++k) {  // commands moving into contact, acquisitions included
    cmd.p[2] -= 0.00005;
    cycle();
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_GT(rig.attr<int>("frames"), 250);
}

}  // namespace
