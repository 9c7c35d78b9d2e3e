// Helpers shared by the WTS tests and the benchmark: frame packets built from
// {s}-layout counts with the protocol's own encoder and a device cell map.
#pragma once

#include <fcntl.h>
#include <stdlib.h>

#include <cstdint>
#include <string>
#include <vector>

#include "tactile_wts/protocol.hpp"

namespace wtstest {

using namespace tactile::wts;

/// A bare pseudo-terminal driven from the test thread itself (no simulator
/// thread whose allocations would count): returns the non-blocking master fd
/// (-1 on failure) and the slave's path in `slave`.
inline int openBarePty(std::string& slave) {
  const int m = posix_openpt(O_RDWR | O_NOCTTY);
  if (m < 0) return -1;
  char name[128];
  if (grantpt(m) != 0 || unlockpt(m) != 0 || ptsname_r(m, name, sizeof(name)) != 0) return -1;
  fcntl(m, F_SETFL, fcntl(m, F_GETFL) | O_NONBLOCK);
  slave = name;
  return m;
}

/// Full packet for a frame: id 0x00 (periodic) or 0x20 (single-frame reply,
/// with a status code). `s_counts` in {s} row-major order.
inline std::vector<uint8_t> framePacket(const CellMap& map, const uint16_t* s_counts, uint32_t t_ms, bool rle,
                                        uint8_t id = 0x00, StatusCode status = StatusCode::Success) {
  const int n = map.cells();
  std::vector<uint16_t> dev(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) dev[static_cast<std::size_t>(k)] = s_counts[map.toSensing(k)];
  std::vector<uint8_t> payload(2 + 5 + 2 * static_cast<std::size_t>(n));
  std::size_t off = 0;
  if (id == 0x20) {
    putU16(payload.data(), static_cast<uint16_t>(status));
    off = 2;
  }
  putU32(payload.data() + off, t_ms);
  payload[off + 4] = rle ? kFlagRle : 0;
  off += 5;
  off += encodeCells(dev.data(), n, rle, payload.data() + off, payload.size() - off);
  std::vector<uint8_t> pkt(off + kOverhead);
  pkt.resize(encodePacket(id, payload.data(), off, pkt.data(), pkt.size()));
  return pkt;
}

/// A contact-like frame: a pressed blob around (r0, c0), zeros elsewhere.
inline void blobFrame(int rows, int cols, int r0, int c0, uint16_t* out) {
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const int d2 = (r - r0) * (r - r0) + (c - c0) * (c - c0);
      out[r * cols + c] = d2 > 4 ? 0 : static_cast<uint16_t>(3000 / (1 + d2));
    }
}

}  // namespace wtstest
