// The KUKA KRC's side of FRI, clock-free: what the controller cabinet puts in
// each measurement packet and what it does with each command reply. One model
// for both simulated KRCs: the headless runner's (tactile_sim run
// --through-fri, bytes through tactile::fri::FriBridge in-process) and the
// UDP test peer tactile::fri::SimKrc (which adds the transport, the pacing and
// the fault injection around it). Time is passed in; nothing here reads a
// clock, allocates or throws per cycle.
//
// Per cycle:
//   1. setState(): the interface state / quality / drive power of the cycle
//      (leaving CMD makes the next applied command an "entry" again);
//   2. holdUnlessCommanding(measured): outside CMD (or with the drives off) the
//      robot holds still: the set point is the measured pose until a command
//      was applied, the KRC's own set point afterwards;
//   3. the plant moves toward setPoint();
//   4. buildMeasurement(): header (sendSeqCount + 1, reflSeqCount = the last
//      command taken), timestamp (ms of `t`), state, quality, sample times,
//      control strategy, measured joints / pose / wrench, the current set point
//      in the form KrcModelParams::cart_offset says (cmdCartPos and
//      cmdCartPosFriOffset, protocol.hpp writeSetPoint: the KRL program's own
//      pose is the set point it held before the first applied command);
//      the wrench in the axes KrcModelParams::wrench_frame says;
//   5. handleReply(): decode; the remote's sendSeqCount must grow by one; a
//      reply whose reflSeqCount is not this cycle's measurement is stale
//      (ignored, as the KRC does); in CMD with the drives on and quality >= OK
//      a finite Cartesian command (flag 0x100 under Cartesian impedance) becomes
//      the set point (step statistics, "no pose jump"); in MON the reply must
//      echo the set point.
//
// Command flags: the remote chooses them in monitor mode; in command mode
// they must stay what they were when command mode was entered (KUKA's
// friremote.cpp changes them in monitor mode only). A reply in CMD with other
// flags is refused as a real KRC does: not applied, counted (flag_changes,
// and flag_errors), and the KRC drops to monitor mode and stays there
// (refused(): the operator acknowledges the error and restarts the
// program: reset()).
//
// The KRL program's exchange (krc/TactileServo.src): each measurement
// carries the program's step in krl.int_data[0] ($FRI_TO_INT[1]: 10 in
// monitor mode, 20 in command mode, 30 once ended); a reply whose
// krl.int_data[0] is 99 ($FRI_FRM_INT[1] = TS_REQ_STOP) ends the program:
// friStop (monitor mode, whatever the script says afterwards) and the step
// 30 (stopRequested(); until reset()).
//
// The link quality from timing (KrcQualityRule, on when enabled): the caller
// reports each open cycle's answer (noteAnswer(): a matching reply or none,
// and its latency); over the last `window` cycles the share of missed or late
// answers gives the quality (PERFECT / OK / BAD / UNACCEPTABLE); the KRC
// reports the lower of it and the script's quality. In command mode a
// quality below OK makes the KRC leave command mode (monitor mode, counted in
// quality_drops); the script's command mode is entered, and re-entered after
// such a drop, only at PERFECT (the KRL program waits for PERFECT before
// friStart, krc/TactileServo.src step 6).
//
// The $STIFFNESS limits (KrcStiffnessLimits, on when set): in command mode
// with the drives on, an estimated external TCP force/torque component beyond
// MAXFORCE, or a deviation of the measured pose from the KRC's set point
// beyond CPMAXDELTA, is a KRC fault: the KRC stops taking commands, brakes the
// drives (power 0, the set point frozen at the measured pose) and leaves
// command mode in the same cycle, until reset() (fault()).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <kdl/frames.hpp>

#include "tactile_fri/protocol.hpp"
#include "tactile_types/config_result.hpp"
#include "tactile_types/types.hpp"

namespace tactile {
namespace fri {

/// What the simulated KRC reads back from the robot.
struct PlantState {
  std::array<double, kNumJoints> q{};     ///< measured joint positions (rad)
  KDL::Frame pose = KDL::Frame::Identity();  ///< measured {g}T{e}
  std::array<double, 6> wrench{};         ///< estimated external TCP wrench [Fx Fy Fz Tx Ty Tz] (N, N m)
};

/// The quality from the answers' timing. KUKA's friComm.h: the KRC's link
/// statistics (answerRate, latency, missRate) are "average rating over the
/// last 100 packets": the window. The shares per level are this project's
/// reading (the thresholds KUKA's controller uses are not public): PERFECT
/// while at most perfect_max of the window's answers were missed or late,
/// OK up to ok_max, BAD up to bad_max, UNACCEPTABLE beyond.
struct KrcQualityRule {
  bool enabled = false;
  uint32_t window = 100;       ///< cycles, [1, kMaxWindow]
  double late_fraction = 0.8;  ///< an answer later than this share of the cycle counts as late, (0, 1]
  double perfect_max = 0.02;   ///< share of missed/late answers still PERFECT, [0, 1]
  double ok_max = 0.10;        ///< ... still OK (>= perfect_max)
  double bad_max = 0.30;       ///< ... still BAD (>= ok_max); beyond: UNACCEPTABLE
  static constexpr uint32_t kMaxWindow = 1000;
};

/// $STIFFNESS.MAXFORCE and $STIFFNESS.CPMAXDELTA as the KRC applies them (the
/// values the KRL program writes, krc/TactileServo.src). 0 in a component:
/// not checked. Components: [X Y Z A B C]; A about z, B about y, C about x of
/// the base (our reading of KUKA's ABC order for the deviation's rotation).
struct KrcStiffnessLimits {
  std::array<double, 6> max_force{};     ///< |estExtTcpFT| per component (N, N m)
  std::array<double, 6> cp_max_delta{};  ///< |set point - measured| per component (m, rad)
  bool any() const {
    for (std::size_t i = 0; i < 6; ++i)
      if (max_force[i] > 0.0 || cp_max_delta[i] > 0.0) return true;
    return false;
  }
};

/// Why the KRC stopped the arm (KrcModel::fault()).
enum class KrcFault : uint8_t { None = 0, MaxForce = 1, CpMaxDelta = 2 };
/// "none", "maxforce", "cpmaxdelta".
const char* toString(KrcFault f);

struct KrcModelParams {
  double period_s = 0.001;  ///< the KRC's measurement / command sample time (s), (0, 0.1]
  KrcQualityRule quality_rule{};
  KrcStiffnessLimits limits{};
  ControlStrategy control = ControlStrategy::CartImpedance;
  /// The form in which the set point is sent: None (cmdCartPos is the set
  /// point, the offset zero), Composed or Elementwise (cmdCartPos the KRL
  /// program's pose, the offset the FRI's part).
  CartOffset cart_offset = CartOffset::None;
  /// The axes of estExtTcpFT, as the KRC's $STIFFNESS.FRAMETYPE says
  /// (krl_settings.hpp reads it from the KRL program): the plant's wrench
  /// ({g} axes) is sent in base axes, or turned into the measured flange's.
  WrenchFrame wrench_frame = WrenchFrame::Base;
};

struct KrcModelStats {
  uint64_t replies = 0;           ///< replies matching the cycle's sendSeqCount
  uint64_t stale_replies = 0;     ///< well-formed replies reflecting an older measurement
  uint64_t malformed_replies = 0; ///< wrong size / id
  uint64_t remote_seq_errors = 0; ///< the remote's sendSeqCount did not increase by exactly 1
  uint64_t flag_errors = 0;       ///< CMD reply without the flag the strategy needs, or with changed flags
  uint64_t flag_changes = 0;      ///< CMD replies whose flags differ from those at CMD entry (refused)
  uint64_t nonfinite_commands = 0;
  uint64_t applied = 0;           ///< commands applied (CMD, quality >= OK)
  uint64_t mon_echo_errors = 0;   ///< MON/power-off replies whose pose differs from the KRC's set point by > 1e-5
  double max_cmd_step_m = 0.0;    ///< largest translation between consecutive applied commands
  double max_cmd_step_rad = 0.0;  ///< largest rotation between consecutive applied commands
  double max_entry_offset_m = 0.0;   ///< first applied command after entering CMD vs the set point the KRC held
  double max_entry_offset_rad = 0.0;
  uint64_t answers_missed = 0;    ///< noteAnswer(): cycles without a matching reply
  uint64_t answers_late = 0;      ///< noteAnswer(): matching replies later than late_fraction of the cycle
  uint64_t quality_drops = 0;     ///< command mode left because the quality fell below OK
  uint64_t faults = 0;            ///< MAXFORCE / CPMAXDELTA faults (0 or 1: latched until reset())
  std::array<uint64_t, 4> quality_cycles{};  ///< measurements sent at each quality (UNACCEPTABLE..PERFECT)
};

enum class ReplyResult : uint8_t { Matched = 0, Stale = 1, Malformed = 2 };

/// One step of a KRC's script, at a time (s): KRL's own calls and the link's
/// changes.
struct KrcEvent {
  enum class Kind : uint8_t {
    FriOpen,   ///< friOpen: the link opens in monitor mode
    FriStart,  ///< friStart: command mode
    FriStop,   ///< friStop: back to monitor mode
    FriClose,  ///< friClose: the KRC stops sending
    Quality,   ///< the link quality changes (quality=BAD)
    Power      ///< the drives go off / on (power=off)
  };
  double t_s = 0.0;
  Kind kind = Kind::FriOpen;
  Quality quality = Quality::Perfect;  ///< Kind::Quality
  bool power = true;                   ///< Kind::Power
};

/// A KRC's script over a run: what the KRL program and the link do when,
/// e.g. "0:friOpen,1.0:friStart,6:quality=BAD,6.3:quality=PERFECT,8:friStop,
/// 8.5:friStart" (times in s, increasing; words as in KRL: friOpen, friStart,
/// friStop, friClose; quality=UNACCEPTABLE|BAD|OK|PERFECT; power=off|on).
/// Before its first event the KRC is silent (closed). The empty script is
/// "0:friOpen,0:friStart" at perfect quality: command mode from the start.
/// Used by the simulated KRCs (the headless runner, the simulated arm
/// component, lab_sim); parse() allocates, at() does not.
class KrcScript {
 public:
  /// Parses `spec`; errors name `where` (file and key), the item and what is valid.
  ConfigResult parse(const std::string& spec, const std::string& where);
  /// The KRC at time t: open (sending), interface state, quality, drives.
  struct At {
    bool open = false;
    State state = State::Off;
    Quality quality = Quality::Perfect;
    bool power = true;
  };
  At at(double t_s) const;
  bool empty() const { return events_.empty(); }
  const std::vector<KrcEvent>& events() const { return events_; }

 private:
  std::vector<KrcEvent> events_;
};

/// The RobotState a simulated arm behind `krc` reports (the FRI bridge's
/// rule, bridge.hpp, for a KRC that agrees with the configuration): closed
/// or OFF -> Off, MON, CMD; commandable in CMD with the drives on and quality
/// >= OK. Joints are left to the caller.
void robotStateOf(const KrcScript::At& krc, double t_s, tactile::RobotState& out);

class KrcModel {
 public:
  ConfigResult configure(const KrcModelParams& params);
  /// Start: no packet exchanged yet, the set point at `pose`, statistics cleared.
  void reset(const KDL::Frame& pose);

  /// The script's state, quality and drives (the KRC applies the timing rule,
  /// a refusal, a stop request and a fault on top: state(), quality()).
  void setState(State state, Quality quality, uint16_t power);
  /// One open cycle's answer, after its reply wait: `answered` a reply matched
  /// this cycle's measurement, `latency_s` its latency (0 where the transport
  /// does not measure it). Updates the timing quality (quality_rule) and the
  /// state. With the rule the timing quality starts UNACCEPTABLE (nothing answered
  /// yet); without it, it stays PERFECT.
  void noteAnswer(bool answered, double latency_s);
  /// Outside CMD (or drives off) the set point follows the measured pose
  /// until a command was first applied; afterwards the KRC keeps it (friStop,
  /// a quality drop or braked drives keep a pressing contact's force).
  void holdUnlessCommanding(const KDL::Frame& measured);
  /// The next measurement packet from the measured plant state at time t (s).
  void buildMeasurement(const PlantState& plant, double t_s, MsrPacket& out);
  /// One reply datagram (a size beyond the buffer is passed as such: decoding rejects it).
  ReplyResult handleReply(const uint8_t* data, std::size_t size);

  const KDL::Frame& setPoint() const { return set_point_; }
  State state() const { return state_; }
  Quality quality() const { return quality_; }
  uint16_t power() const { return power_; }
  uint16_t sendSeq() const { return seq_; }
  const KrcModelStats& stats() const { return stats_; }
  const MsrPacket& lastMeasurement() const { return msr_; }
  const CmdPacket& lastCommand() const { return cmd_; }
  /// The KRC refused a change of command flags in CMD and left command mode
  /// (monitor mode until reset()).
  bool refused() const { return refused_; }
  /// The RT PC asked the KRL program to end (krl.int_data[0] = 99): it left
  /// command mode and reports the step 30 (closed) until reset().
  bool stopRequested() const { return stop_requested_; }
  /// MAXFORCE / CPMAXDELTA fault: the KRC stopped the arm (until reset()).
  KrcFault fault() const { return fault_; }
  /// The quality the answers' timing alone gives (PERFECT with the rule off).
  Quality timingQuality() const { return timing_quality_; }

 private:
  void applyState();
  void checkLimits(const PlantState& plant);
  KrcModelParams params_{};
  KrcModelStats stats_{};
  State state_ = State::Mon;
  Quality quality_ = Quality::Perfect;
  uint16_t power_ = 0x7F;
  uint16_t seq_ = 0;
  uint16_t last_remote_seq_ = 0;       // last command taken (matching reply): reflected
  uint16_t last_seen_remote_seq_ = 0;  // last well-formed command seen (sequence check)
  bool have_remote_seq_ = false;
  bool have_applied_ = false;
  bool ever_applied_ = false;  // a command was applied since reset(): the set point is the KRC's own
  uint32_t flags_ = 0;         // the flags of the last reply outside CMD (kept on entering CMD)
  bool have_flags_ = false;
  bool refused_ = false;       // a flag change in CMD: monitor mode until reset()
  bool stop_requested_ = false;  // the RT PC's stop request: the program ended
  State script_state_ = State::Mon;      // setState()'s, before the rules
  Quality script_quality_ = Quality::Perfect;
  uint16_t script_power_ = 0x7F;
  Quality timing_quality_ = Quality::Perfect;
  std::array<uint8_t, KrcQualityRule::kMaxWindow> answer_ring_{};  // 1: missed or late
  uint32_t ring_pos_ = 0;
  uint32_t ring_bad_ = 0;  // ones in the window
  KrcFault fault_ = KrcFault::None;
  KDL::Frame set_point_ = KDL::Frame::Identity();
  KDL::Frame krl_pose_ = KDL::Frame::Identity();  // the KRL program's own pose (cmdCartPos unless form None)
  KDL::Frame last_applied_ = KDL::Frame::Identity();
  MsrPacket msr_{};
  CmdPacket cmd_{};
};

}  // namespace fri
}  // namespace tactile
