// tactile::FriBridgeComponent in-process on 127.0.0.1 with an ephemeral port:
//  * against the simulated KRC (tactile::fri::SimKrc) with the component on a
//    real non-periodic RTT activity (paced by the packets, trigger() loop);
//  * on a SlaveActivity with the test acting as the KRC packet by packet
//    (replies checked, malformed datagrams, timeouts, zero allocations).
#include <gtest/gtest.h>

#include <rtt/Activity.hpp>
#include <rtt/InputPort.hpp>
#include <rtt/OutputPort.hpp>
#include <rtt/TaskContext.hpp>
#include <rtt/extras/SlaveActivity.hpp>
#include <rtt/os/TimeService.hpp>
#include <rtt/os/main.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "alloc_counter.hpp"
#include "tactile_fri/bridge.hpp"
#include "tactile_fri/protocol.hpp"
#include "tactile_fri/sim_krc.hpp"
#include "tactile_fri/udp.hpp"
#include "tactile_fri_rtt/fri_bridge_component.hpp"
#include "tactile_types/kdl_pose.hpp"
#include "support/rtt_environment.hpp"

namespace {

using tactile::Pose;
using tactile::PoseCommand;
namespace fri = tactile::fri;

const auto* const env =
    ::testing::AddGlobalTestEnvironment(new tactile::test::RttEnvironment(tactile::test::Clock::System));

double now() { return RTT::os::TimeService::Instance()->secondsSince(0); }

std::string writeTemp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

// Loopback, ephemeral port, and a desired-pose age limit the test's writes meet.
const char* kParams =
    "fri:\n  max_lin_speed: 0.05\n  max_rot_speed: 0.25\n  max_desired_age_s: 10\n"
    "  udp: {bind_address: 127.0.0.1, port: 0}\n";

struct Rig {
  tactile::FriBridgeComponent comp{"fri"};
  RTT::OutputPort<PoseCommand> command_out{"command_out"};
  RTT::InputPort<Pose> pose_in{"pose_in"};
  RTT::InputPort<std::vector<double>> wrench_in{"wrench_in"};
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
  int attr(const char* name) { return RTT::Attribute<int>(comp.provides()->getAttribute(name)).get(); }
};

TEST(FriBridgeComponent, InterfaceIsDeclaredAndDocumented) {
  tactile::FriBridgeComponent c("f");
  for (const char* port : {"pose_command", "flange_pose", "estimated_wrench"}) {
    ASSERT_NE(c.ports()->getPort(port), nullptr) << port;
    EXPECT_FALSE(c.ports()->getPort(port)->getDescription().empty()) << port;
  }
  for (const char* prop : {"param_file", "port", "receive_timeout"})
    ASSERT_NE(c.properties()->getProperty(prop), nullptr) << prop;
  for (const char* a : {"local_port", "bridge_status", "fri_state", "fri_quality", "received", "replies", "lost",
                        "timeouts", "socket_errors"})
    EXPECT_NE(c.provides()->getAttribute(a), nullptr) << a;
  EXPECT_TRUE(c.provides()->hasOperation("lastError"));
  EXPECT_TRUE(c.provides()->hasOperation("statusName"));
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
    EXPECT_GT(RTT::Attribute<int>(c.provides()->getAttribute("local_port")).get(), 0);
  }
}

// The whole chain in real time-free fast mode: SimKrc in this thread, the
// component in its own (non-periodic) RTT activity, triggered by packets.
TEST(FriBridgeComponent, FollowsTheDesiredPoseAgainstTheSimulatedKrc) {
  Rig rig(new RTT::Activity(ORO_SCHED_OTHER, 0, 0.0), writeTemp("fri_ok.yaml", kParams));
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
  std::vector<double> w;
  EXPECT_NE(rig.wrench_in.read(w), RTT::NoData);
  EXPECT_EQ(w.size(), 6u);
  EXPECT_GE(rig.attr("received"), 1500);
  EXPECT_GE(rig.attr("replies"), 1495);
  EXPECT_EQ(rig.attr("fri_state"), static_cast<int>(fri::State::Cmd));
  EXPECT_EQ(rig.attr("socket_errors"), 0);
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
  std::vector<double> wrench(6);

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

  // No packet: update() returns after receive_timeout and counts a timeout.
  rig.comp.properties()->getPropertyType<double>("receive_timeout")->set(0.02);
  const int timeouts = rig.attr("timeouts");
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_TRUE(rig.comp.update());
  const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(rig.attr("timeouts"), timeouts + 1);
  EXPECT_GE(waited, 0.015);
  EXPECT_LT(waited, 1.0);
}

}  // namespace
