// tactile::LwrSimComponent (the simulated arm) and tactile::WtsSimComponent
// (the simulated sensor) in-process: SlaveActivity, update() by hand, outputs
// compared with tactile::sim::World and tactile::sim::TaxelResponse driven
// directly from the same scene.
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
#include "tactile_sim_runner/scene.hpp"
#include "tactile_sim_lwr/world.hpp"
#include "tactile_sim_runner/loop.hpp"
#include "tactile_sim_lwr/taxel_response.hpp"
#include "tactile_sim_rtt/lwr_sim_component.hpp"
#include "tactile_sim_rtt/wts_sim_component.hpp"
#include "support/rtt_environment.hpp"
#include "temp_file.hpp"
#include "tactile_types_rtt/atomic_attribute.hpp"

namespace {

using tactile::Pose;
using tactile::PoseCommand;
using tactile::RawTactileFrame;
using tactile::TactileFrame;

const auto* const env =
    ::testing::AddGlobalTestEnvironment(new tactile::test::RttEnvironment(tactile::test::Clock::Manual));

const std::string kScene = TACTILE_SCENE_DIR "/edge_exploration.yaml";
const std::string kProgram = TACTILE_PROGRAM_DIR "/edge_exploration.yaml";  // the registry's for kScene

struct Rig {
  tactile::LwrSimComponent comp{"sim"};
  tactile::WtsSimComponent sensor{"sensor"};
  RTT::OutputPort<PoseCommand> command_out{"command_out"};
  RTT::InputPort<Pose> pose_in{"pose_in"};
  RTT::InputPort<TactileFrame> forces_in{"forces_in"};
  RTT::InputPort<tactile::SimTruth> truth_in{"truth_in"};
  RTT::InputPort<tactile::Wrench> wrench_in{"wrench_in"};
  RTT::InputPort<RawTactileFrame> raw_in{"raw_in"};
  RTT::TaskContext io{"io"};  // declared last: destroyed before the ports it holds

  explicit Rig(const std::string& scene, const std::string& program = kProgram) {
    comp.setActivity(new RTT::extras::SlaveActivity(0.001));
    sensor.setActivity(new RTT::extras::SlaveActivity(0.0));
    io.ports()->addPort(command_out);
    io.ports()->addPort(pose_in);
    io.ports()->addPort(forces_in);
    io.ports()->addPort(truth_in);
    io.ports()->addPort(wrench_in);
    io.ports()->addPort(raw_in);
    comp.properties()->getPropertyType<std::string>("scene_file")->set(scene);
    comp.properties()->getPropertyType<std::string>("program_file")->set(program);
    sensor.properties()->getPropertyType<std::string>("scene_file")->set(scene);
    EXPECT_TRUE(command_out.connectTo(comp.ports()->getPort("pose_command")));
    EXPECT_TRUE(comp.ports()->getPort("flange_pose")->connectTo(&pose_in));
    EXPECT_TRUE(comp.ports()->getPort("taxel_forces")->connectTo(&forces_in));
    EXPECT_TRUE(comp.ports()->getPort("truth")->connectTo(&truth_in));
    EXPECT_TRUE(comp.ports()->getPort("estimated_wrench")->connectTo(&wrench_in));
    EXPECT_TRUE(comp.ports()->getPort("taxel_forces")->connectTo(sensor.ports()->getPort("taxel_forces")));
    EXPECT_TRUE(sensor.ports()->getPort("raw_frame")->connectTo(&raw_in));
    command_out.setDataSample(PoseCommand());
  }
  template <typename T>
  T attr(const char* name) {
    return tactile::readAttribute<T>(*comp.provides(), name);
  }
};

std::string writeTemp(const std::string& name, const std::string& text) {
  return tactile::test::writeTempFile(name, text);
}

TEST(LwrSimComponent, InterfaceIsDeclaredAndDocumented) {
  tactile::LwrSimComponent c("s");
  for (const char* port : {"pose_command", "flange_pose", "estimated_wrench", "robot_state", "taxel_forces", "truth"}) {
    ASSERT_NE(c.ports()->getPort(port), nullptr) << port;
    EXPECT_FALSE(c.ports()->getPort(port)->getDescription().empty()) << port;
  }
  EXPECT_EQ(c.ports()->getPort("raw_frame"), nullptr) << "the sensor is a separate component";
  for (const char* prop : {"scene_file", "program_file"}) {
    ASSERT_NE(c.properties()->getProperty(prop), nullptr) << prop;
    EXPECT_FALSE(c.properties()->getProperty(prop)->getDescription().empty()) << prop;
  }
  for (const char* a : {"sim_period", "sim_time", "sim_status", "frames"})
    EXPECT_NE(c.provides()->getAttribute(a), nullptr) << a;
  for (const char* op : {"lastError", "statusName"}) {
    EXPECT_TRUE(c.provides()->hasOperation(op)) << op;
    EXPECT_FALSE(c.provides()->getDescription(op).empty()) << op;
  }
  tactile::WtsSimComponent w("w");
  for (const char* port : {"taxel_forces", "raw_frame"}) {
    ASSERT_NE(w.ports()->getPort(port), nullptr) << port;
    EXPECT_FALSE(w.ports()->getPort(port)->getDescription().empty()) << port;
  }
  ASSERT_NE(w.properties()->getProperty("scene_file"), nullptr);
  EXPECT_FALSE(w.properties()->getProperty("scene_file")->getDescription().empty());
  EXPECT_NE(w.provides()->getAttribute("frames"), nullptr);
}

TEST(LwrSimComponent, ConfigureErrorsNameTheProblem) {
  {
    tactile::LwrSimComponent c("s");
    EXPECT_FALSE(c.configure());
    EXPECT_NE(c.lastError().find("scene_file"), std::string::npos) << c.lastError();
    EXPECT_FALSE(c.start());
  }
  {
    tactile::LwrSimComponent c("s");
    c.properties()->getPropertyType<std::string>("scene_file")->set(TACTILE_SCENE_DIR "/edge_exploration.yaml");
    EXPECT_FALSE(c.configure());
    EXPECT_NE(c.lastError().find("program_file is empty"), std::string::npos) << c.lastError();
  }
  {
    tactile::LwrSimComponent c("s");
    c.properties()->getPropertyType<std::string>("scene_file")->set("/nonexistent/scene.yaml");
    c.properties()->getPropertyType<std::string>("program_file")->set(TACTILE_PROGRAM_DIR "/edge_exploration.yaml");
    EXPECT_FALSE(c.configure());
    EXPECT_NE(c.lastError().find("/nonexistent/scene.yaml"), std::string::npos) << c.lastError();
  }
  {
    // An invalid scene value: the scene loader's message (file and field) comes through.
    const std::string bad = writeTemp("bad_scene.yaml",
                                      "name: bad\n"
                                      "rates: {sim: -5}\n");
    tactile::LwrSimComponent c("s");
    c.properties()->getPropertyType<std::string>("scene_file")->set(bad);
    c.properties()->getPropertyType<std::string>("program_file")->set(TACTILE_PROGRAM_DIR "/edge_exploration.yaml");
    EXPECT_FALSE(c.configure());
    EXPECT_NE(c.lastError().find("rates.sim"), std::string::npos) << c.lastError();
    tactile::WtsSimComponent w("w");
    w.properties()->getPropertyType<std::string>("scene_file")->set(bad);
    EXPECT_FALSE(w.configure());
    EXPECT_NE(w.lastError().find("rates.sim"), std::string::npos) << w.lastError();
  }
  {
    // A KRC script that does not begin with friOpen: the scene's key named.
    const std::string bad = writeTemp("bad_krc_scene.yaml",
                                      "name: bad\n"
                                      "krc: \"1:friStart\"\n");
    tactile::LwrSimComponent c("s");
    c.properties()->getPropertyType<std::string>("scene_file")->set(bad);
    c.properties()->getPropertyType<std::string>("program_file")->set(TACTILE_PROGRAM_DIR "/edge_exploration.yaml");
    EXPECT_FALSE(c.configure());
    EXPECT_NE(c.lastError().find("krc"), std::string::npos) << c.lastError();
    EXPECT_NE(c.lastError().find("friOpen"), std::string::npos) << c.lastError();
  }
}

// robot_state, as the FRI bridge's: the shipped scenes' KRC is in command mode
// throughout; the joints are the arm's, the set point its held command.
TEST(LwrSimComponent, RobotStateSaysCommandableWithTheArmsJointsAndSetPoint) {
  Rig rig(kScene);
  RTT::InputPort<tactile::RobotState> robot_in{"robot_in"};
  rig.io.ports()->addPort(robot_in);
  ASSERT_TRUE(rig.comp.ports()->getPort("robot_state")->connectTo(&robot_in));
  ASSERT_TRUE(rig.comp.configure());
  ASSERT_TRUE(rig.comp.start());
  for (int k = 0; k < 10; ++k) ASSERT_TRUE(rig.comp.update());
  tactile::RobotState r;
  ASSERT_EQ(robot_in.read(r), RTT::NewData);
  EXPECT_TRUE(r.commandable);
  EXPECT_EQ(r.mode, tactile::RobotMode::Command);
  EXPECT_TRUE(r.config_ok);
  EXPECT_FALSE(r.dry_run);
  EXPECT_NEAR(r.time_s, rig.attr<double>("sim_time"), 1e-12);
  const auto& st = rig.comp.world().state();
  for (int j = 0; j < tactile::kArmJoints; ++j) EXPECT_DOUBLE_EQ(r.q[std::size_t(j)], st.q(j)) << j;
  for (int i = 0; i < 3; ++i) EXPECT_DOUBLE_EQ(r.setpoint.p[std::size_t(i)], st.command_g.p[std::size_t(i)]);
}

// The arm is World::step + World::acquireForces on the loop's schedule, the
// sensor TaxelResponse on the file's calibration, nothing else: drive both
// cores from the same scene with the same commands and compare.
TEST(LwrSimComponent, OutputsMatchTheWorldAndTheResponseDrivenDirectly) {
  Rig rig(kScene);
  ASSERT_TRUE(rig.comp.configure()) << rig.comp.lastError();
  ASSERT_TRUE(rig.sensor.configure()) << rig.sensor.lastError();
  ASSERT_TRUE(rig.sensor.start());
  ASSERT_TRUE(rig.comp.start());
  EXPECT_DOUBLE_EQ(rig.attr<double>("sim_period"), 0.001);

  tactile::sim::Scene scene;
  ASSERT_TRUE(tactile::sim::loadRun({kScene, kProgram, ""}, scene).ok());
  tactile::sim::WorldParams wp = scene.world;
  wp.seed = scene.seed;
  tactile::sim::World world;
  ASSERT_TRUE(world.configure(wp).ok());
  tactile::sim::TaxelResponseParams rp;
  rp.calibration = scene.calibration;
  rp.noise_counts = scene.world.pad.noise_counts;
  rp.threshold = scene.world.pad.threshold;
  rp.seed = scene.seed;
  tactile::sim::TaxelResponse response;
  ASSERT_TRUE(response.configure(rp).ok());
  tactile::sim::Schedule sched;
  ASSERT_TRUE(sched.configure(scene.rates, scene.duration).ok());
  tactile::Calibration cal;  // the reader's calibration: the same file
  ASSERT_TRUE(cal.configure(scene.calibration).ok());
  tactile::sim::SimState st = world.state();
  // The arm's estimated wrench with the scene's error (effects.wrench_error:
  // the shipped edge exploration's offset and noise), as the runner makes it.
  tactile::sim::EstimatedWrench estimate;
  estimate.configure(scene.wrench_error, scene.seed);
  estimate.start(st);
  EXPECT_TRUE(scene.wrench_error.any());
  tactile::sim::SensorTruth truth;
  TactileFrame forces_want;
  RawTactileFrame raw_want;

  const Pose start = st.command_g;
  Pose cmd = start;
  int frames = 0, with_contact = 0;
  double worst_cal = 0.0;
  auto acquisition = [&](int k) {  // the arm wrote the image of tick k's acquisition
    world.acquireForces(forces_want, truth);
    TactileFrame forces;
    ASSERT_EQ(rig.forces_in.read(forces), RTT::NewData) << k;
    EXPECT_EQ(forces.force, forces_want.force) << k;
    // The sensor turns it into counts: TaxelResponse on the same seed.
    ASSERT_TRUE(rig.sensor.update());
    response.respond(forces_want, RTT::os::TimeService::Instance()->secondsSince(0), raw_want);
    RawTactileFrame raw;
    ASSERT_EQ(rig.raw_in.read(raw), RTT::NewData) << k;
    EXPECT_EQ(raw.counts, raw_want.counts) << k;
    EXPECT_EQ(raw.seq, static_cast<uint32_t>(frames));
    EXPECT_DOUBLE_EQ(raw.time_s, RTT::os::TimeService::Instance()->secondsSince(0));  // the servo's clock
    // Calibrated with the file, the counts give back the forces (noise, 12-bit, threshold).
    TactileFrame back;
    cal.step(raw, back);
    for (int i = 0; i < back.size(); ++i)
      if (forces_want.force[static_cast<std::size_t>(i)] > 0.5)
        worst_cal = std::max(worst_cal, std::fabs(back.force[static_cast<std::size_t>(i)] -
                                                  forces_want.force[static_cast<std::size_t>(i)]) /
                                            forces_want.force[static_cast<std::size_t>(i)]);
    ++frames;
    if (truth.in_contact) ++with_contact;
  };
  acquisition(0);  // tick 0: written by start()
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
    sched.advance();
    Pose got;
    ASSERT_EQ(rig.pose_in.read(got), RTT::NewData) << k;
    // Same code, same inputs: bit-identical (tolerance 0).
    ASSERT_EQ(got.p, st.flange_g.p) << k;
    ASSERT_EQ(got.q, st.flange_g.q) << k;
    tactile::SimTruth t;
    ASSERT_EQ(rig.truth_in.read(t), RTT::NewData) << k;
    EXPECT_EQ(t.wrench_s, st.wrench_s) << k;
    tactile::Wrench w;
    ASSERT_EQ(rig.wrench_in.read(w), RTT::NewData) << k;
    // The contact force at the flange in {g} axes (the torque moves with the
    // reference point), with the scene's estimation error on top.
    tactile::Wrench want;
    estimate.fill(st, want);
    for (int i = 0; i < 6; ++i) EXPECT_NEAR(w.w[static_cast<std::size_t>(i)], want.w[static_cast<std::size_t>(i)], 1e-12) << k;
    const KDL::Vector f_g = st.T_gs.M * KDL::Vector(st.wrench_s[0], st.wrench_s[1], st.wrench_s[2]);
    for (int i = 0; i < 3; ++i)  // bias (1, -1, 2) N and 0.5 N noise: within |bias| + 6 sigma
      EXPECT_NEAR(w.w[static_cast<std::size_t>(i)], f_g(i), 2.0 + 6 * 0.5) << k;
    if (sched.fires().wts) {
      acquisition(k + 1);
    } else {
      TactileFrame forces;
      EXPECT_NE(rig.forces_in.read(forces), RTT::NewData) << "no acquisition due at step " << k;
    }
  }
  // 3 s at 140 Hz: 420 or 421 acquisitions (plus tick 0's).
  EXPECT_NEAR(frames, 421, 1);
  EXPECT_EQ(rig.attr<int>("frames"), frames);
  EXPECT_NEAR(rig.attr<double>("sim_time"), 3.0, 1e-9);
  // The ramp ends 11.2 cm lower: the sensor must have reached the bar.
  EXPECT_GT(with_contact, 10);
  EXPECT_LT(st.flange_g.p[2], start.p[2] - 0.02);
  EXPECT_LT(worst_cal, 0.05) << "taxels above 0.5 N calibrate back within 5 % (6 counts of noise)";
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
  // restart: back to the scene's initial state (and its tick-0 image)
  ASSERT_TRUE(rig.comp.stop());
  ASSERT_TRUE(rig.comp.start());
  EXPECT_EQ(rig.attr<double>("sim_time"), 0.0);
  EXPECT_EQ(rig.attr<int>("frames"), 1);
}

TEST(LwrSimComponent, UpdateDoesNotAllocate) {
  Rig rig(kScene);
  ASSERT_TRUE(rig.comp.configure());
  ASSERT_TRUE(rig.sensor.configure());
  ASSERT_TRUE(rig.sensor.start());
  ASSERT_TRUE(rig.comp.start());
  Pose cmd = rig.comp.world().state().flange_g;
  PoseCommand pc;
  RawTactileFrame raw;
  TactileFrame forces;
  tactile::SimTruth truth;
  tactile::Wrench wrench;
  Pose pose;
  auto cycle = [&] {  // command in, one update of each, every output read
    pc.pose = cmd;
    rig.command_out.write(pc);
    rig.comp.update();
    rig.sensor.update();
    rig.pose_in.read(pose);
    rig.forces_in.read(forces);
    rig.truth_in.read(truth);
    rig.wrench_in.read(wrench);
    rig.raw_in.read(raw);
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
