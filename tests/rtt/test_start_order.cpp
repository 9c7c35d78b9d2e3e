// Safe start: whatever order the components of a loop start in, nothing is
// commanded before the servo has a valid measured pose, the servo's first
// command IS that measured pose, and the arm never moves further than the
// program's steps allow (none before the first command, none with the first,
// at most max_trans_speed / max_rot_speed times the servo period per later command).
//
//  * Sim loop: arm (LwrSimComponent), sensor (WtsSimComponent), features (FeatureComponent), servo
//    (ServoComponent) started in all 24 orders, 20 ms apart, each on a
//    SlaveActivity updated in data-flow order on a simulated clock (1 ms
//    ticks; servo every 10 ticks). The run continues until the program leaves
//    free_motion (the bar is touched), which the default-pose bug never did.
//  * Robot loop: FriBridgeComponent + ServoComponent (both orders) with the
//    KRC coming up late: the simulated KRC (fri::SimKrc, FirstOrderPlant) on
//    loopback starts after both components ran without it, (a) directly in
//    CMD, (b) in MON and in CMD 5 cycles later, (c) in MON for 300 cycles while
//    the servo integrates, then CMD: the bridge's start gate refuses the
//    drifted command (desired_far) and the arm does not move at all.
//
// Components are found by role in a table and wired BY PORT NAME (as a
// deployment does): re-point the test at other components by editing
// makeSimLoop()/makeRobotLoop() only.
#include <gtest/gtest.h>

#include <rtt/Attribute.hpp>
#include <rtt/ConnPolicy.hpp>
#include <rtt/InputPort.hpp>
#include <rtt/TaskContext.hpp>
#include <rtt/base/InputPortInterface.hpp>
#include <rtt/extras/SlaveActivity.hpp>
#include <rtt/os/TimeService.hpp>
#include <rtt/os/main.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <kdl/frames.hpp>

#include "tactile_features_rtt/feature_component.hpp"
#include "tactile_fri/bridge.hpp"
#include "tactile_fri/protocol.hpp"
#include "tactile_fri/sim_krc.hpp"
#include "tactile_fri_rtt/fri_bridge_component.hpp"
#include "tactile_servo/program_io.hpp"
#include "tactile_servo_rtt/servo_component.hpp"
#include "tactile_sim_rtt/lwr_sim_component.hpp"
#include "tactile_sim_rtt/wts_sim_component.hpp"
#include "tactile_types/kdl_pose.hpp"
#include "support/rtt_environment.hpp"
#include "tactile_types_rtt/atomic_attribute.hpp"

namespace {

using tactile::ContactFeatures;
using tactile::PhaseState;
using tactile::Pose;
using tactile::PoseCommand;
using tactile::ServoStatus;
namespace fri = tactile::fri;

const auto* const env =
    ::testing::AddGlobalTestEnvironment(new tactile::test::RttEnvironment(tactile::test::Clock::Manual));

const std::string kProgram = TACTILE_PROGRAM_DIR "/edge_exploration.yaml";
const std::string kScene = TACTILE_SCENE_DIR "/edge_exploration.yaml";
const std::string kFeatureParams = TACTILE_FEATURE_PARAMS;
const std::string kFriParams = TACTILE_FRI_PARAM_FILE;
constexpr double kTick = 0.001;  // s: the arm's physics step, the KRC's period
constexpr int kServoEvery = 10;  // ticks: the servo at 100 Hz

void advanceClock(double dt) { RTT::os::TimeService::Instance()->secondsChange(dt); }

bool isInput(RTT::base::PortInterface* p) { return dynamic_cast<RTT::base::InputPortInterface*>(p) != nullptr; }

// connect(from.out, to.in) by name, as the deployer does (types must match).
bool connectByName(RTT::TaskContext& from, const std::string& out, RTT::TaskContext& to, const std::string& in,
                   const RTT::ConnPolicy& policy = RTT::ConnPolicy()) {
  RTT::base::PortInterface* o = from.ports()->getPort(out);
  RTT::base::PortInterface* i = to.ports()->getPort(in);
  if (!o || !i || isInput(o) || !isInput(i) || o->getTypeInfo() != i->getTypeInfo()) return false;
  return o->connectTo(i, policy);
}

template <typename T>
T attr(RTT::TaskContext& tc, const char* name) {
  return tactile::readAttribute<T>(*tc.provides(), name);
}

// The program's step limits (the bound on every later command's motion).
struct Steps {
  double trans = 0.0, rot = 0.0, lever = 0.0;  // m, rad per cycle; |{e}p{s}| (m)
};
Steps programSteps() {
  tactile::ServoParams p;
  EXPECT_TRUE(tactile::loadServoProgram(kProgram, p).ok());
  const double period = 0.01;  // the servo's period here: every 10 ticks of 1 ms
  return {p.safety.max_trans_speed * period, p.safety.max_rot_speed * period, p.sensor_mount.p.Norm()};
}

double transDist(const Pose& a, const Pose& b) {
  return (tactile::toFrame(a).p - tactile::toFrame(b).p).Norm();
}
double rotDist(const Pose& a, const Pose& b) {
  KDL::Vector axis;
  return fri::rotationAngle(tactile::toFrame(a).M.Inverse() * tactile::toFrame(b).M, axis);
}

// The flange may move, per command after the first, one translation step plus
// the swing of the flange about the sensor origin (lever * rotation step).
void expectWithinSteps(const Pose& start, const Pose& now, int commands, const Steps& s, double tol,
                       const std::string& where) {
  const int n = std::max(0, commands - 1);
  EXPECT_LE(transDist(start, now), n * (s.trans + s.lever * s.rot) + tol) << where << ", commands " << commands;
  EXPECT_LE(rotDist(start, now), n * s.rot + tol) << where << ", commands " << commands;
}

// A component of a loop: its role, and how often it is updated (ticks).
struct Node {
  std::string role;
  std::unique_ptr<RTT::TaskContext> tc;
  int every = 1;
  bool running = false;
};

// Observation ports (a probe TaskContext holds them).
struct Probe {
  RTT::InputPort<Pose> measured{"measured"};
  RTT::InputPort<PoseCommand> commands{"commands"};
  RTT::InputPort<PhaseState> phase{"phase"};
  RTT::OutputPort<ContactFeatures> features{"features"};  // robot loop: the sensor stand-in
  RTT::TaskContext tc{"probe"};  // declared last: destroyed before the ports it holds
  Probe() {
    tc.ports()->addPort(measured);
    tc.ports()->addPort(commands);
    tc.ports()->addPort(phase);
    tc.ports()->addPort(features);
  }
};

// ---------------------------------------------------------------- sim loop

/// A loop of components under test and the probe on its ports.
struct Loop {
  std::vector<Node> nodes;  // data-flow order: update order within a tick
  Probe probe;
  RTT::TaskContext& get(const std::string& role) {
    for (Node& n : nodes)
      if (n.role == role) return *n.tc;
    ADD_FAILURE() << "no node " << role;
    return *nodes.front().tc;
  }
};
using SimLoop = Loop;

std::unique_ptr<SimLoop> makeSimLoop() {
  auto loop = std::make_unique<SimLoop>();
  auto arm = std::make_unique<tactile::LwrSimComponent>("arm");
  arm->properties()->getPropertyType<std::string>("scene_file")->set(kScene);
  arm->properties()->getPropertyType<std::string>("program_file")->set(kProgram);
  auto sensor = std::make_unique<tactile::WtsSimComponent>("sensor");
  sensor->properties()->getPropertyType<std::string>("scene_file")->set(kScene);
  auto features = std::make_unique<tactile::FeatureComponent>("features");
  features->properties()->getPropertyType<std::string>("param_file")->set(kFeatureParams);
  auto servo = std::make_unique<tactile::ServoComponent>("servo");
  servo->properties()->getPropertyType<std::string>("program_file")->set(kProgram);
  arm->setActivity(new RTT::extras::SlaveActivity(kTick));
  sensor->setActivity(new RTT::extras::SlaveActivity(kTick));
  features->setActivity(new RTT::extras::SlaveActivity(kTick));
  servo->setActivity(new RTT::extras::SlaveActivity(kServoEvery * kTick));
  loop->nodes.push_back({"arm", std::move(arm), 1, false});
  loop->nodes.push_back({"sensor", std::move(sensor), 1, false});
  loop->nodes.push_back({"features", std::move(features), 1, false});
  loop->nodes.push_back({"servo", std::move(servo), kServoEvery, false});
  RTT::TaskContext& a = loop->get("arm");
  RTT::TaskContext& w = loop->get("sensor");
  RTT::TaskContext& f = loop->get("features");
  RTT::TaskContext& s = loop->get("servo");
  EXPECT_TRUE(connectByName(a, "taxel_forces", w, "taxel_forces"));
  EXPECT_TRUE(connectByName(w, "raw_frame", f, "raw_frame"));
  EXPECT_TRUE(connectByName(f, "features", s, "features"));
  EXPECT_TRUE(connectByName(a, "flange_pose", s, "flange_pose"));
  EXPECT_TRUE(connectByName(s, "pose_command", a, "pose_command"));
  EXPECT_TRUE(connectByName(a, "flange_pose", loop->probe.tc, "measured"));
  EXPECT_TRUE(connectByName(s, "pose_command", loop->probe.tc, "commands", RTT::ConnPolicy::buffer(64)));
  EXPECT_TRUE(connectByName(s, "phase", loop->probe.tc, "phase"));
  for (Node& n : loop->nodes) EXPECT_TRUE(n.tc->configure()) << n.role;
  return loop;
}

TEST(StartOrder, SimLoopEveryOrderStartsFromTheMeasuredPose) {
  const Steps steps = programSteps();
  std::vector<std::string> order = {"arm", "sensor", "features", "servo"};
  std::sort(order.begin(), order.end());
  int orders = 0;
  do {
    const std::string name = order[0] + " > " + order[1] + " > " + order[2] + " > " + order[3];
    SCOPED_TRACE(name);
    ++orders;
    std::unique_ptr<SimLoop> loop = makeSimLoop();
    SimLoop& L = *loop;
    Pose start{}, last_measured = tactile::kNoPose;
    bool have_start = false;
    int commands = 0, started = 0;
    std::string phase = "free_motion";
    const int kStagger = 20, kMaxTicks = 6000;
    for (int tick = 0; tick < kMaxTicks && phase == "free_motion"; ++tick) {
      if (tick % kStagger == 0 && started < 4) {
        for (Node& n : L.nodes)
          if (n.role == order[static_cast<std::size_t>(started)]) n.running = n.tc->start();
        ++started;
      }
      advanceClock(kTick);
      for (Node& n : L.nodes) {
        if (!n.running || tick % n.every != 0) continue;
        ASSERT_TRUE(n.tc->update()) << n.role;
        Pose m;  // the arm's pose after each update: what the servo reads next
        while (L.probe.measured.read(m, false) == RTT::NewData) {
          last_measured = m;
          if (!have_start) {
            start = m;
            have_start = true;
          }
          expectWithinSteps(start, m, commands, steps, 1e-9, "tick " + std::to_string(tick));
        }
        if (::testing::Test::HasFailure()) return;
      }
      PoseCommand c;
      while (L.probe.commands.read(c, false) == RTT::NewData) {
        if (commands == 0) {
          // The first command is the measured pose the servo read, unchanged.
          ASSERT_TRUE(have_start) << "a command before the arm published any pose";
          EXPECT_EQ(c.status, ServoStatus::Starting);
          EXPECT_LT(transDist(c.pose, last_measured), 1e-12);
          EXPECT_LT(rotDist(c.pose, last_measured), 1e-9);
          EXPECT_LT(transDist(c.pose, start), 1e-12);  // the arm had not moved
        }
        ++commands;
      }
      PhaseState ph;
      if (L.probe.phase.read(ph, false) == RTT::NewData) phase = ph.name.data();
      if (L.get("arm").isRunning()) {  // no joint limit, no singularity, no force limit
        ASSERT_LT(attr<int>(L.get("arm"), "sim_status"), 10) << "tick " << tick;
      }
    }
    EXPECT_GT(commands, 10);
    EXPECT_NE(phase, "free_motion") << "the arm never reached the bar";
    std::printf("[ start    ] %-28s %4d commands, phase %s, flange moved %.1f mm\n", name.c_str(), commands,
                phase.c_str(), 1e3 * transDist(start, last_measured));
    for (Node& n : L.nodes) n.tc->stop();
  } while (std::next_permutation(order.begin(), order.end()));
  EXPECT_EQ(orders, 24);
}

// ---------------------------------------------------------------- robot loop

using RobotLoop = Loop;

std::unique_ptr<RobotLoop> makeRobotLoop() {
  auto loop = std::make_unique<RobotLoop>();
  auto robot = std::make_unique<tactile::FriBridgeComponent>("robot");
  robot->properties()->getPropertyType<std::string>("param_file")->set(kFriParams);  // the shipped gate
  robot->properties()->getPropertyType<int>("port")->set(0);                         // ephemeral
  robot->properties()->getPropertyType<double>("receive_timeout")->set(0.01);
  auto servo = std::make_unique<tactile::ServoComponent>("servo");
  servo->properties()->getPropertyType<std::string>("program_file")->set(kProgram);
  robot->setActivity(new RTT::extras::SlaveActivity());
  servo->setActivity(new RTT::extras::SlaveActivity(kServoEvery * kTick));
  loop->nodes.push_back({"robot", std::move(robot), 1, false});
  loop->nodes.push_back({"servo", std::move(servo), kServoEvery, false});
  RTT::TaskContext& r = loop->get("robot");
  RTT::TaskContext& s = loop->get("servo");
  EXPECT_TRUE(connectByName(r, "flange_pose", s, "flange_pose"));
  EXPECT_TRUE(connectByName(s, "pose_command", r, "pose_command"));
  EXPECT_TRUE(connectByName(loop->probe.tc, "features", s, "features"));
  EXPECT_TRUE(connectByName(r, "flange_pose", loop->probe.tc, "measured"));
  EXPECT_TRUE(connectByName(s, "pose_command", loop->probe.tc, "commands", RTT::ConnPolicy::buffer(64)));
  for (Node& n : loop->nodes) EXPECT_TRUE(n.tc->configure()) << n.role;
  return loop;
}

ContactFeatures noContact(double t) {
  ContactFeatures f;
  f.time_s = t;
  f.status = tactile::FeatureStatus::NoContact;
  f.contact = tactile::ContactType::None;
  return f;
}

struct KrcScenario {
  const char* name;
  fri::State first;
  uint64_t cmd_at;  // KRC cycle of the switch to CMD (0: up in CMD)
  bool follows;     // the arm follows the servo in the end
};

TEST(StartOrder, RobotLoopKrcLateStartsFromTheMeasuredPose) {
  const Steps steps = programSteps();
  const KrcScenario scenarios[] = {{"KRC up in CMD", fri::State::Cmd, 0, true},
                                   {"KRC up in MON, CMD 5 cycles later", fri::State::Mon, 5, true},
                                   {"KRC in MON for 300 cycles, then CMD", fri::State::Mon, 300, false}};
  for (const KrcScenario& sc : scenarios) {
    for (const char* first : {"robot", "servo"}) {
      SCOPED_TRACE(std::string(sc.name) + ", " + first + " started first");
      std::unique_ptr<RobotLoop> loop = makeRobotLoop();
      RobotLoop& L = *loop;
      RTT::TaskContext& robot = L.get("robot");
      RTT::TaskContext& servo = L.get("servo");
      // Both components start and run for a while with no KRC (40 ms).
      Node& a = L.nodes[first == std::string("robot") ? 0 : 1];
      Node& b = L.nodes[first == std::string("robot") ? 1 : 0];
      ASSERT_TRUE(a.running = a.tc->start());
      for (int k = 0; k < 2; ++k) {
        advanceClock(kTick);
        a.tc->update();
      }
      ASSERT_TRUE(b.running = b.tc->start());
      for (int k = 0; k < 4; ++k) {
        advanceClock(kServoEvery * kTick);
        L.probe.features.write(noContact(RTT::os::TimeService::Instance()->secondsSince(0)));
        robot.update();  // times out: no KRC yet
        servo.update();
      }
      PoseCommand c;
      EXPECT_EQ(L.probe.commands.read(c), RTT::NoData) << "a command before any measured pose";
      EXPECT_EQ(attr<int>(servo, "last_status"), static_cast<int>(ServoStatus::WaitingForPose));
      EXPECT_TRUE(attr<bool>(robot, "krc_silent"));

      // The KRC comes up.
      fri::SimKrcParams kp;
      kp.remote_port = static_cast<uint16_t>(attr<int>(robot, "local_port"));
      kp.period_s = kTick;
      kp.real_time = false;
      kp.reply_timeout_s = 0.5;
      kp.initial.state = sc.first;
      if (sc.cmd_at > 0) kp.schedule = {{sc.cmd_at, fri::State::Cmd, fri::Quality::Perfect, 0x7F}};
      fri::FirstOrderPlant plant(0.02);
      fri::SimKrc krc;
      ASSERT_TRUE(krc.configure(kp, plant).ok());
      const int kCycles = 600;
      std::atomic<bool> stop_krc{false};  // set when the test gives up early: no waiting for 600 replies
      std::thread krc_thread([&krc, &stop_krc] { krc.run(kCycles, &stop_krc); });
      Pose start{}, last_measured = tactile::kNoPose, m;
      bool have_start = false;
      int commands = 0, received = attr<int>(robot, "received"), guard = 0;
      while (received < kCycles && ++guard < 400 * kCycles) {
        robot.update();  // the datagram queued, if any (never waits)
        const int r = attr<int>(robot, "received");
        if (r == received) {  // none yet: this thread (the test's scheduler) waits, not the hook
          std::this_thread::sleep_for(std::chrono::microseconds(50));
          continue;
        }
        received = r;
        advanceClock(kTick);
        while (L.probe.measured.read(m, false) == RTT::NewData) {
          last_measured = m;
          if (!have_start) {
            start = m;
            have_start = true;
          }
          expectWithinSteps(start, m, commands, steps, 1e-6, "cycle " + std::to_string(received));
        }
        if (received % kServoEvery == 0) {
          L.probe.features.write(noContact(RTT::os::TimeService::Instance()->secondsSince(0)));
          servo.update();
          while (L.probe.commands.read(c, false) == RTT::NewData) {
            if (commands == 0) {
              EXPECT_EQ(c.status, ServoStatus::Starting);
              EXPECT_LT(transDist(c.pose, last_measured), 1e-12);
              EXPECT_LT(rotDist(c.pose, last_measured), 1e-9);
            }
            ++commands;
          }
        }
        if (::testing::Test::HasFailure()) break;
      }
      stop_krc = true;
      krc_thread.join();
      std::printf("[ start    ] %-36s %-6s first: %3d commands, bridge %s, flange moved %.2f mm\n", sc.name, first,
                  commands, fri::toString(static_cast<fri::BridgeStatus>(attr<int>(robot, "bridge_status"))),
                  1e3 * transDist(start, last_measured));
      EXPECT_EQ(received, kCycles);
      EXPECT_GT(commands, 40);
      const fri::SimKrcStats& s = krc.stats();
      EXPECT_EQ(s.nonfinite_commands, 0u);
      EXPECT_EQ(s.mon_echo_errors, 0u);
      // The first command the KRC applied in CMD is the measured pose, to float precision.
      EXPECT_LE(s.max_entry_offset_m, 1e-6);
      const fri::BridgeStatus bs = static_cast<fri::BridgeStatus>(attr<int>(robot, "bridge_status"));
      if (sc.follows) {
        EXPECT_TRUE(bs == fri::BridgeStatus::Commanding || bs == fri::BridgeStatus::Limited) << fri::toString(bs);
        EXPECT_GT(transDist(start, last_measured), 1e-3);  // free motion, ~0.1 mm per servo cycle
      } else {
        EXPECT_EQ(bs, fri::BridgeStatus::DesiredFar);
        EXPECT_LT(transDist(start, last_measured), 1e-6);  // never moved
        EXPECT_LT(rotDist(start, last_measured), 1e-5);
      }
      for (Node& n : L.nodes) n.tc->stop();
    }
  }
}

}  // namespace
