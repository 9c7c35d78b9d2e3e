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
//  * MON or OFF state, or drives powered off: the command echoes the pose the
//    KRC holds the arm at: its set point, read from cmdCartPos and
//    cmdCartPosFriOffset as fri.cart_offset says (none | composed |
//    elementwise, protocol.hpp CartOffset), or msrCartPos where the KRC sends
//    no valid cmdCartPos. So
//    nothing moves and the KRC may switch to CMD without a jump; in a pressing
//    contact the set point lies inside the object (force / stiffness) and the
//    force is kept. The rate limiter is re-seeded from that pose.
//  * CMD at quality >= OK: the desired flange pose {g}T{e} goes through the rate
//    limiter (max translational speed, max rotational speed) and is commanded.
//  * Start gate: at the start of a session (configure/reset), each time the KRC
//    (re)enters CMD, and after the desired pose was invalid or stale, the
//    bridge holds the pose it starts from (the held pose, above) and follows the
//    desired pose only once that is within one program step of it
//    (engage_max_trans, engage_max_rot: set them to the servo program's
//    max_trans_speed / max_rot_speed over one servo cycle). Until then: status DesiredFar, hold. The
//    first command of a session is never turned into motion away from the
//    measured pose; the servo's first command is its measured pose.
//  * CMD at quality < OK, invalid/stale desired pose, invalid measured pose:
//    HOLD: the last commanded pose is repeated unchanged; the start gate is
//    passed again before the desired pose is followed.
//  * Command flags (cmdFlags) are chosen outside CMD only, from the control
//    strategy the KRC reports there, and kept unchanged for as long as the KRC
//    stays in CMD (KUKA's friremote.cpp allows a change of flags in monitor
//    mode only; a KRC refuses a change in command mode): Cartesian impedance
//    -> FRI_CMD_CARTPOS (0x100, with 0x1000|0x2000 under command_impedance),
//    any other strategy -> FRI_CMD_JNTPOS (0x1, the KRC's joint set point).
//    A session whose first packet is already in CMD chooses them there, once.
//  * CMD with a control strategy other than Cartesian impedance (position 1,
//    joint impedance 3), or with flags chosen for another strategy: the
//    bridge cannot apply Cartesian poses; it holds with the flags it has
//    (joint flags: jntPos = cmdJntPos + cmdJntPosFriOffset; Cartesian flags:
//    the last command) (status WrongStrategy) and follows nothing.
//  * Configuration checks, every accepted packet: the KRC's sample times
//    (desiredMsrSampleTime, desiredCmdSampleTime: friOpen's cycle) against
//    cycle_time_s, the KRC's UDP source port against krc_port (when set), the
//    control strategy against Cartesian impedance. A disagreement is never
//    silent: it is the status (CycleMismatch, PortMismatch, WrongStrategy),
//    in MON too (where the reply still echoes the measured pose), and in CMD
//    the bridge follows nothing (hold; WrongStrategy: joint hold).
//    BridgeOutput::mismatch has one bit per disagreement.
//  * The set point check, every accepted packet: the set point read under
//    cart_offset must be a valid pose within setpoint_max_dev /
//    setpoint_max_dev_rot of the measured pose (the deflection a contact's
//    force gives against the Cartesian stiffness). Otherwise the KRC sends its
//    set point in another form than cart_offset says (fri_check tells which):
//    status OffsetMismatch (mismatch bit kOffset), in MON the measured pose is
//    echoed instead, in CMD the bridge holds its last command (the measured
//    pose when it has none) and follows nothing.
//  * Dry run (setDryRun(true), bring-up): in CMD the bridge holds the pose
//    where CMD was entered, whatever the desired pose (status DryRun); the
//    robot state says dry_run, so the servo computes and records its commands
//    as if the arm followed.
//  * Robot state (BridgeOutput::robot, the component's robot_state port):
//    per accepted packet, the KRC's mode, quality, drives, strategy, the
//    configuration check, the dry run, the measured joints and `commandable`:
//    CMD, drives on, quality >= OK, Cartesian impedance, configuration
//    agreed, no dry run, a valid measured pose. The servo holds (status
//    waiting_for_robot) while it is false, and resumes from the measured
//    pose, which passes the start gate.
//  * Every reply carries jntPos = cmdJntPos + cmdJntPosFriOffset (the KRC's
//    current joint set point), used by the KRC only when flag 0x1 is set.
//  * Servo fault -> KRC stop: a desired pose whose status is a servo watchdog
//    (tactile::watchdogStatus: PhaseTimeout, ArmStalled, ForceMismatch,
//    PhantomContact, ...; the servo latches it and holds) asks the KRL
//    program to end, as requestStop() does, when stop_krc_on_servo_fault
//    (fri.yaml) is set: that reply and every later one carry
//    $FRI_FRM_INT[1] = krl::kRequestStop. stopCause() names the status.
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
// sample time (desiredCmdSampleTime, or cycle_time_s when the KRC's value
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

/// The bridge's limits on a command, one bit each (BridgeOutput::limits):
/// a clipped command is never silent, it names the limit that clipped it.
namespace limit {
constexpr uint8_t kMaxLinSpeed = 0x1;  ///< fri.max_lin_speed clipped the step's translation
constexpr uint8_t kMaxRotSpeed = 0x2;  ///< fri.max_rot_speed clipped the step's rotation
}  // namespace limit
/// "max_lin_speed", "max_rot_speed", "max_lin_speed+max_rot_speed" or "" (none):
/// the fri.yaml keys of the limits in `bits` (a static string).
const char* limitNames(uint8_t bits) noexcept;

/// Limits a commanded pose's speed: |dp| <= v_max * dt, rotation angle <= w_max * dt.
class PoseRateLimiter {
 public:
  void setLimits(double max_lin_speed, double max_rot_speed) noexcept {
    max_lin_ = max_lin_speed;
    max_rot_ = max_rot_speed;
  }
  void reset(const KDL::Frame& f) noexcept { current_ = f; }
  const KDL::Frame& current() const noexcept { return current_; }
  /// Moves current() towards `target`; returns the limit:: bits that clipped
  /// the step (0: reached).
  uint8_t step(const KDL::Frame& target, double dt) noexcept;

 private:
  double max_lin_ = 0.0;
  double max_rot_ = 0.0;
  KDL::Frame current_ = KDL::Frame::Identity();
};

struct BridgeParams {
  double max_lin_speed = 0.05;      ///< m/s, (0, 2]
  double max_rot_speed = 0.25;      ///< rad/s, (0, 3]
  /// s, (0, 0.1]: the KRC's cycle (KRL friOpen's argument). A KRC reporting
  /// another desiredMsrSampleTime or desiredCmdSampleTime is a CycleMismatch.
  double cycle_time_s = 0.001;
  /// The KRC's UDP source port (its FRI init file's local port), [0, 65535];
  /// 0 = any. Another one is a PortMismatch (see notePeerPort()).
  int krc_port = 0;
  double max_desired_age_s = 0.1;   ///< s, (0, 10]: older desired poses are not followed (hold)
  int resync_after = 8;             ///< [1, 1000] consecutive old packets accepted as a restarted sequence
  bool rewind_on_refl = true;       ///< step from the command the KRC reflects (see above)
  double engage_max_trans = 0.0005;  ///< m, (0, 0.1]: start gate, translation (the program's max_trans_speed x servo period)
  double engage_max_rot = 0.5 * 3.14159265358979323846 / 180.0;  ///< rad, (0, 0.5]: start gate, rotation (max_rot_speed x servo period)
  bool command_impedance = false;   ///< also send Cartesian stiffness/damping (flags 0x1000|0x2000)
  std::array<double, 6> cart_stiffness{{2000.0, 2000.0, 2000.0, 200.0, 200.0, 200.0}};  ///< N/m x3 [0.01,5000], N m/rad x3 [0.01,300]
  std::array<double, 6> cart_damping{{0.7, 0.7, 0.7, 0.7, 0.7, 0.7}};  ///< normalised, [0.1, 1.0]
  /// How the KRC's set point is read from cmdCartPos and cmdCartPosFriOffset
  /// (protocol.hpp CartOffset; fri_check finds the lab KRC's form).
  CartOffset cart_offset = CartOffset::Composed;
  /// The axes the KRC sends estExtTcpFT in (its $STIFFNESS.FRAMETYPE; protocol.hpp
  /// WrenchFrame): the component publishes the wrench in {g} (wrenchInBase).
  WrenchFrame wrench_frame = WrenchFrame::Base;
  /// A servo watchdog status on the desired pose asks the KRL program to end (requestStop()).
  bool stop_krc_on_servo_fault = true;
  double setpoint_max_dev = 0.01;      ///< m, (0, 1]: set point vs measured pose, else OffsetMismatch
  double setpoint_max_dev_rot = 0.05;  ///< rad, (0, 3.2]: the same for the orientation
};

/// Outcome of one step(). Values < kBridgeFirstNoReply (16) produce a reply; the others do not.
enum class BridgeStatus : uint8_t {
  Commanding = 0,      ///< CMD, quality >= OK, following the desired pose
  Limited = 1,         ///< as Commanding, but the rate limiter clipped the step: BridgeOutput::limits
                       ///< names the limit(s) (limitNames(): max_lin_speed, max_rot_speed)
  Monitor = 2,         ///< MON/OFF: echoing the measured pose
  PowerOff = 3,        ///< drives off: echoing the measured pose
  LeftCmd = 4,         ///< the KRC left CMD (now MON/OFF): echoing the measured pose
  QualityLow = 5,      ///< CMD at quality < OK: holding the last command
  DesiredInvalid = 6,  ///< CMD: desired pose NaN/Inf/non-unit quaternion or never set: holding
  DesiredStale = 7,    ///< CMD: desired pose older than max_desired_age_s: holding
  MeasurementInvalid = 8,  ///< measured pose NaN/non-rotation; CMD: holding (reply), else no reply
  WrongStrategy = 9,   ///< the KRC's control strategy is not Cartesian impedance (MON: echo with
                       ///< FRI_CMD_JNTPOS, jntPos = cmdJntPos + cmdJntPosFriOffset; CMD: hold with the
                       ///< flags chosen in MON), nothing followed
  DesiredFar = 10,     ///< CMD, start gate: the desired pose is more than one program step from the
                       ///< pose the bridge starts from (engage_max_trans/rot): holding that pose
  CycleMismatch = 11,  ///< the KRC's sample time is not cycle_time_s: MON echo / CMD hold, nothing followed
  PortMismatch = 12,   ///< the KRC sends from another port than krc_port: MON echo / CMD hold
  DryRun = 13,         ///< CMD in a dry run: holding the pose where CMD was entered
  OffsetMismatch = 14, ///< the set point read under cart_offset is not a pose or lies farther than
                       ///< setpoint_max_dev(_rot) from the measured pose: MON echo of the measured
                       ///< pose / CMD hold, nothing followed
  KrcFault = 15,       ///< the KRC stopped the arm: it left CMD and braked the drives in the same
                       ///< packet (a $STIFFNESS.MAXFORCE / CPMAXDELTA stop or another KRC error, or
                       ///< robot.error set): MON echo, latched until CMD with the drives on again
  DroppedDuplicate = 16,   ///< same sendSeqCount as the last accepted packet: no reply
  DroppedOutOfOrder = 17,  ///< older sendSeqCount: no reply
  Malformed = 18,          ///< decode failed (see packet_status): no reply
  NotConfigured = 19
};
constexpr uint8_t kBridgeFirstNoReply = 16;
inline bool producesReply(BridgeStatus s) { return static_cast<uint8_t>(s) < kBridgeFirstNoReply; }
const char* toString(BridgeStatus s);

/// The KRL exchange with krc/TactileServo.src (its .dat's TS_* codes;
/// krc/check_krc_config.py compares them).
namespace krl {
/// $FRI_FRM_INT[1] (the command packets' krl.int_data[0]): the RT PC asks the
/// KRL program to end (TS_REQ_STOP): friStop, friClose, position control.
constexpr int32_t kRequestStop = 99;
/// $FRI_TO_INT[1] (the measurement packets' krl.int_data[0]): the program's step.
constexpr int32_t kProgramInit = 1;       ///< TS_ST_INIT
constexpr int32_t kProgramMonitor = 10;   ///< TS_ST_MONITOR: monitor mode, waiting for the link quality
constexpr int32_t kProgramConfirm = 15;   ///< TS_ST_CONFIRM: halted before friStart
constexpr int32_t kProgramCommand = 20;   ///< TS_ST_COMMAND: commanding
constexpr int32_t kProgramStopping = 25;  ///< TS_ST_STOPPING: PTP to the measured axes, friStop, friClose
constexpr int32_t kProgramClosed = 30;    ///< TS_ST_CLOSED
/// "init", "waiting_for_quality", "halted_before_start", "commanding",
/// "stopping", "closed", or "unknown" (another value: not this program).
const char* programStepName(int32_t step) noexcept;
}  // namespace krl

/// BridgeOutput::mismatch bits: the KRC disagrees with the configuration.
namespace mismatch {
constexpr uint8_t kCycle = 0x1;    ///< sample time != cycle_time_s
constexpr uint8_t kPort = 0x2;     ///< source port != krc_port
constexpr uint8_t kControl = 0x4;  ///< control strategy != Cartesian impedance
constexpr uint8_t kOffset = 0x8;   ///< the set point read under cart_offset does not fit the measured pose
}  // namespace mismatch

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
  uint8_t mismatch = 0;          ///< mismatch:: bits of this packet (0: the KRC agrees with the configuration)
  uint8_t limits = 0;            ///< limit:: bits that clipped this packet's command (status Limited), else 0
  int32_t krl_program = 0;       ///< the KRL program's step ($FRI_TO_INT[1], krl:: kProgram*) of this packet
  bool stop_requested = false;   ///< this reply asks the KRL program to end (requestStop())
  double krc_cycle_s = 0.0;      ///< the KRC's desiredMsrSampleTime of this packet (s)
  tactile::RobotState robot{};   ///< the robot state of this packet (valid for accepted packets)
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
  uint64_t limited = 0;             ///< commands clipped by any limit (status Limited)
  uint64_t limited_lin_speed = 0;   ///< ... by fri.max_lin_speed
  uint64_t limited_rot_speed = 0;   ///< ... by fri.max_rot_speed
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

  /// The UDP source port of the datagram about to be stepped (0: unknown,
  /// not checked). The transport knows it; the core compares it with krc_port.
  void notePeerPort(uint16_t port) noexcept { peer_port_ = port; }
  /// Bring-up dry run (see above). Takes effect at the next packet.
  void setDryRun(bool on) noexcept { dry_run_ = on; }
  bool dryRun() const noexcept { return dry_run_; }

  /// KRL exchange data sent with every command (zero by default; while a
  /// stop is requested its int_data[0] is krl::kRequestStop).
  void setKrlOut(const KrlData& krl) noexcept {
    krl_out_ = krl;
    if (stop_requested_) krl_out_.int_data[0] = krl::kRequestStop;
  }
  /// Asks the KRL program to end (a latched servo fault, the experiment's
  /// end): every reply from now on carries $FRI_FRM_INT[1] = krl::kRequestStop,
  /// until clearStopRequest() or configure(). reset() keeps it.
  void requestStop() noexcept {
    stop_requested_ = true;
    krl_out_.int_data[0] = krl::kRequestStop;
  }
  void clearStopRequest() noexcept {
    stop_requested_ = false;
    stop_cause_ = ServoStatus::Ok;
    krl_out_.int_data[0] = 0;
  }
  bool stopRequested() const noexcept { return stop_requested_; }
  /// The servo watchdog status that requested the stop (stop_krc_on_servo_fault);
  /// ServoStatus::Ok when none did (no request, or requestStop() alone).
  ServoStatus stopCause() const noexcept { return stop_cause_; }
  const BridgeStats& stats() const noexcept { return stats_; }
  const BridgeParams& params() const noexcept { return params_; }
  bool configured() const noexcept { return configured_; }
  /// The last decoded measurement (valid after a successful stepDatagram).
  const MsrPacket& lastMeasurement() const noexcept { return msr_; }

 private:
  void fillReply(const MsrPacket& msr, const KDL::Frame& pose, BridgeOutput& out) noexcept;
  BridgeStatus stepPacket(const MsrPacket& msr, const PoseCommand& desired, double now_s, BridgeOutput& out) noexcept;

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
  bool last_cmd_powered_ = false;  // the last accepted packet: CMD with the drives on
  bool krc_fault_ = false;         // sticky KrcFault
  uint16_t peer_port_ = 0;     // source port of the current datagram (0: unknown)
  bool dry_run_ = false;
  bool stop_requested_ = false;  // requestStop(): latched
  ServoStatus stop_cause_ = ServoStatus::Ok;  // the servo fault that requested it
  uint32_t cmd_flags_ = flags::kCartPose;  // chosen outside CMD, kept in CMD
  bool have_flags_ = false;                // cmd_flags_ chosen since reset()
  /// The command flags for the KRC's reported control strategy.
  uint32_t flagsFor(uint16_t control) const noexcept;
  /// mismatch:: bits of `msr` against the configuration.
  uint8_t checkConfig(const MsrPacket& msr) const noexcept;
  /// The KRC's set point read under cart_offset (the measured pose where the
  /// KRC sends no valid cmdCartPos); false (held: the measured pose) when it
  /// cannot be read or fails the set point check. Needs a valid measured pose.
  bool heldPose(const MsrPacket& msr, KDL::Frame& held) const noexcept;
  /// out.robot from the packet and this step's status.
  void fillRobotState(const MsrPacket& msr, double now_s, bool msr_valid, BridgeOutput& out) const noexcept;

  // The steps of stepPacket(), in order.
  /// The 16-bit sequence check: false (out.status DroppedDuplicate or
  /// DroppedOutOfOrder) when the packet is dropped; counts lost packets.
  bool acceptSequence(const MsrPacket& msr, BridgeOutput& out) noexcept;
  /// out.state, out.quality and out.state_changed against the last accepted packet.
  void trackState(const MsrPacket& msr, BridgeOutput& out) noexcept;
  /// MON / OFF / drives off: names the reason, echoes `held` (no reply on an invalid measurement).
  BridgeStatus echoOutsideCmd(const MsrPacket& msr, const KDL::Frame& held, bool msr_valid, BridgeOutput& out) noexcept;
  /// CMD with a non-Cartesian strategy or non-Cartesian flags: WrongStrategy,
  /// a hold with the flags chosen outside CMD.
  BridgeStatus strategyHold(const MsrPacket& msr, const KDL::Frame& held, bool msr_valid, BridgeOutput& out) noexcept;
  /// CMD: the limiter starts from `held` on the first command, or rewinds to the
  /// command the KRC reflects; false when there is no command and no valid measurement.
  bool startFromHeldCommand(const MsrPacket& msr, const KDL::Frame& held, bool msr_valid) noexcept;
  /// CMD: true with out.status set when the bridge holds its last command
  /// (measurement, configuration, quality, dry run, desired pose invalid or stale).
  bool holdStatus(const PoseCommand& desired, double now_s, bool msr_valid, BridgeOutput& out) noexcept;
  /// CMD: the start gate, then one rate-limited step towards the desired pose.
  BridgeStatus followDesired(const MsrPacket& msr, const PoseCommand& desired, double T, BridgeOutput& out) noexcept;
};

}  // namespace fri
}  // namespace tactile
