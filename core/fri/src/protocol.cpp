#include "tactile_fri/protocol.hpp"

#include <cmath>
#include <cstring>
#include <type_traits>

namespace tactile {
namespace fri {

static_assert(std::is_trivially_copyable<MsrPacket>::value, "memcpy decoding needs a trivially copyable type");
static_assert(std::is_trivially_copyable<CmdPacket>::value, "memcpy decoding needs a trivially copyable type");

const char* toString(PacketStatus s) {
  switch (s) {
    case PacketStatus::Ok: return "ok";
    case PacketStatus::NullBuffer: return "null_buffer";
    case PacketStatus::TooShort: return "too_short";
    case PacketStatus::TooLong: return "too_long";
    case PacketStatus::SizeFieldMismatch: return "size_field_mismatch";
    case PacketStatus::WrongDatagramId: return "wrong_datagram_id";
    case PacketStatus::BadState: return "bad_state";
    case PacketStatus::BadQuality: return "bad_quality";
    case PacketStatus::BufferTooSmall: return "buffer_too_small";
  }
  return "unknown";
}

const char* toString(State s) {
  switch (s) {
    case State::Off: return "OFF";
    case State::Mon: return "MON";
    case State::Cmd: return "CMD";
  }
  return "INVALID";
}

const char* toString(Quality q) {
  switch (q) {
    case Quality::Unacceptable: return "UNACCEPTABLE";
    case Quality::Bad: return "BAD";
    case Quality::Ok: return "OK";
    case Quality::Perfect: return "PERFECT";
  }
  return "INVALID";
}

bool parseState(const char* word, State& out) {
  for (State s : {State::Off, State::Mon, State::Cmd})
    if (std::strcmp(word, toString(s)) == 0) return out = s, true;
  return false;
}

bool parseQuality(const char* word, Quality& out) {
  for (Quality q : {Quality::Unacceptable, Quality::Bad, Quality::Ok, Quality::Perfect})
    if (std::strcmp(word, toString(q)) == 0) return out = q, true;
  return false;
}

namespace {

// Common checks on a datagram's length and header, before anything is copied.
PacketStatus checkDatagram(const uint8_t* data, std::size_t size, std::size_t expected_size, uint16_t expected_id) {
  if (data == nullptr) return PacketStatus::NullBuffer;
  if (size < expected_size) return PacketStatus::TooShort;
  if (size > expected_size) return PacketStatus::TooLong;
  Header h;
  std::memcpy(&h, data, sizeof(Header));
  if (h.packet_size != expected_size) return PacketStatus::SizeFieldMismatch;
  if (h.datagram_id != expected_id) return PacketStatus::WrongDatagramId;
  return PacketStatus::Ok;
}

}  // namespace

PacketStatus decodeMeasurement(const uint8_t* data, std::size_t size, MsrPacket& out) noexcept {
  const PacketStatus s = checkDatagram(data, size, kMsrPacketSize, kDatagramIdMsr);
  if (s != PacketStatus::Ok) return s;
  IntfState intf;
  std::memcpy(&intf, data + offsetof(MsrPacket, intf), sizeof(IntfState));
  if (intf.state > static_cast<uint16_t>(State::Cmd)) return PacketStatus::BadState;
  if (intf.quality > static_cast<uint16_t>(Quality::Perfect)) return PacketStatus::BadQuality;
  std::memcpy(&out, data, kMsrPacketSize);
  return PacketStatus::Ok;
}

PacketStatus decodeCommand(const uint8_t* data, std::size_t size, CmdPacket& out) noexcept {
  const PacketStatus s = checkDatagram(data, size, kCmdPacketSize, kDatagramIdCmd);
  if (s != PacketStatus::Ok) return s;
  std::memcpy(&out, data, kCmdPacketSize);
  return PacketStatus::Ok;
}

PacketStatus encodeCommand(const CmdPacket& in, uint8_t* buf, std::size_t capacity, std::size_t& written) noexcept {
  written = 0;
  if (buf == nullptr) return PacketStatus::NullBuffer;
  if (capacity < kCmdPacketSize) return PacketStatus::BufferTooSmall;
  std::memcpy(buf, &in, kCmdPacketSize);
  const uint16_t size = static_cast<uint16_t>(kCmdPacketSize);
  const uint16_t id = kDatagramIdCmd;
  std::memcpy(buf + offsetof(Header, packet_size), &size, 2);
  std::memcpy(buf + offsetof(Header, datagram_id), &id, 2);
  written = kCmdPacketSize;
  return PacketStatus::Ok;
}

PacketStatus encodeMeasurement(const MsrPacket& in, uint8_t* buf, std::size_t capacity,
                               std::size_t& written) noexcept {
  written = 0;
  if (buf == nullptr) return PacketStatus::NullBuffer;
  if (capacity < kMsrPacketSize) return PacketStatus::BufferTooSmall;
  std::memcpy(buf, &in, kMsrPacketSize);
  const uint16_t size = static_cast<uint16_t>(kMsrPacketSize);
  const uint16_t id = kDatagramIdMsr;
  std::memcpy(buf + offsetof(Header, packet_size), &size, 2);
  std::memcpy(buf + offsetof(Header, datagram_id), &id, 2);
  written = kMsrPacketSize;
  return PacketStatus::Ok;
}

void toFrame(const float (&m)[kCartFrameDim], KDL::Frame& f) noexcept {
  f.M = KDL::Rotation(m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10]);
  f.p = KDL::Vector(m[3], m[7], m[11]);
}

void fromFrame(const KDL::Frame& f, float (&m)[kCartFrameDim]) noexcept {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m[4 * r + c] = static_cast<float>(f.M(r, c));
    m[4 * r + 3] = static_cast<float>(f.p(r));
  }
}

bool validFriPose(const float (&m)[kCartFrameDim], double tol) noexcept {
  for (float v : m) {
    if (!std::isfinite(v)) return false;
  }
  // |R^T R - I| entrywise
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double d = 0.0;
      for (int k = 0; k < 3; ++k) d += static_cast<double>(m[4 * k + i]) * static_cast<double>(m[4 * k + j]);
      if (std::fabs(d - (i == j ? 1.0 : 0.0)) > tol) return false;
    }
  }
  const double det = static_cast<double>(m[0]) * (double(m[5]) * m[10] - double(m[6]) * m[9]) -
                     static_cast<double>(m[1]) * (double(m[4]) * m[10] - double(m[6]) * m[8]) +
                     static_cast<double>(m[2]) * (double(m[4]) * m[9] - double(m[5]) * m[8]);
  return det > 0.0;
}

const char* toString(CartOffset f) {
  switch (f) {
    case CartOffset::None: return "none";
    case CartOffset::Composed: return "composed";
    case CartOffset::Elementwise: return "elementwise";
  }
  return "invalid";
}

bool parseCartOffset(const char* word, CartOffset& out) {
  for (CartOffset f : {CartOffset::None, CartOffset::Composed, CartOffset::Elementwise})
    if (std::strcmp(word, toString(f)) == 0) return out = f, true;
  return false;
}

bool readSetPoint(const float (&cmd)[kCartFrameDim], const float (&offset)[kCartFrameDim], CartOffset form,
                  KDL::Frame& sp) noexcept {
  if (!validFriPose(cmd)) return false;
  bool zero = true;
  for (float v : offset) zero = zero && v == 0.0f;
  if (form == CartOffset::None || zero) {
    toFrame(cmd, sp);
    return true;
  }
  if (form == CartOffset::Composed) {
    if (!validFriPose(offset)) return false;
    KDL::Frame c, o;
    toFrame(cmd, c);
    toFrame(offset, o);
    sp = c * o;
    return true;
  }
  float sum[kCartFrameDim];
  for (int i = 0; i < kCartFrameDim; ++i) sum[i] = cmd[i] + offset[i];
  if (!validFriPose(sum)) return false;
  toFrame(sum, sp);
  return true;
}

void writeSetPoint(const KDL::Frame& krl, const KDL::Frame& sp, CartOffset form, float (&cmd)[kCartFrameDim],
                   float (&offset)[kCartFrameDim]) noexcept {
  switch (form) {
    case CartOffset::None:
      fromFrame(sp, cmd);
      for (float& v : offset) v = 0.0f;
      return;
    case CartOffset::Composed:
      fromFrame(krl, cmd);
      fromFrame(krl.Inverse() * sp, offset);
      return;
    case CartOffset::Elementwise: {
      fromFrame(krl, cmd);
      float s[kCartFrameDim];
      fromFrame(sp, s);
      for (int i = 0; i < kCartFrameDim; ++i) offset[i] = s[i] - cmd[i];
      return;
    }
  }
}

double rotationAngle(const KDL::Rotation& r, KDL::Vector& axis) noexcept {
  double x, y, z, w;
  r.GetQuaternion(x, y, z, w);
  if (w < 0.0) {  // the shorter way round
    x = -x;
    y = -y;
    z = -z;
    w = -w;
  }
  const double s = std::sqrt(x * x + y * y + z * z);
  if (!(s > 0.0)) {
    axis = KDL::Vector(0.0, 0.0, 1.0);
    return 0.0;
  }
  axis = KDL::Vector(x / s, y / s, z / s);
  return 2.0 * std::atan2(s, w);
}

std::array<double, 6> toWrench(const float (&ft)[kCartVecDim]) noexcept {
  return {ft[0], ft[1], ft[2], ft[5], ft[4], ft[3]};
}

void fromWrench(const std::array<double, 6>& w, float (&ft)[kCartVecDim]) noexcept {
  ft[0] = static_cast<float>(w[0]);
  ft[1] = static_cast<float>(w[1]);
  ft[2] = static_cast<float>(w[2]);
  ft[3] = static_cast<float>(w[5]);
  ft[4] = static_cast<float>(w[4]);
  ft[5] = static_cast<float>(w[3]);
}

const char* toString(WrenchFrame f) { return f == WrenchFrame::Tool ? "tool" : "base"; }

bool parseWrenchFrame(const char* word, WrenchFrame& out) {
  for (WrenchFrame f : {WrenchFrame::Base, WrenchFrame::Tool})
    if (word != nullptr && std::strcmp(word, toString(f)) == 0) return out = f, true;
  return false;
}

namespace {
/// Force and moment of `w` turned by `r` (r * f, r * m).
std::array<double, 6> turned(const std::array<double, 6>& w, const KDL::Rotation& r) noexcept {
  const KDL::Vector f = r * KDL::Vector(w[0], w[1], w[2]);
  const KDL::Vector m = r * KDL::Vector(w[3], w[4], w[5]);
  return {f.x(), f.y(), f.z(), m.x(), m.y(), m.z()};
}
}  // namespace

std::array<double, 6> wrenchInBase(const float (&ft)[kCartVecDim], WrenchFrame frame,
                                   const KDL::Rotation& msr) noexcept {
  const std::array<double, 6> w = toWrench(ft);
  return frame == WrenchFrame::Tool ? turned(w, msr) : w;  // {g}R{e} * w_e
}

std::array<double, 6> wrenchInFrame(const std::array<double, 6>& w_base, WrenchFrame frame,
                                    const KDL::Rotation& msr) noexcept {
  return frame == WrenchFrame::Tool ? turned(w_base, msr.Inverse()) : w_base;  // {e}R{g} * w_g
}

void fromWrenchIn(const std::array<double, 6>& w_base, WrenchFrame frame, const KDL::Rotation& msr,
                  float (&ft)[kCartVecDim]) noexcept {
  fromWrench(wrenchInFrame(w_base, frame, msr), ft);
}

}  // namespace fri
}  // namespace tactile
