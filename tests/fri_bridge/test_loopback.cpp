// The real bridge (FriBridge + UdpSocket) against the simulated KRC over UDP
// on 127.0.0.1 with ephemeral ports, with and without injected faults.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <vector>
#include <thread>

#include <poll.h>

#include "alloc_counter.hpp"
#include "fri_test_util.hpp"
#include "tactile_fri/bridge.hpp"
#include "tactile_fri/sim_krc.hpp"
#include "tactile_fri/udp.hpp"

using namespace tactile;
using namespace tactile::fri;
using namespace fri_test;

namespace {

double steadyNow() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Float quantisation of poses on the wire (see test_bridge.cpp).
constexpr double kPosTol = 2e-7;
constexpr double kRotTol = 2e-6;

/// The remote side as the RTT component will run it: triggered by each
/// received datagram, one bridge step, one reply.
class BridgeLoop {
 public:
  /// A fixed desired pose `target`, centimetres from the start: these tests
  /// exercise the rate limiter and the fault handling, so the start gate is
  /// opened to its widest (its own tests are in test_bridge.cpp).
  explicit BridgeLoop(BridgeParams p, const KDL::Frame& target) {
    p.engage_max_trans = 0.1;
    p.engage_max_rot = 0.5;
    EXPECT_TRUE(bridge_.configure(p).ok());
    UdpParams up;
    up.bind_address = "127.0.0.1";
    up.port = 0;
    EXPECT_TRUE(sock_.open(up).ok());
    desired_.status = ServoStatus::Ok;
    toPose(target, desired_.pose);
  }
  uint16_t port() const { return sock_.localPort(); }
  void start() {
    thread_ = std::thread([this] { loop(); });
  }
  void stop() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
  }
  ~BridgeLoop() { stop(); }
  const BridgeStats& stats() const { return bridge_.stats(); }
  uint64_t seen(BridgeStatus s) const { return status_count_[static_cast<std::size_t>(s)]; }

 private:
  void loop() {
    std::array<uint8_t, 2048> buf{};
    uint8_t tx[kCmdPacketSize];
    BridgeOutput out;
    while (!stop_) {
      std::size_t n = 0;
      const UdpStatus s = sock_.receive(buf.data(), buf.size(), n, 20000);
      if (s != UdpStatus::Ok && s != UdpStatus::Truncated) continue;
      const double now = steadyNow();
      desired_.time_s = now;
      bridge_.stepDatagram(buf.data(), n, desired_, now, out);
      ++status_count_[static_cast<std::size_t>(out.status)];
      if (out.reply) {
        std::size_t w = 0;
        encodeCommand(out.cmd, tx, sizeof tx, w);
        sock_.reply(tx, w);
      }
    }
  }
  FriBridge bridge_;
  UdpSocket sock_;
  PoseCommand desired_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
  std::array<uint64_t, static_cast<std::size_t>(BridgeStatus::NotConfigured) + 1> status_count_{};  // every status
};

SimKrcParams fastKrc(uint16_t port) {
  SimKrcParams p;
  p.remote_port = port;
  p.period_s = 0.001;
  p.real_time = false;       // faster than real time: wait for each reply instead of sleeping
  p.reply_timeout_s = 0.5;   // generous: the machine is shared
  p.initial_pose = startPose();
  p.initial.state = State::Mon;
  p.initial.quality = Quality::Perfect;
  return p;
}

}  // namespace

TEST(FriLoopback, CleanLinkMonCmdMon) {
  BridgeParams bp;
  bp.max_lin_speed = 0.05;
  const KDL::Frame target(startPose().M, startPose().p + KDL::Vector(0.01, 0.0, 0.0));
  BridgeLoop bridge(bp, target);
  SimKrcParams kp = fastKrc(bridge.port());
  kp.schedule = {{50, State::Cmd, Quality::Perfect, 0x7F}, {450, State::Mon, Quality::Perfect, 0x7F}};
  FirstOrderPlant plant(0.02);
  SimKrc krc;
  ASSERT_TRUE(krc.configure(kp, plant).ok());
  bridge.start();
  krc.run(500);
  bridge.stop();
  const SimKrcStats& s = krc.stats();
  EXPECT_EQ(s.replies, 500u);
  EXPECT_EQ(s.missed, 0u);
  EXPECT_EQ(s.stale_replies, 0u);
  EXPECT_EQ(s.malformed_replies, 0u);
  EXPECT_EQ(s.remote_seq_errors, 0u);
  EXPECT_EQ(s.flag_errors, 0u);
  EXPECT_EQ(s.mon_echo_errors, 0u);
  EXPECT_EQ(s.applied, 400u);
  EXPECT_LE(s.max_cmd_step_m, bp.max_lin_speed * 0.001 + kPosTol);
  EXPECT_LE(s.max_entry_offset_m, bp.max_lin_speed * 0.001 + kPosTol);
  // 10 mm at 50 mm/s = 200 commands, then 200 more cycles with tau = 20 ms: the
  // plant sits on the target to well below 0.1 mm (exp(-10) * 10 mm).
  EXPECT_LT((krc.plantState().pose.p - target.p).Norm(), 1e-4);
  EXPECT_GT(bridge.seen(BridgeStatus::Limited), 150u);
  EXPECT_GT(bridge.seen(BridgeStatus::Commanding), 100u);
  EXPECT_EQ(bridge.seen(BridgeStatus::LeftCmd), 50u);
  EXPECT_EQ(bridge.seen(BridgeStatus::Monitor), 50u);
}

TEST(FriLoopback, FaultsNeverProduceAJumpOrAWrongEcho) {
  BridgeParams bp;
  bp.max_lin_speed = 0.05;
  bp.max_rot_speed = 0.25;
  const KDL::Frame target(KDL::Rotation::RotZ(0.1) * startPose().M, startPose().p + KDL::Vector(0.0, 0.03, 0.0));
  BridgeLoop bridge(bp, target);
  SimKrcParams kp = fastKrc(bridge.port());
  kp.schedule = {{100, State::Cmd, Quality::Perfect, 0x7F}, {600, State::Cmd, Quality::Bad, 0x7F},
                 {700, State::Cmd, Quality::Ok, 0x7F},       {1000, State::Mon, Quality::Ok, 0x7F},
                 {1100, State::Cmd, Quality::Perfect, 0x7F}, {1400, State::Cmd, Quality::Unacceptable, 0x7F},
                 {1450, State::Mon, Quality::Bad, 0x7F},     {1500, State::Cmd, Quality::Perfect, 0x7F},
                 {1800, State::Cmd, Quality::Perfect, 0x00}, {1900, State::Cmd, Quality::Perfect, 0x7F}};
  kp.faults.loss = 0.03;
  kp.faults.duplicate = 0.03;
  kp.faults.reorder = 0.03;
  kp.faults.late = 0.02;
  kp.faults.wrong_size = 0.02;
  kp.faults.wrong_id = 0.02;
  kp.faults.seed = 12345;
  kp.reply_timeout_s = 0.2;
  FirstOrderPlant plant(0.02);
  SimKrc krc;
  ASSERT_TRUE(krc.configure(kp, plant).ok());
  bridge.start();
  krc.run(2500);
  bridge.stop();
  const SimKrcStats& s = krc.stats();
  // every fault kind was exercised
  EXPECT_GT(s.inj_lost, 20u);
  EXPECT_GT(s.inj_duplicate, 20u);
  EXPECT_GT(s.inj_reorder, 20u);
  EXPECT_GT(s.inj_late, 10u);
  EXPECT_GT(s.inj_wrong_size, 10u);
  EXPECT_GT(s.inj_wrong_id, 10u);
  // and the bridge saw them
  const BridgeStats& b = bridge.stats();
  EXPECT_EQ(b.duplicates, s.inj_duplicate);
  EXPECT_GE(b.out_of_order, s.inj_reorder / 2);
  EXPECT_EQ(b.malformed, s.inj_wrong_size + s.inj_wrong_id);
  EXPECT_GT(b.lost, s.inj_lost);
  EXPECT_GT(b.holds, 100u);  // the quality drops
  EXPECT_GT(bridge.seen(BridgeStatus::LeftCmd), 50u);
  EXPECT_GT(bridge.seen(BridgeStatus::PowerOff), 50u);
  // safety: no jump, no wrong echo, nothing non-finite, protocol kept
  EXPECT_LE(s.max_cmd_step_m, bp.max_lin_speed * 0.001 + kPosTol);
  EXPECT_LE(s.max_cmd_step_rad, bp.max_rot_speed * 0.001 + kRotTol);
  EXPECT_LE(s.max_entry_offset_m, bp.max_lin_speed * 0.001 + kPosTol);
  EXPECT_LE(s.max_entry_offset_rad, bp.max_rot_speed * 0.001 + kRotTol);
  EXPECT_EQ(s.mon_echo_errors, 0u);
  EXPECT_EQ(s.nonfinite_commands, 0u);
  EXPECT_EQ(s.flag_errors, 0u);
  EXPECT_EQ(s.malformed_replies, 0u);
  EXPECT_EQ(s.remote_seq_errors, 0u);
  EXPECT_GT(s.applied, 1000u);
}

TEST(FriLoopback, CommandLossOnTheWayBackIsSeenByTheKrc) {
  // Losing our replies: the KRC sees gaps in our sendSeqCount, never a jump.
  BridgeParams bp;
  const KDL::Frame target(startPose().M, startPose().p + KDL::Vector(0.0, 0.0, -0.02));
  BridgeLoop bridge(bp, target);
  SimKrcParams kp = fastKrc(bridge.port());
  kp.initial.state = State::Cmd;
  kp.faults.cmd_loss = 0.05;
  kp.faults.seed = 99;
  kp.reply_timeout_s = 0.2;  // a lost reply costs this wait
  FirstOrderPlant plant(0.02);
  SimKrc krc;
  ASSERT_TRUE(krc.configure(kp, plant).ok());
  bridge.start();
  krc.run(300);
  bridge.stop();
  const SimKrcStats& s = krc.stats();
  EXPECT_GT(s.inj_cmd_lost, 5u);
  EXPECT_GE(s.missed, s.inj_cmd_lost);  // (a reply later than the timeout on a loaded machine adds a miss)
  // The KRC reflects the last command it took; the bridge steps on from that
  // one, so the applied commands never jump (below).
  EXPECT_GE(bridge.stats().rewinds, s.inj_cmd_lost);
  EXPECT_GT(s.remote_seq_errors, 0u);
  EXPECT_LE(s.remote_seq_errors, s.inj_cmd_lost);
  EXPECT_LE(s.max_cmd_step_m, bp.max_lin_speed * 0.001 + kPosTol);
}

TEST(FriUdp, StatusesForTimeoutTruncationPeerAndBind) {
  UdpSocket a;
  UdpParams up;
  up.bind_address = "127.0.0.1";
  up.port = 0;
  ASSERT_TRUE(a.open(up).ok());
  ASSERT_NE(a.localPort(), 0);
  uint8_t buf[64];
  std::size_t n = 99;
  const double t0 = steadyNow();
  EXPECT_EQ(a.receive(buf, sizeof buf, n, 20000), UdpStatus::Timeout);
  const double waited = steadyNow() - t0;
  EXPECT_GE(waited, 0.015);  // bounded wait: ~20 ms (lower bound with scheduling slack)
  EXPECT_LT(waited, 1.0);
  EXPECT_EQ(n, 0u);
  EXPECT_EQ(a.reply(buf, 4), UdpStatus::NoPeer);
  // oversize datagram: Truncated with its real size
  UdpSocket b;
  ASSERT_TRUE(b.open(up).ok());
  std::vector<uint8_t> big(1000, 0x5A);
  ASSERT_EQ(b.sendTo(loopbackAddress(a.localPort()), big.data(), big.size()), UdpStatus::Ok);
  EXPECT_EQ(a.receive(buf, sizeof buf, n, 1000000), UdpStatus::Truncated);
  EXPECT_EQ(n, 1000u);
  // reply goes back to b
  ASSERT_EQ(a.reply(buf, 8), UdpStatus::Ok);
  EXPECT_EQ(b.receive(buf, sizeof buf, n, 1000000), UdpStatus::Ok);
  EXPECT_EQ(n, 8u);
  // errors name the parameter
  UdpSocket c;
  UdpParams clash = up;
  clash.port = a.localPort();
  ConfigResult r = c.open(clash);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.message().find("bind(127.0.0.1:"), std::string::npos) << r.message();
  UdpParams bad = up;
  bad.bind_address = "localhost:1";
  r = c.open(bad);
  EXPECT_NE(r.message().find("fri.udp.bind_address"), std::string::npos) << r.message();
  EXPECT_EQ(c.receive(buf, sizeof buf, n, 0), UdpStatus::NotOpen);
}

TEST(FriUdp, NoHeapAllocationPerCycleOverTheSocket) {
  // One thread plays both sides so that the scope counts exactly one cycle's
  // work: send measurement, receive, bridge step, encode, reply, receive reply.
  UdpParams up;
  up.bind_address = "127.0.0.1";
  up.port = 0;
  UdpSocket remote, krc;
  ASSERT_TRUE(remote.open(up).ok());
  ASSERT_TRUE(krc.open(up).ok());
  FriBridge bridge;
  ASSERT_TRUE(bridge.configure(BridgeParams{}).ok());
  std::vector<std::vector<uint8_t>> packets;
  for (int i = 0; i < 500; ++i)
    packets.push_back(makeMsr(static_cast<uint16_t>(i + 1), i < 100 ? State::Mon : State::Cmd, Quality::Perfect,
                              startPose()));
  const sockaddr_in to = loopbackAddress(remote.localPort());
  PoseCommand desired;
  desired.status = ServoStatus::Ok;
  toPose(KDL::Frame(startPose().M, startPose().p + KDL::Vector(0.01, 0, 0)), desired.pose);
  BridgeOutput out;
  uint8_t rx[2048], tx[kCmdPacketSize];
  std::size_t got_replies = 0;
  tactile::test::AllocationScope scope;
  for (const auto& p : packets) {
    std::size_t n = 0;
    krc.sendTo(to, p.data(), p.size());
    if (remote.receive(rx, sizeof rx, n, 1000000) != UdpStatus::Ok) continue;
    bridge.stepDatagram(rx, n, desired, 0.0, out);
    if (!out.reply) continue;
    std::size_t w = 0;
    encodeCommand(out.cmd, tx, sizeof tx, w);
    remote.reply(tx, w);
    if (krc.receive(rx, sizeof rx, n, 1000000) == UdpStatus::Ok && n == kCmdPacketSize) ++got_replies;
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_EQ(got_replies, packets.size());
}

// The helpers an event loop (the RTT component's FileDescriptorActivity) uses:
// fd() to wait on, receive(..., 0) that never waits, discardPending() that
// drops a backlog without waiting.
TEST(FriUdp, FdForAnEventLoopZeroTimeoutReceiveAndDiscardPending) {
  UdpSocket a, b;
  EXPECT_EQ(a.fd(), -1);
  EXPECT_EQ(a.discardPending(), 0u);  // closed: nothing, no error
  UdpParams up;
  up.bind_address = "127.0.0.1";
  up.port = 0;
  ASSERT_TRUE(a.open(up).ok());
  ASSERT_TRUE(b.open(up).ok());
  ASSERT_GE(a.fd(), 0);
  uint8_t buf[64];
  std::size_t n = 0;
  // Nothing queued: a zero timeout returns at once, and the fd is not readable.
  const double t0 = steadyNow();
  EXPECT_EQ(a.receive(buf, sizeof buf, n, 0), UdpStatus::Timeout);
  EXPECT_LT(steadyNow() - t0, 0.005);
  pollfd pfd{a.fd(), POLLIN, 0};
  EXPECT_EQ(::poll(&pfd, 1, 0), 0);
  // Three datagrams queued: the fd is readable; receive(0) takes exactly one.
  const sockaddr_in to = loopbackAddress(a.localPort());
  for (uint8_t i = 1; i <= 3; ++i) {
    const uint8_t d[4] = {i, i, i, i};
    ASSERT_EQ(b.sendTo(to, d, sizeof d), UdpStatus::Ok);
  }
  pfd.revents = 0;
  EXPECT_EQ(::poll(&pfd, 1, 1000), 1);
  EXPECT_TRUE(pfd.revents & POLLIN);
  ASSERT_EQ(a.receive(buf, sizeof buf, n, 0), UdpStatus::Ok);
  EXPECT_EQ(n, 4u);
  EXPECT_EQ(buf[0], 1);
  // discardPending drops the other two, without waiting, and keeps the peer.
  EXPECT_EQ(a.discardPending(), 2u);
  EXPECT_EQ(a.receive(buf, sizeof buf, n, 0), UdpStatus::Timeout);
  pfd.revents = 0;
  EXPECT_EQ(::poll(&pfd, 1, 0), 0);
  ASSERT_EQ(a.reply(buf, 4), UdpStatus::Ok);
  EXPECT_EQ(b.receive(buf, sizeof buf, n, 1000000), UdpStatus::Ok);
  // bounded by `max`
  for (uint8_t i = 0; i < 5; ++i) ASSERT_EQ(b.sendTo(to, buf, 4), UdpStatus::Ok);
  EXPECT_EQ(::poll(&pfd, 1, 1000), 1);
  EXPECT_EQ(a.discardPending(2), 2u);
  EXPECT_EQ(a.discardPending(), 3u);
  a.close();
  EXPECT_EQ(a.fd(), -1);
}

// The latency record of the simulated KRC (scripts/realtime/rt_latency.sh): a reply
// that misses its cycle is ignored by the KRC (stale, the cycle counts as
// missed), but its true latency is entered in its cycle's sample, marked not
// on time; a measurement never answered stays NaN. Single-threaded: the KRC
// polls without waiting, the remote answers in between.
TEST(FriLoopback, LatencyLogRecordsLateRepliesWithTheirTrueLatency) {
  BridgeParams bp;
  FriBridge bridge;
  ASSERT_TRUE(bridge.configure(bp).ok());
  UdpSocket remote;
  UdpParams up;
  up.bind_address = "127.0.0.1";
  up.port = 0;
  ASSERT_TRUE(remote.open(up).ok());
  SimKrcParams p = fastKrc(remote.localPort());
  p.reply_timeout_s = 0.0;  // poll once: every reply comes after its cycle
  FirstOrderPlant plant;
  SimKrc krc;
  ASSERT_TRUE(krc.configure(p, plant).ok());
  std::vector<SimKrc::LatencySample> log;
  log.reserve(8);
  krc.setLatencyLog(&log);

  const double t_before = steadyNow();
  krc.runCycle();  // measurement 1, no reply yet
  ASSERT_EQ(log.size(), 1u);
  EXPECT_TRUE(std::isnan(log[0].latency_s));
  EXPECT_FALSE(log[0].on_time);

  std::array<uint8_t, 2048> buf{};
  std::size_t n = 0;
  ASSERT_EQ(remote.receive(buf.data(), buf.size(), n, 500000), UdpStatus::Ok);
  PoseCommand desired;
  desired.status = ServoStatus::Ok;
  toPose(startPose(), desired.pose);
  BridgeOutput out;
  bridge.stepDatagram(buf.data(), n, desired, steadyNow(), out);
  ASSERT_TRUE(out.reply);
  uint8_t tx[kCmdPacketSize];
  std::size_t w = 0;
  ASSERT_EQ(encodeCommand(out.cmd, tx, sizeof tx, w), PacketStatus::Ok);
  ASSERT_EQ(remote.reply(tx, w), UdpStatus::Ok);

  krc.runCycle();  // measurement 2; the late reply to 1 arrives now
  const double t_after = steadyNow();
  ASSERT_EQ(log.size(), 2u);
  EXPECT_EQ(krc.stats().stale_replies, 1u);
  EXPECT_EQ(krc.stats().missed, 2u);
  EXPECT_FALSE(log[0].on_time);
  ASSERT_FALSE(std::isnan(log[0].latency_s)) << "the late reply's latency was not recorded";
  EXPECT_GT(log[0].latency_s, 0.0);
  EXPECT_LE(log[0].latency_s, t_after - t_before);  // it happened inside this window
  EXPECT_TRUE(std::isnan(log[1].latency_s));        // measurement 2 was never answered

  krc.runCycle();  // still no reply to 2: its sample stays NaN
  EXPECT_TRUE(std::isnan(log[1].latency_s));
  EXPECT_EQ(log.size(), 3u);
}

// A 2 ms KRC (friOpen(2)) with its two rules on, over UDP against the real
// bridge: the link rated from the answers (a burst of 15 measurements lost,
// 15 % of the 100-cycle window: BAD, command mode left and entered again at
// PERFECT, the bridge holding, then following with 2 ms steps), then a press
// beyond $STIFFNESS.MAXFORCE: the KRC brakes the drives and leaves command
// mode, the bridge names it krc_fault.
TEST(FriLoopback, TwoMillisecondKrcRatesTheLinkAndStopsAPressBeyondMaxForce) {
  constexpr double kCycle = 0.002;
  BridgeParams bp;
  bp.cycle_time_s = kCycle;
  bp.max_lin_speed = 0.05;
  const KDL::Frame target(startPose().M, startPose().p + KDL::Vector(0.01, 0.0, 0.0));
  BridgeLoop bridge(bp, target);
  SimKrcParams kp = fastKrc(bridge.port());
  kp.period_s = kCycle;
  kp.initial.state = State::Cmd;  // the script's friStart at once: entered at PERFECT
  kp.quality_rule.enabled = true;
  kp.limits.max_force = {20.0, 20.0, 20.0, 2.0, 2.0, 2.0};
  kp.limits.cp_max_delta = {0.015, 0.015, 0.015, 0.087, 0.087, 0.087};
  kp.faults.burst_start = 200;
  kp.faults.burst_length = 15;
  FirstOrderPlant plant(0.02);
  SimKrc krc;
  ASSERT_TRUE(krc.configure(kp, plant).ok());
  bridge.start();
  krc.run(600);
  const SimKrcStats& s = krc.stats();
  EXPECT_EQ(s.quality_drops, 1u) << "the burst: BAD, command mode left once";
  EXPECT_EQ(s.answers_missed, 15u) << "the burst's, no other";
  EXPECT_EQ(s.inj_lost, 15u);
  EXPECT_EQ(krc.state(), State::Cmd) << "entered again at PERFECT";
  EXPECT_EQ(krc.quality(), Quality::Perfect);
  EXPECT_EQ(krc.fault(), KrcFault::None);
  EXPECT_LE(s.max_cmd_step_m, bp.max_lin_speed * kCycle + kPosTol) << "one limited step per 2 ms packet";
  EXPECT_GT(s.max_cmd_step_m, bp.max_lin_speed * 0.001 + kPosTol) << "the bridge steps by the KRC's 2 ms";
  EXPECT_LE(s.max_entry_offset_m, bp.max_lin_speed * kCycle + kPosTol) << "no jump at either entry";
  EXPECT_EQ(s.mon_echo_errors, 0u);
  EXPECT_LT((krc.plantState().pose.p - target.p).Norm(), 1e-4) << "the target reached after the resume";
  plant.setWrench({0.0, 0.0, -25.0, 0.0, 0.0, 0.0});  // a press beyond MAXFORCE Z
  krc.run(50);
  bridge.stop();
  EXPECT_EQ(krc.fault(), KrcFault::MaxForce);
  EXPECT_EQ(krc.state(), State::Mon);
  EXPECT_EQ(krc.power(), 0u);
  EXPECT_EQ(krc.stats().faults, 1u);
  EXPECT_GT(bridge.seen(BridgeStatus::KrcFault), 40u) << "named at each packet after the stop";
  EXPECT_GT(bridge.seen(BridgeStatus::LeftCmd), 50u) << "the quality drop: held and reported";
  EXPECT_EQ(krc.stats().mon_echo_errors, 0u);
}
