// libFuzzer target: arbitrary bytes, in arbitrary chunks, through the WTS
// parser and every CRC-valid packet through the frame decoder (plain and RLE,
// both cell orders) and the matrix-info decoder. Any crash, sanitizer report or
// broken invariant (abort) is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "tactile_wts/protocol.hpp"

using namespace tactile::wts;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static FrameDecoder dec[2];
  static bool init = false;
  if (!init) {
    CellMapParams p;
    dec[0].configure(p);
    p.transpose = false;
    p.flip_rows = true;
    dec[1].configure(p);
    init = true;
  }
  // first byte: bits 0..5 pick the chunk size (split points), bit 6 the
  // direction filter, bit 7 the filter's frame size (6x14 or kMaxTaxels)
  const int max_cells = size && (data[0] & 0x80) ? 84 : tactile::kMaxTaxels;
  Parser parser(size && (data[0] & 0x40) ? Direction::FromDevice : Direction::Any, max_cells);
  tactile::RawTactileFrame out;
  const std::size_t chunk = size ? (data[0] % 64) + 1 : 1;
  std::size_t off = size ? 1 : 0;
  while (off < size) {
    const std::size_t n = size - off < chunk ? size - off : chunk;
    std::size_t taken = 0;
    while (taken < n) {
      taken += parser.feed(data + off + taken, n - taken);
      PacketView pkt;
      ParseStatus st;
      int guard = 0;
      while ((st = parser.next(pkt)) != ParseStatus::NeedMore) {
        if (++guard > 1 << 20) abort();  // next() must always make progress
        if (st == ParseStatus::Packet) {
          if (pkt.size > kMaxPayload) abort();
          if ((data[0] & 0x40) && !plausibleHeader(Direction::FromDevice, pkt.id, pkt.size, max_cells)) abort();
          for (auto& d : dec) {
            const FrameStatus fs = d.decode(pkt, out);
            if (fs == FrameStatus::Ok) {
              for (int i = 0; i < out.rows * out.cols; ++i)
                if (out.counts[static_cast<std::size_t>(i)] > kFullScale) abort();
            }
          }
          MatrixInfo mi;
          decodeMatrixInfo(pkt, mi);
          StatusCode sc;
          if (pkt.status(sc)) (void)toString(sc);
        }
      }
    }
    off += n;
  }
  if (parser.buffered() > 2 * kMaxPacket) abort();
  return 0;
}
