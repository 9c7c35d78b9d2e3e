// bench_fri: per-packet cost of the FRI protocol core and bridge.
//
//   BM_DecodeMeasurement       checked memcpy decode of a 916-byte packet (the library)
//   BM_DecodeFieldByField      alternative: explicit little-endian field-by-field
//                              deserialisation of the same packet (the usual portable way)
//   BM_EncodeCommand           376-byte command packet
//   BM_BridgeStepDatagram      decode + sequence/state logic + rate limiter + reply
//   BM_UdpRoundTrip            one full cycle over loopback sockets (send, receive,
//                              bridge step, reply, receive), for scale against 1 ms
// Every benchmark reports allocs_per_iter (counting operator new): it must be 0.
#include <benchmark/benchmark.h>

#include <cstring>
#include <vector>

#include "alloc_counter.hpp"
#include "fri_test_util.hpp"
#include "tactile_fri/bridge.hpp"
#include "tactile_fri/udp.hpp"

using namespace tactile;
using namespace tactile::fri;
using namespace fri_test;

namespace {

std::vector<uint8_t> samplePacket() {
  std::vector<uint8_t> b = makeMsr(42, State::Cmd, Quality::Perfect, startPose());
  for (std::size_t i = kOffMsrJnt; i + 4 <= kMsrPacketSize; i += 4) {
    if (i >= kOffMsrCart && i < kOffMsrCart + 48) continue;
    putF32(b, i, 0.001f * float(i));
  }
  return b;
}

// ---- alternative decoder: explicit field-by-field little-endian reads ----
struct Reader {
  const uint8_t* p;
  std::size_t off = 0;
  uint16_t u16() {
    const uint16_t v = uint16_t(p[off] | (p[off + 1] << 8));
    off += 2;
    return v;
  }
  uint32_t u32() {
    const uint32_t v = uint32_t(p[off]) | (uint32_t(p[off + 1]) << 8) | (uint32_t(p[off + 2]) << 16) |
                       (uint32_t(p[off + 3]) << 24);
    off += 4;
    return v;
  }
  float f32() {
    const uint32_t v = u32();
    float f;
    std::memcpy(&f, &v, 4);
    return f;
  }
  template <std::size_t N>
  void floats(float (&a)[N]) {
    for (auto& x : a) x = f32();
  }
};

PacketStatus decodeFieldByField(const uint8_t* data, std::size_t size, MsrPacket& m) {
  if (data == nullptr) return PacketStatus::NullBuffer;
  if (size != kMsrPacketSize) return size < kMsrPacketSize ? PacketStatus::TooShort : PacketStatus::TooLong;
  Reader r{data};
  m.head.send_seq = r.u16();
  m.head.refl_seq = r.u16();
  m.head.packet_size = r.u16();
  m.head.datagram_id = r.u16();
  if (m.head.packet_size != kMsrPacketSize) return PacketStatus::SizeFieldMismatch;
  if (m.head.datagram_id != kDatagramIdMsr) return PacketStatus::WrongDatagramId;
  r.floats(m.krl.real_data);
  for (auto& x : m.krl.int_data) x = static_cast<int32_t>(r.u32());
  m.krl.bool_data = r.u16();
  m.krl.fill = r.u16();
  m.intf.timestamp = r.u32();
  m.intf.state = r.u16();
  m.intf.quality = r.u16();
  m.intf.desired_msr_sample_time = r.f32();
  m.intf.desired_cmd_sample_time = r.f32();
  m.intf.safety_limits = r.f32();
  m.intf.stat.answer_rate = r.f32();
  m.intf.stat.latency = r.f32();
  m.intf.stat.jitter = r.f32();
  m.intf.stat.miss_rate = r.f32();
  m.intf.stat.miss_counter = r.u32();
  if (m.intf.state > 2) return PacketStatus::BadState;
  if (m.intf.quality > 3) return PacketStatus::BadQuality;
  m.robot.power = r.u16();
  m.robot.control = r.u16();
  m.robot.error = r.u16();
  m.robot.warning = r.u16();
  r.floats(m.robot.temperature);
  RobotData& d = m.data;
  r.floats(d.msr_jnt_pos);
  r.floats(d.msr_cart_pos);
  r.floats(d.cmd_jnt_pos);
  r.floats(d.cmd_jnt_pos_fri_offset);
  r.floats(d.cmd_cart_pos);
  r.floats(d.cmd_cart_pos_fri_offset);
  r.floats(d.msr_jnt_trq);
  r.floats(d.est_ext_jnt_trq);
  r.floats(d.est_ext_tcp_ft);
  r.floats(d.jacobian);
  r.floats(d.mass_matrix);
  r.floats(d.gravity);
  return r.off == kMsrPacketSize ? PacketStatus::Ok : PacketStatus::TooLong;
}

void reportAllocs(benchmark::State& state, std::size_t allocs) {
  state.counters["allocs_per_iter"] =
      benchmark::Counter(static_cast<double>(allocs) / static_cast<double>(state.iterations()));
}

void BM_DecodeMeasurement(benchmark::State& state) {
  const std::vector<uint8_t> b = samplePacket();
  MsrPacket m;
  tactile::test::AllocationScope scope;
  for (auto _ : state) {
    benchmark::DoNotOptimize(decodeMeasurement(b.data(), b.size(), m));
    benchmark::ClobberMemory();
  }
  reportAllocs(state, scope.count());
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * kMsrPacketSize));
}
BENCHMARK(BM_DecodeMeasurement);

void BM_DecodeFieldByField(benchmark::State& state) {
  const std::vector<uint8_t> b = samplePacket();
  MsrPacket m, ref;
  if (decodeFieldByField(b.data(), b.size(), m) != PacketStatus::Ok ||
      decodeMeasurement(b.data(), b.size(), ref) != PacketStatus::Ok || std::memcmp(&m, &ref, sizeof m) != 0) {
    state.SkipWithError("the two decoders disagree");
    return;
  }
  tactile::test::AllocationScope scope;
  for (auto _ : state) {
    benchmark::DoNotOptimize(decodeFieldByField(b.data(), b.size(), m));
    benchmark::ClobberMemory();
  }
  reportAllocs(state, scope.count());
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * kMsrPacketSize));
}
BENCHMARK(BM_DecodeFieldByField);

void BM_EncodeCommand(benchmark::State& state) {
  CmdPacket c{};
  fromFrame(startPose(), c.cmd.cart_pos);
  uint8_t buf[kCmdPacketSize];
  std::size_t n = 0;
  tactile::test::AllocationScope scope;
  for (auto _ : state) {
    ++c.head.send_seq;
    benchmark::DoNotOptimize(encodeCommand(c, buf, sizeof buf, n));
    benchmark::ClobberMemory();
  }
  reportAllocs(state, scope.count());
}
BENCHMARK(BM_EncodeCommand);

void BM_BridgeStepDatagram(benchmark::State& state) {
  std::vector<uint8_t> b = samplePacket();
  FriBridge bridge;
  if (!bridge.configure(BridgeParams{}).ok()) {
    state.SkipWithError("configure failed");
    return;
  }
  PoseCommand desired;
  desired.status = ServoStatus::Ok;
  // a target that keeps the rate limiter busy (translation and rotation)
  toPose(KDL::Frame(KDL::Rotation::RotZ(1.0) * startPose().M, startPose().p + KDL::Vector(10.0, 0, 0)), desired.pose);
  BridgeOutput out;
  uint8_t tx[kCmdPacketSize];
  uint16_t seq = 1;
  tactile::test::AllocationScope scope;
  for (auto _ : state) {
    putU16(b, 0, ++seq);
    putU16(b, 2, out.cmd.head.send_seq);
    bridge.stepDatagram(b.data(), b.size(), desired, 0.0, out);
    std::size_t n = 0;
    encodeCommand(out.cmd, tx, sizeof tx, n);
    benchmark::DoNotOptimize(tx);
  }
  reportAllocs(state, scope.count());
  if (bridge.stats().replies != bridge.stats().received) state.SkipWithError("a packet was not answered");
}
BENCHMARK(BM_BridgeStepDatagram);

void BM_UdpRoundTrip(benchmark::State& state) {
  UdpParams up;
  up.bind_address = "127.0.0.1";
  up.port = 0;
  UdpSocket remote, krc;
  if (!remote.open(up).ok() || !krc.open(up).ok()) {
    state.SkipWithError("socket");
    return;
  }
  std::vector<uint8_t> b = samplePacket();
  FriBridge bridge;
  bridge.configure(BridgeParams{});
  PoseCommand desired;
  desired.status = ServoStatus::Ok;
  toPose(startPose(), desired.pose);
  BridgeOutput out;
  uint8_t rx[2048], tx[kCmdPacketSize];
  const sockaddr_in to = loopbackAddress(remote.localPort());
  uint16_t seq = 1;
  tactile::test::AllocationScope scope;
  for (auto _ : state) {
    putU16(b, 0, ++seq);
    std::size_t n = 0;
    krc.sendTo(to, b.data(), b.size());
    remote.receive(rx, sizeof rx, n, 1000000);
    bridge.stepDatagram(rx, n, desired, 0.0, out);
    encodeCommand(out.cmd, tx, sizeof tx, n);
    remote.reply(tx, n);
    krc.receive(rx, sizeof rx, n, 1000000);
  }
  reportAllocs(state, scope.count());
}
BENCHMARK(BM_UdpRoundTrip);

}  // namespace

BENCHMARK_MAIN();
