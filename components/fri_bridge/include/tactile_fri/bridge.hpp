// The FRI bridge core: one measurement packet in, at most one command packet
// out. RTT-free, allocation-free, exception-free, clock-free (time is passed in).
//
// Behaviour per received measurement (the component is triggered by each
// packet, so one step() per datagram):
//
//  * Sequence check on header.sendSeqCount (16-bit, wrap-around): a packet whose
//    counter is not newer than the last accepted one is a duplicate or arrived
//    out of order; it is dropped WITHOUT a reply (the KRC already got, or will
//    get, the reply to the newer packet). Gaps count as lost packets.
//    `resync_after` consecutive "older" packets are taken as a restarted KRC
//    sequence and accepted.
//  * MON or OFF state, or drives powered off: the command echoes the measured
//    Cartesian pose (msrCartPos), so nothing moves and the KRC may switch to
//    CMD without a jump. The rate limiter is re-seeded from the measured pose.
//  * CMD at quality >= OK: the desired flange pose {g}T{e} goes through the rate
//    limiter (max translational speed, max rotational speed) and is commanded.
//  * Start gate: at the start of a session (configure/reset), each time the KRC
//    (re)enters CMD, and after the desired pose was invalid or stale, the
//    bridge holds the pose it starts from (the measured pose) and follows the
//    desired pose only once that is within one program step of it
//    (engage_max_trans, engage_max_rot: set them to the servo program's
//    max_trans_speed / max_rot_speed over one servo cycle). Until then: status DesiredFar, hold. The
//    first command of a session is never turned into motion away from the
//    measured pose; the servo's first command is its measured pose.
//  * CMD at quality < OK, invalid/stale desired pose, invalid measured pose:
//    HOLD: the last commanded pose is repeated unchanged.
//  * CMD with a control strategy other than Cartesian impedance (position 1,
//    joint impedance 3): the bridge cannot apply Cartesian poses; it replies a
//    joint hold (status WrongStrategy) and follows nothing.
//  * Every reply carries jntPos = cmdJntPos + cmdJntPosFriOffset (the KRC's
//    current joint set point), used by the KRC only when flag 0x1 is set.
//  * Leaving CMD: status LeftCmd (sticky while the KRC stays out of CMD) and
//    the measured pose is echoed again.
//
// Lost or late COMMANDS (on the way back): the KRC reflects the sendSeqCount
// of the last command it received in reflSeqCount. When that is not our latest
// command, the KRC is holding an older one; the bridge rewinds its limiter to
// that command (kept in a 64-entry ring) and steps from there, so the KRC never
// sees two consecutive applied commands further apart than one limited step
// (`rewind_on_refl`; a refl older than the ring is ignored: hold).
//
// Packet loss and reordering - HOLD, never extrapolate: the limiter advances
// at most v_max * T and w_max * T per reply, where T is the KRC's command
// sample time (desiredCmdSampleTime, or nominal_period_s when the KRC's value
// is not in (0, 0.1] s), whatever time passed since the previous reply. After
// a gap the KRC has been holding our last command, and the next command is
// within one limited step of it: no jump, no catch-up. Dropped (stale) packets
// get no reply at all, so a late packet can never move the command backwards.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include <kdl/frames.hpp>

#include "tactile_fri/protocol.hpp"
#include "tactile_types/config_result.hpp"
#include "tactile_types/types.hpp"

namespace tactile {
namespace fri {

/// Limits a commanded pose's speed: |dp| <= v_max * dt, rotation angle <= w_max * dt.
class PoseRateLimiter {
 public:
  void setLimits(double max_lin_speed, double max_rot_speed) noexcept {
    max_lin_ = max_lin_speed;
    max_rot_ = max_rot_speed;
  }
  void reset(const KDL::Frame& f) noexcept { current_ = f; }
  const KDL::Frame& current() const noexcept { return current_; }
  /// Moves current() towards `target`; returns true when the step was clipped.
  bool step(const KDL::Frame& target, double dt) noexcept;

 private:
  double max_lin_ = 0.0;
  double max_rot_ = 0.0;
  KDL::Frame current_ = KDL::Frame::Identity();
};

struct BridgeParams {
  double max_lin_speed = 0.05;      ///< m/s, (0, 2]
  double max_rot_speed = 0.25;      ///< rad/s, (0, 3]
  double nominal_period_s = 0.001;  ///< s, (0, 0.1]: used when the KRC's desiredCmdSampleTime is not in (0, 0.1]
  double max_desired_age_s = 0.1;   ///< s, (0, 10]: older desired poses are not followed (hold)
  int resync_after = 8;             ///< [1, 1000] consecutive old packets accepted as a restarted sequence
  bool rewind_on_refl = true;       ///< step from the command the KRC reflects (see above)
  double engage_max_trans = 0.0005;  ///< m, (0, 0.1]: start gate, translation (the program's max_trans_speed x servo period)
  double engage_max_rot = 0.5 * 3.14159265358979323846 / 180.0;  ///< rad, (0, 0.5]: start gate, rotation (max_rot_speed x servo period)
  bool command_impedance = false;   ///< also send Cartesian stiffness/damping (flags 0x1000|0x2000)
  std::array<double, 6> cart_stiffness{{2000.0, 2000.0, 2000.0, 200.0, 200.0, 200.0}};  ///< N/m x3 [0.01,5000], N m/rad x3 [0.01,300]
  std::array<double, 6> cart_damping{{0.7, 0.7, 0.7, 0.7, 0.7, 0.7}};  ///< normalised, [0.1, 1.0]
};

/// Outcome of one step(). Values < kBridgeFirstNoReply (16) produce a reply; the others do not.
enum class BridgeStatus : uint8_t {
  Commanding = 0,      ///< CMD, quality >= OK, following the desired pose
  Limited = 1,         ///< as Commanding, but the rate limiter clipped the step
  Monitor = 2,         ///< MON/OFF: echoing the measured pose
  PowerOff = 3,        ///< drives off: echoing the measured pose
  LeftCmd = 4,         ///< the KRC left CMD (now MON/OFF): echoing the measured pose
  QualityLow = 5,      ///< CMD at quality < OK: holding the last command
  DesiredInvalid = 6,  ///< CMD: desired pose NaN/Inf/non-unit quaternion or never set: holding
  DesiredStale = 7,    ///< CMD: desired pose older than max_desired_age_s: holding
  MeasurementInvalid = 8,  ///< measured pose NaN/non-rotation; CMD: holding (reply), else no reply
  WrongStrategy = 9,   ///< CMD, but the KRC's control strategy is not Cartesian impedance:
                       ///< joint hold (flag 0x1, jntPos = cmdJntPos + cmdJntPosFriOffset), nothing else applied
  DesiredFar = 10,     ///< CMD, start gate: the desired pose is more than one program step from the
                       ///< pose the bridge starts from (engage_max_trans/rot): holding that pose
  DroppedDuplicate = 16,   ///< same sendSeqCount as the last accepted packet: no reply
  DroppedOutOfOrder = 17,  ///< older sendSeqCount: no reply
  Malformed = 18,          ///< decode failed (see packet_status): no reply
  NotConfigured = 19
};
constexpr uint8_t kBridgeFirstNoReply = 16;
inline bool producesReply(BridgeStatus s) { return static_cast<uint8_t>(s) < kBridgeFirstNoReply; }
const char* toString(BridgeStatus s);

struct BridgeOutput {
  bool reply = false;  ///< send `cmd` back to the KRC
  CmdPacket cmd{};     ///< the command packet (valid when reply)
  BridgeStatus status = BridgeStatus::NotConfigured;
  PacketStatus packet_status = PacketStatus::Ok;  ///< decode result (stepDatagram)
  State state = State::Off;
  Quality quality = Quality::Unacceptable;
  bool state_changed = false;    ///< state or quality differs from the previous accepted packet
  uint16_t lost_before = 0;      ///< packets missing between the previous accepted one and this
  KDL::Frame commanded = KDL::Frame::Identity();  ///< {g}T{e} sent (valid when reply)
};

struct BridgeStats {
  uint64_t received = 0;      ///< step() calls
  uint64_t accepted = 0;      ///< packets passing the sequence check
  uint64_t replies = 0;
  uint64_t lost = 0;          ///< sum of sequence gaps
  uint64_t duplicates = 0;
  uint64_t out_of_order = 0;
  uint64_t malformed = 0;
  uint64_t resyncs = 0;
  uint64_t limited = 0;
  uint64_t holds = 0;         ///< replies that repeated the last command
  uint64_t rewinds = 0;       ///< limiter rewound to the command the KRC reflected
};

class FriBridge {
 public:
  ConfigResult configure(const BridgeParams& params);
  /// Forget sequence history and state (e.g. after the transport reopened).
  void reset() noexcept;

  /// One decoded measurement. Fills `out` (out.cmd only when out.reply).
  BridgeStatus step(const MsrPacket& msr, const PoseCommand& desired, double now_s, BridgeOutput& out) noexcept;
  /// Decode `data` then step(); a malformed datagram gives Malformed and no reply.
  BridgeStatus stepDatagram(const uint8_t* data, std::size_t size, const PoseCommand& desired, double now_s,
                            BridgeOutput& out) noexcept;

  /// KRL exchange data sent with every command (zero by default).
  void setKrlOut(const KrlData& krl) noexcept { krl_out_ = krl; }
  const BridgeStats& stats() const noexcept { return stats_; }
  const BridgeParams& params() const noexcept { return params_; }
  bool configured() const noexcept { return configured_; }
  /// The last decoded measurement (valid after a successful stepDatagram).
  const MsrPacket& lastMeasurement() const noexcept { return msr_; }

 private:
  void fillReply(const MsrPacket& msr, const KDL::Frame& pose, BridgeOutput& out, bool joint_hold = false) noexcept;

  BridgeParams params_{};
  bool configured_ = false;
  PoseRateLimiter limiter_;
  BridgeStats stats_{};
  KrlData krl_out_{};
  MsrPacket msr_{};  // decode scratch for stepDatagram
  bool have_seq_ = false;
  uint16_t last_seq_ = 0;
  int backwards_run_ = 0;
  uint16_t send_seq_ = 0;
  bool have_state_ = false;
  State last_state_ = State::Off;
  Quality last_quality_ = Quality::Unacceptable;
  static constexpr int kRing = 64;  // recently sent command poses, by sendSeqCount % kRing
  std::array<KDL::Frame, kRing> sent_pose_{};
  std::array<uint16_t, kRing> sent_seq_{};
  std::array<bool, kRing> sent_valid_{};
  bool have_command_ = false;  // limiter_ holds a pose that was sent
  bool engaged_ = false;       // start gate passed: following the desired pose
  bool was_in_cmd_ = false;    // sticky LeftCmd
};

}  // namespace fri
}  // namespace tactile
