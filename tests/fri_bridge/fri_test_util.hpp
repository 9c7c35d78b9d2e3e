// Helpers shared by the FRI tests: build measurement packets without going
// through the structs, so that the byte layout is checked independently.
#pragma once

#include <cstdint>
#include <cstring>
#include <vector>

#include <kdl/frames.hpp>

#include "tactile_fri/protocol.hpp"

namespace fri_test {

using namespace tactile::fri;

inline void putU16(std::vector<uint8_t>& b, std::size_t off, uint16_t v) {
  b[off] = static_cast<uint8_t>(v & 0xFF);
  b[off + 1] = static_cast<uint8_t>(v >> 8);
}
inline void putU32(std::vector<uint8_t>& b, std::size_t off, uint32_t v) {
  for (int i = 0; i < 4; ++i) b[off + std::size_t(i)] = static_cast<uint8_t>((v >> (8 * i)) & 0xFF);
}
inline void putF32(std::vector<uint8_t>& b, std::size_t off, float f) {
  uint32_t v;
  std::memcpy(&v, &f, 4);
  putU32(b, off, v);
}
inline uint16_t getU16(const uint8_t* b, std::size_t off) { return uint16_t(b[off] | (b[off + 1] << 8)); }
inline uint32_t getU32(const uint8_t* b, std::size_t off) {
  return uint32_t(b[off]) | (uint32_t(b[off + 1]) << 8) | (uint32_t(b[off + 2]) << 16) | (uint32_t(b[off + 3]) << 24);
}
inline float getF32(const uint8_t* b, std::size_t off) {
  const uint32_t v = getU32(b, off);
  float f;
  std::memcpy(&f, &v, 4);
  return f;
}

// Byte offsets written out by hand from the protocol description (not from offsetof).
constexpr std::size_t kOffState = 8 + 132 + 4;          // 144
constexpr std::size_t kOffQuality = kOffState + 2;       // 146
constexpr std::size_t kOffCmdSampleTime = 8 + 132 + 12;  // 152
constexpr std::size_t kOffPower = 8 + 132 + 40;          // 180
constexpr std::size_t kOffControl = kOffPower + 2;       // 182
constexpr std::size_t kOffMsrJnt = 8 + 132 + 40 + 36;    // 216
constexpr std::size_t kOffMsrCart = kOffMsrJnt + 28;     // 244
constexpr std::size_t kOffExtFT = kOffMsrJnt + 284;      // 500
constexpr std::size_t kOffGravity = kOffMsrJnt + 672;    // 888
constexpr std::size_t kOffCmdFlags = 8 + 132;            // 140 (command packet)
constexpr std::size_t kOffCmdCart = kOffCmdFlags + 4 + 28;  // 172

/// A well-formed measurement datagram.
inline std::vector<uint8_t> makeMsr(uint16_t seq, State st, Quality q, const KDL::Frame& pose, uint16_t power = 0x7F,
                                    float cmd_T = 0.001f) {
  std::vector<uint8_t> b(kMsrPacketSize, 0);
  putU16(b, 0, seq);
  putU16(b, 2, 0);
  putU16(b, 4, 916);
  putU16(b, 6, 0x2006);
  putU16(b, kOffState, static_cast<uint16_t>(st));
  putU16(b, kOffQuality, static_cast<uint16_t>(q));
  putF32(b, kOffCmdSampleTime - 4, cmd_T);
  putF32(b, kOffCmdSampleTime, cmd_T);
  putU16(b, kOffPower, power);
  putU16(b, kOffControl, 2);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) putF32(b, kOffMsrCart + 4 * std::size_t(4 * r + c), float(pose.M(r, c)));
    putF32(b, kOffMsrCart + 4 * std::size_t(4 * r + 3), float(pose.p(r)));
  }
  return b;
}

inline KDL::Frame cmdPose(const uint8_t* cmd) {
  float m[kCartFrameDim];
  for (int i = 0; i < kCartFrameDim; ++i) m[i] = getF32(cmd, kOffCmdCart + 4 * std::size_t(i));
  KDL::Frame f;
  toFrame(m, f);
  return f;
}

inline KDL::Frame startPose() {
  return KDL::Frame(KDL::Rotation::RPY(3.0, 0.1, -0.4), KDL::Vector(0.5, -0.1, 0.4));
}

}  // namespace fri_test
