// libFuzzer target: the frame decoder fed directly with arbitrary payloads
// (id from the first byte), bypassing the CRC, so the decoder's own bounds and
// RLE checks are exercised on every input. Also checks the encode/decode
// round trip of packets built from the input.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "tactile_wts/protocol.hpp"

using namespace tactile::wts;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static FrameDecoder dec;
  static bool init = false;
  if (!init) {
    dec.configure(CellMapParams{});
    init = true;
  }
  if (size < 1) return 0;
  PacketView pkt;
  pkt.id = (data[0] & 1) ? 0x20 : 0x00;
  pkt.payload = data + 1;
  pkt.size = static_cast<uint16_t>(size - 1 > 0xFFFF ? 0xFFFF : size - 1);
  tactile::RawTactileFrame out;
  const FrameStatus fs = dec.decode(pkt, out);
  if (fs == FrameStatus::Ok)
    for (int i = 0; i < out.rows * out.cols; ++i)
      if (out.counts[static_cast<std::size_t>(i)] > kFullScale) abort();
  // round trip: any payload that fits must come back byte-identical
  static uint8_t buf[kMaxPacket];
  const std::size_t len = encodePacket(data[0], data + 1, size - 1, buf, sizeof(buf));
  if (size - 1 <= kMaxPayload) {
    if (len != size - 1 + kOverhead) abort();
    Parser p;
    p.feed(buf, len);
    PacketView v;
    if (p.next(v) != ParseStatus::Packet || v.id != data[0] || v.size != size - 1 ||
        (v.size && std::memcmp(v.payload, data + 1, v.size) != 0))
      abort();
  } else if (len != 0) {
    abort();
  }
  return 0;
}
