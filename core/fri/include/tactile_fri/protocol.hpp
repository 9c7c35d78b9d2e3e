// KUKA FRI (Fast Research Interface, LWR 4+ / KRC2) wire protocol, declared
// from the public facts of the protocol (not copied from KUKA's friComm.h):
//
//   * UDP, little-endian, 4-byte IEEE floats, 4-byte signed ints, u16 flags.
//   * measurement packet KRC -> remote: 916 bytes, datagram id 0x2006;
//   * command packet remote -> KRC:     376 bytes, datagram id 0x1005;
//   * header = sendSeqCount, reflSeqCount, packetSize, datagramId (u16 each).
//
// Every struct below is a plain aggregate whose memory image IS the wire image
// on a little-endian host (asserted at compile time): every field is naturally
// aligned, so no padding exists, which the static_asserts on every size and
// every offset prove. Decoding is a checked memcpy from a byte buffer; nothing
// here allocates, throws, logs or reads a clock.
//
// Pose convention: FRI's Cartesian poses are {g}T{e} (robot base -> flange) as
// the first three rows of the homogeneous matrix, row-major:
//   [r00 r01 r02 px  r10 r11 r12 py  r20 r21 r22 pz]   (metres).
// Wrench convention on the wire: estExtTcpFT = [Fx Fy Fz Tz Ty Tx] (note the
// reversed torque order); toWrench()/fromWrench() convert to/from the project's
// [Fx Fy Fz Tx Ty Tz].
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include <kdl/frames.hpp>

#include "tactile_types/kdl_pose.hpp"
#include "tactile_types/types.hpp"

#if !defined(__BYTE_ORDER__) || (__BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__)
#error "tactile_fri decodes FRI packets by memcpy and needs a little-endian host"
#endif

namespace tactile {
namespace fri {

static_assert(sizeof(float) == 4, "FRI floats are 4 bytes");

constexpr int kNumJoints = 7;
constexpr int kCartFrameDim = 12;  ///< 3x4 row-major homogeneous matrix
constexpr int kCartVecDim = 6;
constexpr int kUserSize = 16;      ///< KRL exchange data: 16 floats, 16 ints

constexpr uint16_t kDatagramIdMsr = 0x2006;
constexpr uint16_t kDatagramIdCmd = 0x1005;
constexpr std::size_t kMsrPacketSize = 916;
constexpr std::size_t kCmdPacketSize = 376;
constexpr uint16_t kDefaultPort = 49938;

/// Interface state (tFriIntfState.state).
enum class State : uint16_t { Off = 0, Mon = 1, Cmd = 2 };
/// Communication quality (tFriIntfState.quality), ordered.
enum class Quality : uint16_t { Unacceptable = 0, Bad = 1, Ok = 2, Perfect = 3 };
/// Control strategy of the KRC (tFriRobotState.control).
enum class ControlStrategy : uint16_t { Other = 0, Position = 1, CartImpedance = 2, JointImpedance = 3 };

/// Command flags (tFriRobotCommand.cmdFlags).
namespace flags {
constexpr uint32_t kJointPosition = 0x0001;
constexpr uint32_t kJointTorque = 0x0004;
constexpr uint32_t kJointStiffness = 0x0010;
constexpr uint32_t kJointDamping = 0x0020;
constexpr uint32_t kCartPose = 0x0100;
constexpr uint32_t kTcpWrench = 0x0400;
constexpr uint32_t kCartStiffness = 0x1000;
constexpr uint32_t kCartDamping = 0x2000;
}  // namespace flags

// ---- wire layout ------------------------------------------------------------

struct Header {
  uint16_t send_seq;    ///< sendSeqCount: incremented by the sender every packet
  uint16_t refl_seq;    ///< reflSeqCount: the peer's last sendSeqCount
  uint16_t packet_size; ///< total datagram size in bytes
  uint16_t datagram_id; ///< kDatagramIdMsr or kDatagramIdCmd
};

struct KrlData {
  float real_data[kUserSize];
  int32_t int_data[kUserSize];
  uint16_t bool_data;
  uint16_t fill;
};

struct IntfStatistics {
  float answer_rate;  ///< fraction of answered packets (0..1)
  float latency;      ///< s
  float jitter;       ///< s
  float miss_rate;    ///< fraction of missed answers (0..1)
  uint32_t miss_counter;
};

struct IntfState {
  uint32_t timestamp;
  uint16_t state;    ///< State
  uint16_t quality;  ///< Quality
  float desired_msr_sample_time;  ///< s
  float desired_cmd_sample_time;  ///< s
  float safety_limits;
  IntfStatistics stat;
};

struct RobotState {
  uint16_t power;    ///< bit per drive; != 0 means powered
  uint16_t control;  ///< ControlStrategy
  uint16_t error;
  uint16_t warning;
  float temperature[kNumJoints];
};

struct RobotData {
  float msr_jnt_pos[kNumJoints];                 ///< rad
  float msr_cart_pos[kCartFrameDim];             ///< {g}T{e}, 3x4 row-major
  float cmd_jnt_pos[kNumJoints];
  float cmd_jnt_pos_fri_offset[kNumJoints];
  float cmd_cart_pos[kCartFrameDim];
  float cmd_cart_pos_fri_offset[kCartFrameDim];
  float msr_jnt_trq[kNumJoints];                 ///< N m
  float est_ext_jnt_trq[kNumJoints];             ///< N m
  float est_ext_tcp_ft[kCartVecDim];             ///< Fx Fy Fz Tz Ty Tx
  float jacobian[kCartVecDim * kNumJoints];      ///< 6x7 row-major
  float mass_matrix[kNumJoints * kNumJoints];    ///< 7x7 row-major
  float gravity[kNumJoints];
};

struct MsrPacket {
  Header head;
  KrlData krl;
  IntfState intf;
  RobotState robot;
  RobotData data;
};

struct RobotCommand {
  uint32_t cmd_flags;
  float jnt_pos[kNumJoints];
  float cart_pos[kCartFrameDim];
  float add_jnt_trq[kNumJoints];
  float add_tcp_ft[kCartVecDim];
  float jnt_stiffness[kNumJoints];
  float jnt_damping[kNumJoints];
  float cart_stiffness[kCartVecDim];
  float cart_damping[kCartVecDim];
};

struct CmdPacket {
  Header head;
  KrlData krl;
  RobotCommand cmd;
};

// ---- layout proofs: every size and every offset -------------------------------
static_assert(sizeof(Header) == 8, "Header size");
static_assert(offsetof(Header, send_seq) == 0 && offsetof(Header, refl_seq) == 2 &&
                  offsetof(Header, packet_size) == 4 && offsetof(Header, datagram_id) == 6,
              "Header offsets");
static_assert(sizeof(KrlData) == 132, "KrlData size");
static_assert(offsetof(KrlData, real_data) == 0 && offsetof(KrlData, int_data) == 64 &&
                  offsetof(KrlData, bool_data) == 128 && offsetof(KrlData, fill) == 130,
              "KrlData offsets");
static_assert(sizeof(IntfStatistics) == 20, "IntfStatistics size");
static_assert(offsetof(IntfStatistics, answer_rate) == 0 && offsetof(IntfStatistics, latency) == 4 &&
                  offsetof(IntfStatistics, jitter) == 8 && offsetof(IntfStatistics, miss_rate) == 12 &&
                  offsetof(IntfStatistics, miss_counter) == 16,
              "IntfStatistics offsets");
static_assert(sizeof(IntfState) == 40, "IntfState size");
static_assert(offsetof(IntfState, timestamp) == 0 && offsetof(IntfState, state) == 4 &&
                  offsetof(IntfState, quality) == 6 && offsetof(IntfState, desired_msr_sample_time) == 8 &&
                  offsetof(IntfState, desired_cmd_sample_time) == 12 && offsetof(IntfState, safety_limits) == 16 &&
                  offsetof(IntfState, stat) == 20,
              "IntfState offsets");
static_assert(sizeof(RobotState) == 36, "RobotState size");
static_assert(offsetof(RobotState, power) == 0 && offsetof(RobotState, control) == 2 &&
                  offsetof(RobotState, error) == 4 && offsetof(RobotState, warning) == 6 &&
                  offsetof(RobotState, temperature) == 8,
              "RobotState offsets");
static_assert(sizeof(RobotData) == 700, "RobotData size (175 floats)");
static_assert(offsetof(RobotData, msr_jnt_pos) == 0 && offsetof(RobotData, msr_cart_pos) == 28 &&
                  offsetof(RobotData, cmd_jnt_pos) == 76 && offsetof(RobotData, cmd_jnt_pos_fri_offset) == 104 &&
                  offsetof(RobotData, cmd_cart_pos) == 132 && offsetof(RobotData, cmd_cart_pos_fri_offset) == 180 &&
                  offsetof(RobotData, msr_jnt_trq) == 228 && offsetof(RobotData, est_ext_jnt_trq) == 256 &&
                  offsetof(RobotData, est_ext_tcp_ft) == 284 && offsetof(RobotData, jacobian) == 308 &&
                  offsetof(RobotData, mass_matrix) == 476 && offsetof(RobotData, gravity) == 672,
              "RobotData offsets");
static_assert(sizeof(MsrPacket) == kMsrPacketSize, "measurement packet is 916 bytes");
static_assert(offsetof(MsrPacket, head) == 0 && offsetof(MsrPacket, krl) == 8 && offsetof(MsrPacket, intf) == 140 &&
                  offsetof(MsrPacket, robot) == 180 && offsetof(MsrPacket, data) == 216,
              "MsrPacket offsets");
static_assert(sizeof(RobotCommand) == 236, "RobotCommand size");
static_assert(offsetof(RobotCommand, cmd_flags) == 0 && offsetof(RobotCommand, jnt_pos) == 4 &&
                  offsetof(RobotCommand, cart_pos) == 32 && offsetof(RobotCommand, add_jnt_trq) == 80 &&
                  offsetof(RobotCommand, add_tcp_ft) == 108 && offsetof(RobotCommand, jnt_stiffness) == 132 &&
                  offsetof(RobotCommand, jnt_damping) == 160 && offsetof(RobotCommand, cart_stiffness) == 188 &&
                  offsetof(RobotCommand, cart_damping) == 212,
              "RobotCommand offsets");
static_assert(sizeof(CmdPacket) == kCmdPacketSize, "command packet is 376 bytes");
static_assert(offsetof(CmdPacket, head) == 0 && offsetof(CmdPacket, krl) == 8 && offsetof(CmdPacket, cmd) == 140,
              "CmdPacket offsets");

// ---- decode / encode ----------------------------------------------------------

/// Result of decoding one datagram. Anything but Ok carries no usable data.
enum class PacketStatus : uint8_t {
  Ok = 0,
  NullBuffer = 1,        ///< data == nullptr
  TooShort = 2,          ///< fewer bytes than the packet size
  TooLong = 3,           ///< more bytes than the packet size
  SizeFieldMismatch = 4, ///< header.packetSize disagrees with the packet type
  WrongDatagramId = 5,   ///< header.datagramId is not the expected one
  BadState = 6,          ///< intf.state outside OFF/MON/CMD
  BadQuality = 7,        ///< intf.quality outside 0..3
  BufferTooSmall = 8     ///< encode: output buffer smaller than the packet
};
const char* toString(PacketStatus s);
const char* toString(State s);
const char* toString(Quality q);
/// The inverses of toString: "OFF" | "MON" | "CMD", "UNACCEPTABLE" | "BAD" |
/// "OK" | "PERFECT"; false (out unchanged) for any other word.
bool parseState(const char* word, State& out);
bool parseQuality(const char* word, Quality& out);

/// Decode a measurement datagram (KRC -> remote). `out` is written only on Ok.
PacketStatus decodeMeasurement(const uint8_t* data, std::size_t size, MsrPacket& out) noexcept;
/// Decode a command datagram (remote -> KRC); used by the simulated KRC and tests.
PacketStatus decodeCommand(const uint8_t* data, std::size_t size, CmdPacket& out) noexcept;
/// Encode into `buf`; returns Ok and sets `written`, or BufferTooSmall.
/// The header's packetSize and datagramId are filled in here.
PacketStatus encodeCommand(const CmdPacket& in, uint8_t* buf, std::size_t capacity, std::size_t& written) noexcept;
PacketStatus encodeMeasurement(const MsrPacket& in, uint8_t* buf, std::size_t capacity,
                               std::size_t& written) noexcept;

inline State stateOf(const MsrPacket& m) { return static_cast<State>(m.intf.state); }
inline Quality qualityOf(const MsrPacket& m) { return static_cast<Quality>(m.intf.quality); }
inline bool powerOn(const MsrPacket& m) { return m.robot.power != 0; }

/// Sequence-counter distance b - a on the 16-bit wrap-around circle, in [-32768, 32767].
inline int seqDelta(uint16_t a, uint16_t b) { return static_cast<int16_t>(static_cast<uint16_t>(b - a)); }

// ---- pose conversions: 3x4 row-major FRI pose <-> KDL::Frame <-> tactile::Pose

void toFrame(const float (&m)[kCartFrameDim], KDL::Frame& f) noexcept;
void fromFrame(const KDL::Frame& f, float (&m)[kCartFrameDim]) noexcept;
// tactile::Pose <-> KDL::Frame: the project-wide conversion (strict
// bool toFrame(pose, frame); callers reject invalid poses with validPose() first).
using tactile::toFrame;
using tactile::toPose;

/// All 12 entries finite and the 3x3 part a rotation within `tol`
/// (|R^T R - I|_max <= tol and det(R) > 0).
bool validFriPose(const float (&m)[kCartFrameDim], double tol = 1e-3) noexcept;
/// Finite position and unit quaternion: the project's one rule (tactile_types/types.hpp).
using tactile::validPose;

/// How the KRC's Cartesian set point is read from a measurement's cmdCartPos
/// (C) and cmdCartPosFriOffset (O), both 3x4 row-major (fri.cart_offset):
///  * None: C alone (the offset is ignored);
///  * Composed: C * O as homogeneous transforms (O a rotation and translation;
///    all twelve entries 0 read as the identity);
///  * Elementwise: C + O entry by entry over the 12 entries. Stanford's FRI
///    library (Fast Research Interface Library 1.2,
///    FastResearchInterface/SetControlScheme.cpp)
///    notes this as what the KUKA documentation asks for before a Cartesian
///    impedance start (its twelve-entry loop, left commented out there, so
///    that library itself reads C alone); KUKA's friremote.cpp mirrors the joint set point in the same way
///    (cmdJntPos[i] + cmdJntPosFriOffset[i]).
/// Which one a given KRC uses is not documented beyond that: fri_check finds
/// it (docs/bringup.md).
enum class CartOffset : uint8_t { None = 0, Composed = 1, Elementwise = 2 };
/// "none" | "composed" | "elementwise" (the fri.yaml words).
const char* toString(CartOffset f);
/// The inverse of toString(CartOffset); false (out unchanged) for another word.
bool parseCartOffset(const char* word, CartOffset& out);
/// The set point C (form) O; false when C, O or the result is not a valid pose
/// (validFriPose), e.g. an elementwise offset read as composed. `sp` is
/// written only on true.
bool readSetPoint(const float (&cmd)[kCartFrameDim], const float (&offset)[kCartFrameDim], CartOffset form,
                  KDL::Frame& sp) noexcept;
/// The KRC's side: cmdCartPos and cmdCartPosFriOffset for the set point `sp`
/// when the KRL program's own commanded pose is `krl` (None: C = sp, O = 0;
/// Composed: C = krl, O = krl^-1 * sp; Elementwise: C = krl, O = sp - krl
/// entry by entry).
void writeSetPoint(const KDL::Frame& krl, const KDL::Frame& sp, CartOffset form, float (&cmd)[kCartFrameDim],
                   float (&offset)[kCartFrameDim]) noexcept;

/// Angle (in [0, pi]) and unit axis of a rotation, accurate for small angles
/// (computed from the quaternion with atan2; KDL's GetRotAngle returns 0 below
/// about 1.4e-3 rad). axis = (0,0,1) when the angle is 0.
double rotationAngle(const KDL::Rotation& r, KDL::Vector& axis) noexcept;

/// estExtTcpFT [Fx Fy Fz Tz Ty Tx] -> [Fx Fy Fz Tx Ty Tz] and back.
std::array<double, 6> toWrench(const float (&ft)[kCartVecDim]) noexcept;
void fromWrench(const std::array<double, 6>& w, float (&ft)[kCartVecDim]) noexcept;

/// The axes estExtTcpFT is expressed in. KUKA's friComm.h: "reference frame:
/// $STIFFNESS.TASKFRAME"; this project reads $STIFFNESS.FRAMETYPE #BASE as
/// the robot's base {g} (with $STIFFNESS.BASE the null frame) and #TOOL as
/// the TCP's axes, here the flange {e} ($STIFFNESS.TOOL the null frame). The
/// public sources do not say more (ISIR's resetSTIFFNESS.src names #TOOL and
/// #BASE as the Cartesian stiffness' frame); the day-one known-weight check
/// (fri_check --wrench-check, docs/bringup.md) decides on the arm. The
/// moment is about the TCP in either case: only the axes differ.
enum class WrenchFrame : uint8_t { Base = 0, Tool = 1 };
/// "base" | "tool" (the fri.yaml words).
const char* toString(WrenchFrame f);
/// The inverse of toString(WrenchFrame); false (out unchanged) for another word.
bool parseWrenchFrame(const char* word, WrenchFrame& out);
/// estExtTcpFT in `frame`'s axes -> [Fx Fy Fz Tx Ty Tz] in {g} axes; `msr`
/// is the measured {g}R{e} (msrCartPos's rotation), used for Tool.
std::array<double, 6> wrenchInBase(const float (&ft)[kCartVecDim], WrenchFrame frame,
                                   const KDL::Rotation& msr) noexcept;
/// The KRC's side: a wrench [Fx Fy Fz Tx Ty Tz] in {g} axes turned into
/// `frame`'s axes (the values estExtTcpFT carries, before float32).
std::array<double, 6> wrenchInFrame(const std::array<double, 6>& w_base, WrenchFrame frame,
                                    const KDL::Rotation& msr) noexcept;
/// The KRC's side: a wrench [Fx Fy Fz Tx Ty Tz] in {g} axes written as
/// estExtTcpFT in `frame`'s axes.
void fromWrenchIn(const std::array<double, 6>& w_base, WrenchFrame frame, const KDL::Rotation& msr,
                  float (&ft)[kCartVecDim]) noexcept;

}  // namespace fri
}  // namespace tactile
