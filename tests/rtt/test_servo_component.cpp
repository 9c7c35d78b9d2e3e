// tactile::ServoComponent in-process: SlaveActivity, RTT's TimeService driven
// by hand, outputs compared with tactile::TactileServo run directly.
#include <gtest/gtest.h>

#include <rtt/Attribute.hpp>
#include <rtt/InputPort.hpp>
#include <rtt/OutputPort.hpp>
#include <rtt/TaskContext.hpp>
#include <rtt/extras/SlaveActivity.hpp>
#include <rtt/plugin/PluginLoader.hpp>
#include <rtt/scripting/Scripting.hpp>
#include <rtt/os/TimeService.hpp>
#include <rtt/os/main.h>

#include <cmath>
#include <string>

#include "alloc_counter.hpp"
#include "tactile_servo/program_io.hpp"
#include "tactile_servo/servo.hpp"
#include "tactile_servo_rtt/servo_component.hpp"
#include "support/rtt_environment.hpp"
#include "tactile_types_rtt/atomic_attribute.hpp"

namespace {

using tactile::ContactFeatures;
using tactile::PhaseState;
using tactile::Pose;
using tactile::PoseCommand;
using tactile::ServoStatus;

const auto* const env =
    ::testing::AddGlobalTestEnvironment(new tactile::test::RttEnvironment(tactile::test::Clock::Manual));

const std::string kProgram = TACTILE_SERVO_PROGRAM_DIR "/edge_exploration.yaml";
constexpr double kDt = 0.01;  // 100 Hz, the rate the program's gains are sized for

double now() { return RTT::os::TimeService::Instance()->secondsSince(0); }

struct Rig {
  tactile::ServoComponent comp{"servo"};
  RTT::OutputPort<ContactFeatures> features_out{"features_out"};
  RTT::OutputPort<Pose> pose_out{"pose_out"};
  RTT::InputPort<PoseCommand> command_in{"command_in"};
  RTT::InputPort<PhaseState> phase_in{"phase_in"};
  RTT::TaskContext io{"io"};  // declared last: destroyed before the ports it holds

  explicit Rig(const std::string& program) {
    comp.setActivity(new RTT::extras::SlaveActivity(kDt));
    io.ports()->addPort(features_out);
    io.ports()->addPort(pose_out);
    io.ports()->addPort(command_in);
    io.ports()->addPort(phase_in);
    comp.properties()->getPropertyType<std::string>("program_file")->set(program);
    EXPECT_TRUE(features_out.connectTo(comp.ports()->getPort("features")));
    EXPECT_TRUE(pose_out.connectTo(comp.ports()->getPort("flange_pose")));
    EXPECT_TRUE(comp.ports()->getPort("pose_command")->connectTo(&command_in));
    EXPECT_TRUE(comp.ports()->getPort("phase")->connectTo(&phase_in));
  }
};

ContactFeatures noContact(double t) {
  ContactFeatures f;
  f.time_s = t;
  f.status = tactile::FeatureStatus::NoContact;
  f.contact = tactile::ContactType::None;
  return f;
}

ContactFeatures edge(double t, double cop_x, double alpha) {
  ContactFeatures f;
  f.time_s = t;
  f.cop_x = cop_x;
  f.coc_x = cop_x;
  f.alpha_z = alpha;
  f.alpha_defined = true;
  f.force = 4.0;
  f.d_z = 4.0 / 1800.0;
  f.lambda1 = 1e-4;
  f.lambda2 = 1e-6;
  f.area = 14;
  f.contact = tactile::ContactType::Edge;
  f.status = tactile::FeatureStatus::Ok;
  return f;
}

Pose startPose() {
  Pose p;
  p.p = {0.5, 0.0, 0.4};
  p.q = {1.0, 0.0, 0.0, 0.0};  // sensor facing down
  return p;
}

std::vector<double> integralAttribute(tactile::ServoComponent& c) {
  RTT::base::AttributeBase* a = c.provides()->getAttribute("integral");
  if (!a) return {};
  auto ds = RTT::internal::DataSource<std::vector<double>>::narrow(a->getDataSource().get());
  return ds ? ds->get() : std::vector<double>();
}

TEST(ServoComponent, InterfaceIsDeclaredAndDocumented) {
  tactile::ServoComponent c("s");
  for (const char* port : {"features", "flange_pose", "estimated_wrench", "robot_state", "pose_command", "phase"}) {
    ASSERT_NE(c.ports()->getPort(port), nullptr) << port;
    EXPECT_FALSE(c.ports()->getPort(port)->getDescription().empty()) << port;
  }
  for (const char* prop : {"program_file", "controller_mode", "period"}) {
    ASSERT_NE(c.properties()->getProperty(prop), nullptr) << prop;
    EXPECT_FALSE(c.properties()->getProperty(prop)->getDescription().empty()) << prop;
  }
  for (const char* attr : {"last_status", "integral"}) EXPECT_NE(c.provides()->getAttribute(attr), nullptr) << attr;
  EXPECT_EQ(integralAttribute(c).size(), 6u);
  for (const char* op : {"switchPhase", "phaseName", "phaseIndex", "phaseIndexOf", "controllerMode", "lastError"}) {
    EXPECT_TRUE(c.provides()->hasOperation(op)) << op;
    EXPECT_FALSE(c.provides()->getDescription(op).empty()) << op;
  }
}

TEST(ServoComponent, CommandsMatchTheCore) {
  Rig rig(kProgram);
  ASSERT_TRUE(rig.comp.configure()) << rig.comp.lastError();
  ASSERT_TRUE(rig.comp.start());
  tactile::TactileServo core;
  tactile::ServoParams p;
  ASSERT_TRUE(tactile::loadServoProgram(kProgram, p).ok());
  ASSERT_TRUE(core.configure(p).ok());
  tactile::ServoInput in;
  tactile::ServoOutput want;
  Pose pose = startPose();
  int commands = 0;
  int integral_nonzero = 0;
  double t_prev = 0.0;
  for (int k = 0; k < 60; ++k) {
    RTT::os::TimeService::Instance()->secondsChange(kDt);
    const double t = now();
    // The component's dt: the activity period on the first cycle, then the
    // difference of TimeService readings.
    const double dt = k == 0 ? kDt : t - t_prev;
    t_prev = t;
    // Free motion for 20 cycles, then an edge appears (phase changes follow).
    const ContactFeatures f = k < 20 ? noContact(t) : edge(t, 0.002, 0.1);
    rig.features_out.write(f);
    rig.pose_out.write(pose);
    ASSERT_TRUE(rig.comp.update());
    in.time_s = t;
    in.features = f;
    in.flange_measured = pose;
    core.step(in, dt, want);
    PoseCommand got;
    ASSERT_EQ(rig.command_in.read(got), RTT::NewData) << k;
    ++commands;
    // Same code, same inputs, same dt: bit-identical (tolerance 0).
    EXPECT_EQ(got.pose.p, want.command.pose.p) << k;
    EXPECT_EQ(got.pose.q, want.command.pose.q) << k;
    EXPECT_EQ(got.status, want.command.status) << k;
    PhaseState ph;
    ASSERT_EQ(rig.phase_in.read(ph), RTT::NewData);
    EXPECT_EQ(ph.index, want.phase.index) << k;
    EXPECT_STREQ(ph.name.data(), want.phase.name.data());
    // The integrator's view (attribute integral): the core's state after the same step.
    const std::vector<double> integral = integralAttribute(rig.comp);
    ASSERT_EQ(integral.size(), 6u);
    for (int i = 0; i < 6; ++i) EXPECT_EQ(integral[static_cast<std::size_t>(i)], core.controlLaw().integral()[i]) << k << " axis " << i;
    if (core.controlLaw().integral().norm() > 0.0) ++integral_nonzero;
    pose = got.pose;  // an ideal robot follows the command
  }
  // The comparison above is not only between zero vectors: the edge phase integrated its error.
  EXPECT_GT(integral_nonzero, 0);
  EXPECT_EQ(commands, 60);
  // The run left phase I (free motion) once the edge appeared.
  EXPECT_NE(rig.comp.phaseName(), "free_motion");
  EXPECT_GT(pose.p[2], 0.0);
}

TEST(ServoComponent, FreeMotionMovesAlongTheApproachDirection) {
  Rig rig(kProgram);
  ASSERT_TRUE(rig.comp.configure());
  ASSERT_TRUE(rig.comp.start());
  EXPECT_EQ(rig.comp.phaseName(), "free_motion");
  Pose pose = startPose();
  for (int k = 0; k < 10; ++k) {
    RTT::os::TimeService::Instance()->secondsChange(kDt);
    rig.features_out.write(noContact(now()));
    rig.pose_out.write(pose);
    rig.comp.update();
    PoseCommand c;
    ASSERT_EQ(rig.command_in.read(c), RTT::NewData);
    pose = c.pose;
  }
  // Sensor facing down ({s} z along -z_g): the first command is the measured
  // pose, then 9 cycles at 0.01 m/s, 10 ms: 0.9 mm down.
  // Tolerance 1e-9 m: floating-point accumulation over 10 pose compositions.
  EXPECT_NEAR(pose.p[2], 0.4 - 0.0009, 1e-9);
  EXPECT_NEAR(pose.p[0], 0.5, 1e-9);
}

TEST(ServoComponent, SwitchPhaseByName) {
  Rig rig(kProgram);
  EXPECT_FALSE(rig.comp.switchPhase("explore"));  // not configured
  ASSERT_TRUE(rig.comp.configure());
  ASSERT_TRUE(rig.comp.start());
  EXPECT_FALSE(rig.comp.switchPhase("no_such_phase"));
  EXPECT_TRUE(rig.comp.switchPhase("explore"));
  RTT::os::TimeService::Instance()->secondsChange(kDt);
  rig.features_out.write(edge(now(), 0.0, 0.0));
  rig.pose_out.write(startPose());
  rig.comp.update();
  EXPECT_EQ(rig.comp.phaseName(), "explore");
  PhaseState ph;
  ASSERT_EQ(rig.phase_in.read(ph), RTT::NewData);
  EXPECT_STREQ(ph.name.data(), "explore");
  EXPECT_EQ(ph.index, 3);
  EXPECT_EQ(rig.comp.phaseIndexOf("explore"), 3);
  EXPECT_EQ(rig.comp.phaseIndexOf("free_motion"), 0);
  EXPECT_EQ(rig.comp.phaseIndexOf("no_such_phase"), -1);
}

TEST(ServoComponent, PhaseIndexOperations) {
  Rig rig(kProgram);
  EXPECT_EQ(rig.comp.phaseIndex(), -1);  // not configured
  EXPECT_EQ(rig.comp.phaseIndexOf("explore"), -1);
  ASSERT_TRUE(rig.comp.configure());
  EXPECT_EQ(rig.comp.phaseIndex(), 0);
  EXPECT_EQ(rig.comp.phaseIndexOf("explore"), 3);
  EXPECT_EQ(rig.comp.phaseIndexOf("no_such_phase"), -1);
  ASSERT_TRUE(rig.comp.start());
  EXPECT_TRUE(rig.comp.switchPhase("explore"));
  RTT::os::TimeService::Instance()->secondsChange(kDt);
  rig.features_out.write(edge(now(), 0.0, 0.0));
  rig.pose_out.write(startPose());
  rig.comp.update();
  EXPECT_EQ(rig.comp.phaseIndex(), 3);
}

// controller_mode overrides the program's controller.mode (the deployments'
// the registry entry bent_bar_baseline selects the Li et al. baseline this way,
// bent_bar_no_rotation the ablation).
TEST(ServoComponent, ControllerModeProperty) {
  auto mode = [](const std::string& m) {
    Rig rig(kProgram);
    rig.comp.properties()->getPropertyType<std::string>("controller_mode")->set(m);
    const bool ok = rig.comp.configure();
    return ok ? rig.comp.controllerMode() : "refused: " + rig.comp.lastError();
  };
  EXPECT_EQ(mode(""), "proposed");  // the program's controller.mode
  EXPECT_EQ(mode("proposed"), "proposed");
  EXPECT_EQ(mode("baseline"), "baseline");
  EXPECT_EQ(mode("no_rotation"), "no_rotation");
  const std::string bad = mode("Baseline");
  EXPECT_NE(bad.find("refused: "), std::string::npos) << bad;
  EXPECT_NE(bad.find("controller_mode = 'Baseline'"), std::string::npos) << bad;
  EXPECT_NE(bad.find("proposed, baseline or no_rotation"), std::string::npos) << bad;
  const std::string bad2 = mode("li");
  EXPECT_NE(bad2.find("controller_mode = 'li'"), std::string::npos) << bad2;
}

TEST(ServoComponent, NoFlangePoseNoCommand) {
  Rig rig(kProgram);
  ASSERT_TRUE(rig.comp.configure());
  ASSERT_TRUE(rig.comp.start());
  RTT::os::TimeService::Instance()->secondsChange(kDt);
  rig.features_out.write(noContact(now()));
  rig.comp.update();
  PoseCommand c;
  EXPECT_EQ(rig.command_in.read(c), RTT::NoData);
  PhaseState ph;
  EXPECT_EQ(rig.phase_in.read(ph), RTT::NewData);  // the phase is still reported
}

// A pose written before start() does not count (it may be stale): the servo
// waits for a sample written after it, and its first command is that pose.
TEST(ServoComponent, FirstCommandIsAPoseWrittenAfterStart) {
  Rig rig(kProgram);
  ASSERT_TRUE(rig.comp.configure());
  Pose stale = startPose();
  stale.p = {0.0, 0.0, 0.019};
  rig.pose_out.write(stale);
  ASSERT_TRUE(rig.comp.start());
  PoseCommand c;
  for (int k = 0; k < 5; ++k) {
    RTT::os::TimeService::Instance()->secondsChange(kDt);
    rig.features_out.write(noContact(now()));
    rig.comp.update();
    EXPECT_EQ(rig.command_in.read(c), RTT::NoData) << k;
    EXPECT_EQ(tactile::readAttribute<int>(*rig.comp.provides(), "last_status"),
              static_cast<int>(ServoStatus::WaitingForPose));
  }
  RTT::os::TimeService::Instance()->secondsChange(kDt);
  rig.features_out.write(noContact(now()));
  rig.pose_out.write(startPose());
  rig.comp.update();
  ASSERT_EQ(rig.command_in.read(c), RTT::NewData);
  EXPECT_EQ(c.status, ServoStatus::Starting);
  EXPECT_EQ(c.pose.p, startPose().p);
}

TEST(ServoComponent, NaNPoseHoldsWithAFiniteCommand) {
  Rig rig(kProgram);
  ASSERT_TRUE(rig.comp.configure());
  ASSERT_TRUE(rig.comp.start());
  RTT::os::TimeService::Instance()->secondsChange(kDt);
  rig.features_out.write(noContact(now()));
  rig.pose_out.write(startPose());
  rig.comp.update();
  PoseCommand c;
  ASSERT_EQ(rig.command_in.read(c), RTT::NewData);
  Pose bad = startPose();
  bad.p[1] = std::nan("");
  RTT::os::TimeService::Instance()->secondsChange(kDt);
  rig.features_out.write(noContact(now()));
  rig.pose_out.write(bad);
  rig.comp.update();
  ASSERT_EQ(rig.command_in.read(c), RTT::NewData);
  EXPECT_EQ(c.status, ServoStatus::InvalidInput);
  for (double v : c.pose.p) EXPECT_TRUE(std::isfinite(v));
  for (double v : c.pose.q) EXPECT_TRUE(std::isfinite(v));
}

TEST(ServoComponent, BadProgramFileMakesConfigureFail) {
  {
    Rig rig(TACTILE_SERVO_PROGRAM_DIR "/does_not_exist.yaml");
    EXPECT_FALSE(rig.comp.configure());
    EXPECT_NE(rig.comp.lastError().find("does_not_exist.yaml"), std::string::npos) << rig.comp.lastError();
  }
  {
    Rig rig("");
    EXPECT_FALSE(rig.comp.configure());
    EXPECT_NE(rig.comp.lastError().find("program_file"), std::string::npos);
  }
}

TEST(ServoComponent, UpdateCycleDoesNotAllocate) {
  Rig rig(kProgram);
  ASSERT_TRUE(rig.comp.configure());
  ASSERT_TRUE(rig.comp.start());
  Pose pose = startPose();
  PoseCommand c;
  PhaseState ph;
  ContactFeatures f = noContact(0);
  auto cycle = [&](int k) {
    RTT::os::TimeService::Instance()->secondsChange(kDt);
    f = k < 5 ? noContact(now()) : edge(now(), 0.001, 0.05);
    rig.features_out.write(f);
    rig.pose_out.write(pose);
    rig.comp.update();
    if (rig.command_in.read(c, false) == RTT::NewData) pose = c.pose;
    rig.phase_in.read(ph, false);
  };
  cycle(0);  // warm-up through every connection
  EXPECT_TRUE(rig.comp.switchPhase("edge_control"));
  tactile::test::AllocationScope scope;
  for (int k = 1; k < 100; ++k) cycle(k);
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_EQ(rig.comp.phaseName().empty(), false);
}

// The experiment state machines (deployments/*_experiment.osd) run in the
// servo's thread, one step per servo cycle: once in a state, a cycle (its run
// program and transition checks: phaseIndex(), phase.last(), arithmetic) must
// not allocate. Loaded here as the deployments load them (RTT's scripting
// service, OCL's print service for the entry programs), stepped by the
// servo's SlaveActivity.
struct OsdCase {
  const char* program;
  const char* osd;
  const char* machine;
  const char* waiting;  ///< the state waiting for the program's working phase
  const char* working;  ///< the state while the program is in that phase
  bool point;           ///< the touch is a point (the sphere), else an edge
  const char* phase;    ///< timed_phase_experiment.osd's phase_name (its registry param), else nullptr
};

TEST(ServoComponent, ExperimentStateMachineCyclesDoNotAllocate) {
  auto loader = RTT::plugin::PluginLoader::Instance();
  ASSERT_TRUE(loader->loadPlugins(TACTILE_RTT_OWN_PACKAGE_DIR));  // scripting
  ASSERT_TRUE(loader->loadPlugins(TACTILE_OCL_PACKAGE_DIR));      // print
  ASSERT_TRUE(loader->loadTypekits(TACTILE_RTT_OWN_PACKAGE_DIR));
  ASSERT_TRUE(loader->loadTypekits(TACTILE_RTT_PACKAGE_DIR));     // /tactile/PhaseState
  const OsdCase cases[] = {
      {"/bent_bar.yaml", "/timed_phase_experiment.osd", "TimedPhaseExperiment", "WAIT_PHASE", "IN_PHASE", false,
       "explore"},
      {"/co_manipulation.yaml", "/timed_phase_experiment.osd", "TimedPhaseExperiment", "WAIT_PHASE", "IN_PHASE",
       false, "balance"},
      {"/edge_exploration.yaml", "/timed_phase_experiment.osd", "TimedPhaseExperiment", "WAIT_PHASE", "IN_PHASE",
       true, "align"},
      {"/first_touch.yaml", "/first_touch_experiment.osd", "FirstTouchExperiment", "WAIT_TOUCH", "HOLD", false,
       nullptr},
  };
  for (const OsdCase& c : cases) {
    SCOPED_TRACE(c.osd);
    Rig rig(std::string(TACTILE_SERVO_PROGRAM_DIR) + c.program);
    ASSERT_TRUE(rig.comp.configure()) << rig.comp.lastError();
    ASSERT_TRUE(loader->loadService("scripting", &rig.comp));
    ASSERT_TRUE(loader->loadService("print", &rig.comp));
    auto scripting = rig.comp.getProvider<RTT::Scripting>("scripting");
    ASSERT_TRUE(scripting->loadStateMachines(std::string(TACTILE_DEPLOYMENTS_DIR) + c.osd));
    ASSERT_TRUE(rig.comp.start());
    Pose pose = startPose();
    PoseCommand cmd;
    PhaseState ph;
    bool touching = false;
    auto cycle = [&]() {
      RTT::os::TimeService::Instance()->secondsChange(kDt);
      ContactFeatures f = touching ? edge(now(), 0.0, 0.0) : noContact(now());
      if (touching && c.point) {
        f.contact = tactile::ContactType::Point;
        f.lambda2 = f.lambda1;
      }
      rig.features_out.write(f);
      rig.pose_out.write(pose);
      rig.comp.update();
      if (rig.command_in.read(cmd, false) == RTT::NewData) pose = cmd.pose;
      rig.phase_in.read(ph, false);
    };
    cycle();
    ASSERT_TRUE(scripting->activateStateMachine(c.machine));
    cycle();  // activate() done (it sets the RootMachine line's params) before a param is set
    if (c.phase) {
      RTT::base::AttributeBase* a = rig.comp.provides()->getService(c.machine)->getAttribute("phase_name");
      ASSERT_NE(a, nullptr);
      auto* d = RTT::internal::AssignableDataSource<std::string>::narrow(a->getDataSource().get());
      ASSERT_NE(d, nullptr);
      d->set(c.phase);
    }
    ASSERT_TRUE(scripting->startStateMachine(c.machine));
    for (int k = 0; k < 3; ++k) cycle();  // INIT -> waiting (its entry prints)
    ASSERT_EQ(scripting->getStateMachineState(c.machine), c.waiting);
    {
      tactile::test::AllocationScope scope;
      for (int k = 0; k < 50; ++k) cycle();
      EXPECT_EQ(scope.count(), 0u) << "per cycle in " << c.waiting;
    }
    touching = true;  // the program's first phase sees contact -> its working phase
    // (20 cycles: the first touch enters its hold after 0.1 s of contact)
    for (int k = 0; k < 20; ++k) cycle();
    ASSERT_EQ(scripting->getStateMachineState(c.machine), c.working) << rig.comp.phaseName();
    {
      tactile::test::AllocationScope scope;
      for (int k = 0; k < 50; ++k) cycle();
      EXPECT_EQ(scope.count(), 0u) << "per cycle in " << c.working;
    }
    EXPECT_EQ(scripting->getStateMachineState(c.machine), c.working);
    ASSERT_TRUE(scripting->stopStateMachine(c.machine));
    rig.comp.update();
    ASSERT_TRUE(rig.comp.stop());
    ASSERT_TRUE(scripting->unloadStateMachine(c.machine));
  }
}

}  // namespace
