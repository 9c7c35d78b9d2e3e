// tactile::FriBridgeComponent in-process on 127.0.0.1 with an ephemeral port:
//  * against the simulated KRC (tactile::fri::SimKrc) with the component on a
//    RTT::extras::FileDescriptorActivity watching its UDP socket (as deployed),
//    and on a periodic RTT::Activity (queued datagrams read without waiting);
//    a plain non-periodic activity is refused;
//  * on a FileDescriptorActivity with the test acting as the KRC: one cycle and
//    one reply (carrying the latest pose_command) per packet, zero allocations,
//    the silent KRC reported after receive_timeout without spinning, no spin
//    while Stopped, the backlog dropped at start;
//  * on a SlaveActivity with the test acting as the KRC packet by packet
//    (replies checked, malformed datagrams, timeouts, zero allocations).
#include <gtest/gtest.h>

#include <rtt/Activity.hpp>
#include <rtt/InputPort.hpp>
#include <rtt/OutputPort.hpp>
#include <rtt/TaskContext.hpp>
#include <rtt/extras/FileDescriptorActivity.hpp>
#include <rtt/extras/SlaveActivity.hpp>
#include <rtt/os/TimeService.hpp>
#include <rtt/os/main.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#include "alloc_counter.hpp"
#include "tactile_fri/bridge.hpp"
#include "tactile_fri/protocol.hpp"
#include "tactile_fri/sim_krc.hpp"
#include "tactile_fri/udp.hpp"
#include "tactile_fri_rtt/fri_bridge_component.hpp"
#include "tactile_types/kdl_pose.hpp"
#include "support/rtt_environment.hpp"
#include "tactile_types_rtt/atomic_attribute.hpp"

namespace {

using tactile::Pose;
using tactile::PoseCommand;
using tactile::Wrench;
namespace fri = tactile::fri;

const auto* const env =
    ::testing::AddGlobalTestEnvironment(new tactile::test::RttEnvironment(tactile::test::Clock::System));

double now() { return RTT::os::TimeService::Instance()->secondsSince(0); }

// Per process: ctest runs each case as its own process, in parallel, and a
// file of a shared name is truncated by one while another reads it.
std::string writeTemp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + std::to_string(::getpid()) + "_" + name;
  std::ofstream(path) << text;
  return path;
}

// Loopback, ephemeral port, and a desired-pose age limit the test's writes meet.
// The tests here move the desired pose centimetres from the start to check the
// component's plumbing: the bridge's start gate is opened to its widest (the
// gate is tested in test_bridge.cpp and, with the servo, test_start_order.cpp).
const char* kParams =
    "fri:\n  max_lin_speed: 0.05\n  max_rot_speed: 0.25\n  max_desired_age_s: 10\n"
    "  engage_max_trans: 0.1\n  engage_max_rot: 0.5\n"
    "  udp: {bind_address: 127.0.0.1, port: 0}\n";

// Counts updateHook calls (the component's cycles).
struct CountingFri : tactile::FriBridgeComponent {
  using tactile::FriBridgeComponent::FriBridgeComponent;
  std::atomic<int> updates{0};
  void updateHook() override {
    updates.fetch_add(1, std::memory_order_relaxed);
    tactile::FriBridgeComponent::updateHook();
  }
};

struct Rig {
  CountingFri comp{"fri"};
  RTT::OutputPort<PoseCommand> command_out{"command_out"};
  RTT::InputPort<Pose> pose_in{"pose_in"};
  RTT::InputPort<Wrench> wrench_in{"wrench_in"};
  RTT::TaskContext io{"io"};  // declared last: destroyed before the ports it holds

  Rig(RTT::base::ActivityInterface* activity, const std::string& param_file) {
    comp.setActivity(activity);
    io.ports()->addPort(command_out);
    io.ports()->addPort(pose_in);
    io.ports()->addPort(wrench_in);
    comp.properties()->getPropertyType<std::string>("param_file")->set(param_file);
    EXPECT_TRUE(command_out.connectTo(comp.ports()->getPort("pose_command")));
    EXPECT_TRUE(comp.ports()->getPort("flange_pose")->connectTo(&pose_in));
    EXPECT_TRUE(comp.ports()->getPort("estimated_wrench")->connectTo(&wrench_in));
    command_out.setDataSample(PoseCommand());
  }
  ~Rig() { comp.stop(); }  // before CountingFri is destroyed: its updateHook may be running
  int attr(const char* name) { return tactile::readAttribute<int>(*comp.provides(), name); }
  bool flag(const char* name) { return tactile::readAttribute<bool>(*comp.provides(), name); }
  RTT::extras::FileDescriptorActivity* fdActivity() {
    return dynamic_cast<RTT::extras::FileDescriptorActivity*>(comp.getActivity());
  }
};

TEST(FriBridgeComponent, InterfaceIsDeclaredAndDocumented) {
  tactile::FriBridgeComponent c("f");
  for (const char* port : {"pose_command", "flange_pose", "estimated_wrench", "robot_state"}) {
    ASSERT_NE(c.ports()->getPort(port), nullptr) << port;
    EXPECT_FALSE(c.ports()->getPort(port)->getDescription().empty()) << port;
  }
  for (const char* prop : {"param_file", "port", "receive_timeout"})
    ASSERT_NE(c.properties()->getProperty(prop), nullptr) << prop;
  for (const char* a : {"local_port", "bridge_status", "fri_state", "fri_quality", "krc_silent", "fd_activity",
                        "received", "replies", "lost", "timeouts", "socket_errors", "limits",
                        "limited_max_lin_speed", "limited_max_rot_speed", "krc_program", "krc_stop_requested", "krc_stop_cause"})
    EXPECT_NE(c.provides()->getAttribute(a), nullptr) << a;
  EXPECT_TRUE(c.provides()->hasOperation("lastError"));
  EXPECT_TRUE(c.provides()->hasOperation("statusName"));
  EXPECT_TRUE(c.provides()->hasOperation("limitNames"));
  EXPECT_TRUE(c.provides()->hasOperation("requestKrcStop"));
  EXPECT_TRUE(c.provides()->hasOperation("krcProgramName"));
}

TEST(FriBridgeComponent, ConfigureErrorsNameTheParameter) {
  {
    tactile::FriBridgeComponent c("f");
    EXPECT_FALSE(c.configure());
    EXPECT_NE(c.lastError().find("param_file"), std::string::npos) << c.lastError();
  }
  {
    tactile::FriBridgeComponent c("f");
    c.properties()->getPropertyType<std::string>("param_file")->set(
        writeTemp("fri_bad.yaml", "fri:\n  max_lin_speed: 7\n"));
    EXPECT_FALSE(c.configure());
    EXPECT_NE(c.lastError().find("max_lin_speed"), std::string::npos) << c.lastError();
  }
  {
    tactile::FriBridgeComponent c("f");
    c.properties()->getPropertyType<std::string>("param_file")->set(writeTemp("fri_ok.yaml", kParams));
    c.properties()->getPropertyType<int>("port")->set(70000);
    EXPECT_FALSE(c.configure());
    EXPECT_NE(c.lastError().find("port"), std::string::npos) << c.lastError();
  }
  {
    tactile::FriBridgeComponent c("f");
    c.properties()->getPropertyType<std::string>("param_file")->set(writeTemp("fri_ok.yaml", kParams));
    c.properties()->getPropertyType<double>("receive_timeout")->set(0.0);
    EXPECT_FALSE(c.configure());
    EXPECT_NE(c.lastError().find("receive_timeout"), std::string::npos) << c.lastError();
  }
  {
    // The shipped parameter file loads (port overridden: the test must not need 49938).
    tactile::FriBridgeComponent c("f");
    c.properties()->getPropertyType<std::string>("param_file")->set(TACTILE_FRI_PARAM_FILE);
    c.properties()->getPropertyType<int>("port")->set(0);
    EXPECT_TRUE(c.configure()) << c.lastError();
    EXPECT_GT(tactile::readAttribute<int>(*c.provides(), "local_port"), 0);
  }
}

// The whole chain in real time-free fast mode: SimKrc in this thread, the
// component in its own RTT activity, triggered by packets.
void followSimKrc(Rig& rig) {
  ASSERT_TRUE(rig.comp.configure()) << rig.comp.lastError();
  const int port = rig.attr("local_port");
  ASSERT_GT(port, 0);

  fri::FirstOrderPlant plant(0.02);
  fri::SimKrc krc;
  fri::SimKrcParams kp;
  kp.remote_port = static_cast<uint16_t>(port);
  kp.real_time = false;
  kp.reply_timeout_s = 0.2;  // generous: the component's thread shares 2 cores with other builds
  kp.initial.state = fri::State::Mon;
  kp.schedule.push_back({100, fri::State::Cmd, fri::Quality::Perfect, 0x7F});
  ASSERT_TRUE(krc.configure(kp, plant).ok());
  const KDL::Frame start = kp.initial_pose;
  const KDL::Frame target(start.M, start.p + KDL::Vector(0.01, -0.005, 0.0));  // 11 mm away

  ASSERT_TRUE(rig.comp.start());
  PoseCommand desired;
  desired.pose = tactile::toPose(target);
  desired.time_s = now();
  desired.status = tactile::ServoStatus::Ok;
  rig.command_out.write(desired);

  krc.run(1500);
  const fri::SimKrcStats& s = krc.stats();
  ASSERT_TRUE(rig.comp.stop());

  // Every measurement got its reply (fast mode waits up to 0.2 s for it).
  EXPECT_EQ(s.sent, 1500u);
  EXPECT_GE(s.replies, 1495u) << "missed " << s.missed;
  EXPECT_EQ(s.malformed_replies, 0u);
  EXPECT_EQ(s.remote_seq_errors, 0u);
  EXPECT_EQ(s.flag_errors, 0u);
  EXPECT_EQ(s.mon_echo_errors, 0u);  // MON: the measured pose echoed
  EXPECT_GT(s.applied, 1300u);
  // No jump: one rate-limited step per 1 ms command period is <= 0.05 m/s * 1 ms (+ float rounding).
  EXPECT_LE(s.max_cmd_step_m, 0.05 * 0.001 + 1e-6);
  // 1400 CMD cycles at <= 50 mm/s cover 11 mm in 0.22 s, then the first-order
  // plant (tau 20 ms) settles: within 0.1 mm of the target (float32 packets: 1e-7 m).
  const KDL::Vector err = krc.plantState().pose.p - target.p;
  EXPECT_LT(err.Norm(), 1e-4);
  // The component published what the KRC measured, and its counters.
  Pose got;
  ASSERT_NE(rig.pose_in.read(got), RTT::NoData);
  EXPECT_NEAR(got.p[0], krc.plantState().pose.p.x(), 1e-4);
  EXPECT_NEAR(got.p[1], krc.plantState().pose.p.y(), 1e-4);
  EXPECT_NEAR(got.p[2], krc.plantState().pose.p.z(), 1e-4);
  Wrench w;
  EXPECT_NE(rig.wrench_in.read(w), RTT::NoData);
  for (double v : w.w) EXPECT_TRUE(std::isfinite(v));
  EXPECT_GE(rig.attr("received"), 1500);
  EXPECT_GE(rig.attr("replies"), 1495);
  EXPECT_EQ(rig.attr("fri_state"), static_cast<int>(fri::State::Cmd));
  EXPECT_EQ(rig.attr("socket_errors"), 0);
  // The 11 mm were covered at the translation limit: each clipped command counted by its limit's name.
  EXPECT_GT(rig.attr("limited_max_lin_speed"), 150);
  EXPECT_EQ(rig.attr("limited_max_rot_speed"), 0);
  EXPECT_EQ(rig.attr("krc_program"), 20) << "the simulated KRL program reports commanding";
  EXPECT_EQ(rig.comp.krcProgramName(), "commanding");
}

// As deployed: a FileDescriptorActivity watching the socket, one cycle per packet.
TEST(FriBridgeComponent, FileDescriptorActivityFollowsTheSimulatedKrc) {
  Rig rig(new RTT::extras::FileDescriptorActivity(ORO_SCHED_OTHER, 0), writeTemp("fri_ok.yaml", kParams));
  followSimKrc(rig);
  EXPECT_TRUE(rig.flag("fd_activity"));
  // Each of the 1500 packets ran exactly one cycle; besides them only the
  // start() trigger and receive_timeout (0.1 s) wake-ups, if the host stalled.
  const int extra = rig.comp.updates.load() - rig.attr("received");
  EXPECT_GE(extra, 0);
  EXPECT_LE(extra, 1 + rig.attr("timeouts"));
  EXPECT_EQ(rig.attr("received"), 1500);
}

// The servo latches a watchdog: its pose command carries the status on the
// port the bridge already reads; the bridge asks the KRL program to end
// (fri.yaml stop_krc_on_servo_fault), and the simulated KRC leaves command mode.
TEST(FriBridgeComponent, AServoWatchdogOnThePoseCommandStopsTheKrc) {
  Rig rig(new RTT::extras::FileDescriptorActivity(ORO_SCHED_OTHER, 0), writeTemp("fri_ok.yaml", kParams));
  ASSERT_TRUE(rig.comp.configure()) << rig.comp.lastError();
  fri::FirstOrderPlant plant(0.02);
  fri::SimKrc krc;
  fri::SimKrcParams kp;
  kp.remote_port = static_cast<uint16_t>(rig.attr("local_port"));
  kp.real_time = false;
  kp.reply_timeout_s = 0.2;
  kp.initial.state = fri::State::Mon;
  kp.schedule.push_back({50, fri::State::Cmd, fri::Quality::Perfect, 0x7F});
  ASSERT_TRUE(krc.configure(kp, plant).ok());
  ASSERT_TRUE(rig.comp.start());
  PoseCommand desired;
  desired.pose = tactile::toPose(kp.initial_pose);
  desired.time_s = now();
  desired.status = tactile::ServoStatus::Ok;
  rig.command_out.write(desired);
  krc.run(200);
  EXPECT_EQ(krc.state(), fri::State::Cmd);
  EXPECT_FALSE(rig.flag("krc_stop_requested"));
  EXPECT_EQ(rig.attr("krc_program"), 20);
  desired.time_s = now();
  desired.status = tactile::ServoStatus::PhantomContact;  // latched by the servo, the command held
  rig.command_out.write(desired);
  krc.run(50);
  ASSERT_TRUE(rig.comp.stop());
  EXPECT_TRUE(rig.flag("krc_stop_requested"));
  EXPECT_EQ(rig.attr("krc_stop_cause"), static_cast<int>(tactile::ServoStatus::PhantomContact));
  EXPECT_EQ(krc.state(), fri::State::Mon) << "friStop: the KRL program ended";
  EXPECT_EQ(rig.attr("krc_program"), 30) << "closed";
  EXPECT_EQ(krc.stats().mon_echo_errors, 0u);
  EXPECT_LE(krc.stats().max_cmd_step_m, 0.05 * 0.001 + 1e-6);
}

// A periodic Activity (1 kHz): each cycle reads what is queued, never waits.
TEST(FriBridgeComponent, PeriodicActivityFollowsTheSimulatedKrc) {
  Rig rig(new RTT::Activity(ORO_SCHED_OTHER, 0, 0.001), writeTemp("fri_ok.yaml", kParams));
  followSimKrc(rig);
  EXPECT_FALSE(rig.flag("fd_activity"));
}

// A plain non-periodic Activity (the TaskContext's default): the hook never
// waits, so it would spin or never read: start() refuses it and says why.
TEST(FriBridgeComponent, NonPeriodicPlainActivityIsRefused) {
  Rig rig(new RTT::Activity(ORO_SCHED_OTHER, 0, 0.0), writeTemp("fri_ok.yaml", kParams));
  ASSERT_TRUE(rig.comp.configure()) << rig.comp.lastError();
  EXPECT_FALSE(rig.comp.start());
  EXPECT_NE(rig.comp.lastError().find("FileDescriptorActivity"), std::string::npos) << rig.comp.lastError();
  EXPECT_EQ(rig.comp.updates.load(), 0);
}

// The test is the KRC: one measurement, one update(), one reply.
struct ManualKrc {
  fri::UdpSocket sock;
  fri::MsrPacket msr{};
  fri::CmdPacket cmd{};
  std::array<uint8_t, 2048> buf{};
  sockaddr_in remote{};
  explicit ManualKrc(uint16_t remote_port) {
    fri::UdpParams up;
    up.bind_address = "127.0.0.1";
    up.port = 0;
    EXPECT_TRUE(sock.open(up).ok());
    remote = fri::loopbackAddress(remote_port);
    msr.intf.state = static_cast<uint16_t>(fri::State::Cmd);
    msr.intf.quality = static_cast<uint16_t>(fri::Quality::Perfect);
    msr.intf.desired_msr_sample_time = msr.intf.desired_cmd_sample_time = 0.001f;
    msr.robot.power = 0x7F;
    msr.robot.control = static_cast<uint16_t>(fri::ControlStrategy::CartImpedance);
    fri::fromFrame(KDL::Frame(KDL::Rotation::RPY(3.14159265358979, 0, 0), KDL::Vector(0.5, 0.0, 0.4)),
                   msr.data.msr_cart_pos);
  }
  void send() {
    ++msr.head.send_seq;
    std::size_t n = 0;
    fri::encodeMeasurement(msr, buf.data(), buf.size(), n);
    sock.sendTo(remote, buf.data(), n);
  }
  bool reply(int64_t timeout_us = 200000) {
    std::size_t n = 0;
    if (sock.receive(buf.data(), buf.size(), n, timeout_us) != fri::UdpStatus::Ok) return false;
    if (fri::decodeCommand(buf.data(), n, cmd) != fri::PacketStatus::Ok) return false;
    msr.head.refl_seq = cmd.head.send_seq;
    return true;
  }
};

TEST(FriBridgeComponent, OnePacketPerUpdateMalformedAndTimeoutsAndNoAllocation) {
  Rig rig(new RTT::extras::SlaveActivity(), writeTemp("fri_ok.yaml", kParams));
  rig.comp.properties()->getPropertyType<double>("receive_timeout")->set(0.2);
  ASSERT_TRUE(rig.comp.configure());
  ASSERT_TRUE(rig.comp.start());
  ManualKrc krc(static_cast<uint16_t>(rig.attr("local_port")));
  PoseCommand desired;
  KDL::Frame start;
  fri::toFrame(krc.msr.data.msr_cart_pos, start);
  desired.pose = tactile::toPose(KDL::Frame(start.M, start.p + KDL::Vector(0.0, 0.0, -0.01)));
  desired.status = tactile::ServoStatus::Ok;
  Pose pose;
  Wrench wrench;

  // Warm-up cycles (first port samples, first reply).
  for (int k = 0; k < 20; ++k) {
    desired.time_s = now();
    rig.command_out.write(desired);
    krc.send();
    ASSERT_TRUE(rig.comp.update());
    ASSERT_TRUE(krc.reply()) << k;
    rig.pose_in.read(pose);
    rig.wrench_in.read(wrench);
  }
  double prev_z = 0.0;
  {
    tactile::test::AllocationScope scope;
    for (int k = 0; k < 500; ++k) {
      desired.time_s = now();
      rig.command_out.write(desired);
      krc.send();
      rig.comp.update();
      const bool ok = krc.reply();
      rig.pose_in.read(pose);
      rig.wrench_in.read(wrench);
      if (!ok) break;
      KDL::Frame c;
      fri::toFrame(krc.cmd.cmd.cart_pos, c);
      prev_z = c.p.z();
    }
    EXPECT_EQ(scope.count(), 0u);
  }
  EXPECT_EQ(rig.attr("replies"), 520);
  EXPECT_EQ(rig.attr("bridge_status"), static_cast<int>(fri::BridgeStatus::Commanding));
  // 520 limited steps of 50 um: the 10 mm move is complete (float32 packet: 1e-6 m).
  EXPECT_NEAR(prev_z, 0.39, 1e-6);
  EXPECT_NEAR(pose.p[2], 0.4, 1e-6);  // the measured pose is what the "KRC" sent

  // A malformed datagram: status Malformed, no reply, nothing crashes.
  const uint8_t junk[10] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
  krc.sock.sendTo(krc.remote, junk, sizeof junk);
  ASSERT_TRUE(rig.comp.update());
  EXPECT_EQ(rig.attr("bridge_status"), static_cast<int>(fri::BridgeStatus::Malformed));
  EXPECT_FALSE(krc.reply(20000));

  // No packet: update() returns at once (never waits) and the KRC is not yet
  // silent; once receive_timeout has passed without a datagram (RTT's
  // TimeService), the next update() counts one timeout and reports krc_silent.
  rig.comp.properties()->getPropertyType<double>("receive_timeout")->set(0.3);
  krc.send();
  ASSERT_TRUE(rig.comp.update());  // a datagram: the silence clock restarts
  ASSERT_TRUE(krc.reply());
  const int timeouts = rig.attr("timeouts");
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_TRUE(rig.comp.update());
  const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(waited, 0.3);  // generous: a wait of receive_timeout would take 0.3 s
  EXPECT_EQ(rig.attr("timeouts"), timeouts);
  EXPECT_FALSE(rig.flag("krc_silent"));
  std::this_thread::sleep_for(std::chrono::milliseconds(350));
  ASSERT_TRUE(rig.comp.update());
  EXPECT_EQ(rig.attr("timeouts"), timeouts + 1);
  EXPECT_TRUE(rig.flag("krc_silent"));
  EXPECT_EQ(rig.comp.statusName(), "krc_silent");
  ASSERT_TRUE(rig.comp.update());  // counted once per receive_timeout, not per cycle
  EXPECT_EQ(rig.attr("timeouts"), timeouts + 1);
  krc.send();  // the next datagram clears it
  ASSERT_TRUE(rig.comp.update());
  EXPECT_TRUE(krc.reply());
  EXPECT_FALSE(rig.flag("krc_silent"));
}

// Polls `pred` every 1 ms for up to `limit_s`; returns the seconds it took, or -1.
template <class Pred>
double waitFor(Pred pred, double limit_s) {
  const auto t0 = std::chrono::steady_clock::now();
  for (;;) {
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (pred()) return t;
    if (t > limit_s) return -1.0;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

// The test is the KRC, the component runs on a FileDescriptorActivity: every
// packet runs exactly one updateHook and gets exactly one reply, which carries
// the pose_command written just before the packet; no allocation per cycle.
TEST(FriBridgeComponent, FileDescriptorActivityOneCycleAndOneReplyPerPacketWithTheLatestCommand) {
  Rig rig(new RTT::extras::FileDescriptorActivity(ORO_SCHED_OTHER, 0), writeTemp("fri_ok.yaml", kParams));
  rig.comp.properties()->getPropertyType<double>("receive_timeout")->set(0.5);  // no timeout in this test
  ASSERT_TRUE(rig.comp.configure()) << rig.comp.lastError();
  EXPECT_TRUE(rig.flag("fd_activity"));
  ASSERT_NE(rig.fdActivity(), nullptr);
  EXPECT_EQ(rig.fdActivity()->getTimeout_us(), 500000);  // receive_timeout
  ASSERT_TRUE(rig.comp.start());
  ManualKrc krc(static_cast<uint16_t>(rig.attr("local_port")));
  KDL::Frame start;
  fri::toFrame(krc.msr.data.msr_cart_pos, start);
  // The desired pose moves 20 um per packet, less than one rate-limited step
  // (0.05 m/s * 1 ms = 50 um): the reply must carry exactly the latest one
  // (the previous one is 20 um away; float32 on the wire: 1e-6 m).
  PoseCommand desired;
  desired.status = tactile::ServoStatus::Ok;
  int k = 0;
  auto command = [&] {
    ++k;
    desired.pose = tactile::toPose(KDL::Frame(start.M, start.p + KDL::Vector(0.0, 0.0, -20e-6 * k)));
    desired.time_s = now();
    rig.command_out.write(desired);
  };
  auto repliedZ = [&] {
    KDL::Frame c;
    fri::toFrame(krc.cmd.cmd.cart_pos, c);
    return c.p.z();
  };
  Pose pose;
  Wrench wrench;
  for (int i = 0; i < 20; ++i) {  // warm-up (first port samples, start() trigger consumed)
    command();
    krc.send();
    ASSERT_TRUE(krc.reply()) << i;
    rig.pose_in.read(pose);
    rig.wrench_in.read(wrench);
  }
  // The component counts a packet after its reply is on the way: let it finish.
  ASSERT_GE(waitFor([&] { return rig.attr("received") == 20; }, 1.0), 0.0);
  const int updates0 = rig.comp.updates.load();
  const int replies0 = rig.attr("replies");
  int wrong = 0;
  {
    tactile::test::AllocationScope scope;
    for (int i = 0; i < 500; ++i) {
      command();
      krc.send();
      if (!krc.reply()) break;
      if (std::abs(repliedZ() - (start.p.z() - 20e-6 * k)) > 1e-6) ++wrong;
      rig.pose_in.read(pose);
      rig.wrench_in.read(wrench);
    }
    EXPECT_EQ(scope.count(), 0u);
  }
  EXPECT_EQ(wrong, 0) << "replies not carrying the latest pose_command";
  EXPECT_FALSE(krc.reply(20000)) << "more replies than packets";
  EXPECT_GE(waitFor([&] { return rig.attr("received") == 520; }, 1.0), 0.0);
  EXPECT_EQ(rig.comp.updates.load() - updates0, 500) << "updateHook calls for 500 packets";
  EXPECT_EQ(rig.attr("replies") - replies0, 500);
  EXPECT_EQ(rig.attr("timeouts"), 0);
  EXPECT_EQ(rig.attr("bridge_status"), static_cast<int>(fri::BridgeStatus::Commanding));
  EXPECT_NEAR(pose.p[2], 0.4, 1e-6);  // the measured pose is what the "KRC" sent

  // A burst of 5 packets sent at once: still one cycle and one reply each.
  const int updates1 = rig.comp.updates.load();
  command();
  for (int i = 0; i < 5; ++i) krc.send();
  int burst_replies = 0;
  while (krc.reply(200000)) ++burst_replies;
  EXPECT_EQ(burst_replies, 5);
  EXPECT_EQ(rig.comp.updates.load() - updates1, 5);
  EXPECT_NEAR(repliedZ(), start.p.z() - 20e-6 * k, 1e-6);
  EXPECT_EQ(rig.attr("socket_errors"), 0);
}

// The KRC goes silent: krc_silent (and statusName() "krc_silent") within about
// receive_timeout, one timeout cycle per receive_timeout (no spinning), cleared
// by the next packet. Stopped, the component does not spin on a readable
// socket, and start() drops the packets queued meanwhile.
TEST(FriBridgeComponent, FileDescriptorActivitySilentKrcIsReportedWithoutSpinning) {
  constexpr double kTimeout = 0.05;
  Rig rig(new RTT::extras::FileDescriptorActivity(ORO_SCHED_OTHER, 0), writeTemp("fri_ok.yaml", kParams));
  rig.comp.properties()->getPropertyType<double>("receive_timeout")->set(kTimeout);
  ASSERT_TRUE(rig.comp.configure()) << rig.comp.lastError();
  ASSERT_TRUE(rig.comp.start());
  ManualKrc krc(static_cast<uint16_t>(rig.attr("local_port")));
  PoseCommand desired;
  KDL::Frame start;
  fri::toFrame(krc.msr.data.msr_cart_pos, start);
  desired.pose = tactile::toPose(start);
  desired.status = tactile::ServoStatus::Ok;
  for (int i = 0; i < 10; ++i) {
    desired.time_s = now();
    rig.command_out.write(desired);
    krc.send();
    ASSERT_TRUE(krc.reply()) << i;
  }
  EXPECT_NE(rig.comp.statusName(), "krc_silent");

  // Silence: reported after about receive_timeout (not before: the last packet
  // arrived just before its reply), well within a few timeouts.
  const double t_silent = waitFor([&] { return rig.comp.statusName() == "krc_silent"; }, 1.0);
  ASSERT_GE(t_silent, 0.0) << "krc_silent not reported within 1 s";
  EXPECT_GE(t_silent, 0.6 * kTimeout) << "reported too early";
  EXPECT_LE(t_silent, kTimeout + 0.25) << "reported too late";
  EXPECT_TRUE(rig.flag("krc_silent"));
  // No spinning: over 0.5 s about 0.5 / 0.05 = 10 timeout cycles.
  const int u0 = rig.comp.updates.load();
  const int t0 = rig.attr("timeouts");
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const int cycles = rig.comp.updates.load() - u0;
  EXPECT_GE(cycles, 3);
  EXPECT_LE(cycles, 12) << "updateHook spins while the KRC is silent";
  EXPECT_NEAR(rig.attr("timeouts") - t0, cycles, 1);  // every one a timeout (sampled while running)
  // The KRC is back: one reply, the status is the bridge's again.
  desired.time_s = now();
  rig.command_out.write(desired);
  krc.send();
  ASSERT_TRUE(krc.reply());
  EXPECT_NE(rig.comp.statusName(), "krc_silent");
  EXPECT_FALSE(rig.flag("krc_silent"));

  // Stopped with a KRC sending: the socket is not watched, the activity does not spin.
  ASSERT_TRUE(rig.comp.stop());
  const unsigned c0 = rig.comp.getCycleCounter();
  for (int i = 0; i < 20; ++i) krc.send();
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_LE(rig.comp.getCycleCounter() - c0, 10u) << "the activity spins on the unread socket while Stopped";
  EXPECT_FALSE(krc.reply(20000));
  // start() drops those 20 stale packets: the next packet is the only one answered.
  const int received = rig.attr("received");
  ASSERT_TRUE(rig.comp.start());
  desired.time_s = now();
  rig.command_out.write(desired);
  krc.send();
  ASSERT_TRUE(krc.reply());
  EXPECT_FALSE(krc.reply(20000));
  EXPECT_EQ(rig.attr("received") - received, 1);
  EXPECT_EQ(rig.attr("socket_errors"), 0);
}

}  // namespace

// estimated_wrench is in {g} whatever axes the KRC sends estExtTcpFT in: the
// component reads them as fri.wrench_frame says. A KRC in tool axes with the
// flange turned 90 deg about base y (flange x points down) sends a 10 N pull
// along base -z as +10 N along flange x.
TEST(FriBridgeComponent, EstimatedWrenchIsInTheBaseFrameForEitherWrenchFrame) {
  const KDL::Frame pose(KDL::Rotation::RPY(3.14159265358979, 3.14159265358979 / 2, 0), KDL::Vector(0.5, 0.0, 0.4));
  const std::array<double, 6> base_w{0.0, 0.0, -10.0, 0.3, 0.0, 0.0};
  for (fri::WrenchFrame frame : {fri::WrenchFrame::Base, fri::WrenchFrame::Tool}) {
    Rig rig(new RTT::extras::SlaveActivity(),
            writeTemp("fri_wrench.yaml", std::string(kParams) + "  wrench_frame: " + fri::toString(frame) + "\n"));
    ASSERT_TRUE(rig.comp.configure()) << rig.comp.lastError();
    ASSERT_TRUE(rig.comp.start());
    ManualKrc krc(static_cast<uint16_t>(rig.attr("local_port")));
    krc.msr.intf.state = static_cast<uint16_t>(fri::State::Mon);
    fri::fromFrame(pose, krc.msr.data.msr_cart_pos);
    fri::fromWrenchIn(base_w, frame, pose.M, krc.msr.data.est_ext_tcp_ft);  // the KRC's $STIFFNESS.FRAMETYPE
    if (frame == fri::WrenchFrame::Tool) {
      EXPECT_NEAR(krc.msr.data.est_ext_tcp_ft[0], 10.0f, 1e-5);
    }
    krc.send();
    ASSERT_TRUE(rig.comp.update());
    ASSERT_TRUE(krc.reply());
    Wrench w;
    ASSERT_NE(rig.wrench_in.read(w), RTT::NoData);
    for (std::size_t i = 0; i < 6; ++i) EXPECT_NEAR(w.w[i], base_w[i], 1e-5) << fri::toString(frame) << " " << i;
  }
}
