// libFuzzer target: the FRI decoders and the bridge core on arbitrary bytes.
//
// Input layout: [flags u8] [desired pose: 7 little-endian doubles, if flags & 1]
// then up to 16 datagrams, each [length u16 LE][bytes], fed in order to a fresh
// FriBridge (so every input is reproducible on its own). Invariants, checked
// with __builtin_trap so that any violation is a finding:
//   * every status is a value of its enum;
//   * a malformed datagram never produces a reply;
//   * every reply is a well-formed 376-byte command whose Cartesian pose is
//     finite and a proper rotation, whose reflSeqCount is the measurement's
//     sendSeqCount, and whose sendSeqCount increases by exactly one.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "tactile_fri/bridge.hpp"
#include "tactile_fri/protocol.hpp"

using namespace tactile;
using namespace tactile::fri;

#define FUZZ_CHECK(cond) \
  do {                   \
    if (!(cond)) __builtin_trap(); \
  } while (0)

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const uint8_t fl = data[0];
  std::size_t off = 1;
  PoseCommand desired;
  desired.status = ServoStatus::Ok;
  desired.pose.p = {0.5, 0.0, 0.4};
  desired.pose.q = {1.0, 0.0, 0.0, 0.0};
  if ((fl & 1) && size >= off + 56) {
    double v[7];
    std::memcpy(v, data + off, sizeof v);
    off += sizeof v;
    desired.pose.p = {v[0], v[1], v[2]};
    desired.pose.q = {v[3], v[4], v[5], v[6]};
  }
  if (fl & 2) desired.status = ServoStatus::NotConfigured;

  // Decoders alone on the whole remaining input.
  MsrPacket m;
  CmdPacket c;
  const PacketStatus s1 = decodeMeasurement(data + off, size - off, m);
  const PacketStatus s2 = decodeCommand(data + off, size - off, c);
  FUZZ_CHECK(static_cast<int>(s1) <= static_cast<int>(PacketStatus::BufferTooSmall));
  FUZZ_CHECK(static_cast<int>(s2) <= static_cast<int>(PacketStatus::BufferTooSmall));

  static FriBridge* bridge = nullptr;
  if (bridge == nullptr) bridge = new FriBridge();  // once per process
  BridgeParams bp;
  bp.command_impedance = (fl & 4) != 0;
  FUZZ_CHECK(bridge->configure(bp).ok());  // also resets the bridge: fresh per input
  BridgeOutput out;
  uint16_t last_sent = 0;
  bool sent_any = false;
  double now = 0.0;
  for (int k = 0; k < 16 && off + 2 <= size; ++k) {
    uint16_t len;
    std::memcpy(&len, data + off, 2);
    off += 2;
    const std::size_t n = len < size - off ? len : size - off;
    const uint8_t* dg = data + off;
    off += n;
    now += 0.001;
    desired.time_s = (fl & 8) ? now - 1.0 : now;
    const PacketStatus ps = decodeMeasurement(dg, n, m);
    const BridgeStatus bs = bridge->stepDatagram(dg, n, desired, now, out);
    FUZZ_CHECK(static_cast<int>(bs) <= static_cast<int>(BridgeStatus::NotConfigured));
    FUZZ_CHECK(out.packet_status == ps);
    if (ps != PacketStatus::Ok) FUZZ_CHECK(!out.reply && bs == BridgeStatus::Malformed);
    if (out.reply) {
      FUZZ_CHECK(producesReply(bs));
      FUZZ_CHECK(validFriPose(out.cmd.cmd.cart_pos));
      FUZZ_CHECK(out.cmd.head.refl_seq == m.head.send_seq);
      if (sent_any) FUZZ_CHECK(static_cast<uint16_t>(last_sent + 1) == out.cmd.head.send_seq);
      last_sent = out.cmd.head.send_seq;
      sent_any = true;
      uint8_t wire[kCmdPacketSize];
      std::size_t w = 0;
      FUZZ_CHECK(encodeCommand(out.cmd, wire, sizeof wire, w) == PacketStatus::Ok && w == kCmdPacketSize);
      FUZZ_CHECK(decodeCommand(wire, w, c) == PacketStatus::Ok);
    } else {
      FUZZ_CHECK(static_cast<int>(bs) >= 8);  // only MeasurementInvalid and the drop statuses have no reply
    }
  }
  return 0;
}
