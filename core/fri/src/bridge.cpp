#include "tactile_fri/bridge.hpp"

#include <cmath>
#include <string>

namespace tactile {
namespace fri {

const char* krl::programStepName(int32_t step) noexcept {
  switch (step) {
    case kProgramInit: return "init";
    case kProgramMonitor: return "waiting_for_quality";
    case kProgramConfirm: return "halted_before_start";
    case kProgramCommand: return "commanding";
    case kProgramStopping: return "stopping";
    case kProgramClosed: return "closed";
    default: return "unknown";
  }
}

const char* limitNames(uint8_t bits) noexcept {
  switch (bits & (limit::kMaxLinSpeed | limit::kMaxRotSpeed)) {
    case limit::kMaxLinSpeed: return "max_lin_speed";
    case limit::kMaxRotSpeed: return "max_rot_speed";
    case limit::kMaxLinSpeed | limit::kMaxRotSpeed: return "max_lin_speed+max_rot_speed";
    default: return "";
  }
}

uint8_t PoseRateLimiter::step(const KDL::Frame& target, double dt) noexcept {
  uint8_t limited = 0;
  // Translation: |dp| <= v_max * dt.
  KDL::Vector dp = target.p - current_.p;
  const double dist = dp.Norm();
  const double max_dist = max_lin_ * dt;
  if (dist > max_dist) {
    dp = dp * (max_dist / dist);
    limited |= limit::kMaxLinSpeed;
  }
  current_.p = current_.p + dp;
  // Rotation: the relative rotation current^-1 * target as axis-angle; the
  // angle is clipped to w_max * dt about the same (body-fixed) axis.
  const KDL::Rotation rel = current_.M.Inverse() * target.M;
  KDL::Vector axis;
  const double angle = rotationAngle(rel, axis);  // [0, pi], unit axis
  const double max_angle = max_rot_ * dt;
  if (angle > max_angle) {
    current_.M = current_.M * KDL::Rotation::Rot2(axis, max_angle);
    limited |= limit::kMaxRotSpeed;
  } else {
    current_.M = target.M;
  }
  return limited;
}

const char* toString(BridgeStatus s) {
  switch (s) {
    case BridgeStatus::Commanding: return "commanding";
    case BridgeStatus::Limited: return "limited";
    case BridgeStatus::Monitor: return "monitor";
    case BridgeStatus::PowerOff: return "power_off";
    case BridgeStatus::LeftCmd: return "left_cmd";
    case BridgeStatus::QualityLow: return "quality_low";
    case BridgeStatus::DesiredInvalid: return "desired_invalid";
    case BridgeStatus::DesiredStale: return "desired_stale";
    case BridgeStatus::MeasurementInvalid: return "measurement_invalid";
    case BridgeStatus::WrongStrategy: return "wrong_strategy";
    case BridgeStatus::DesiredFar: return "desired_far";
    case BridgeStatus::CycleMismatch: return "cycle_mismatch";
    case BridgeStatus::PortMismatch: return "port_mismatch";
    case BridgeStatus::DryRun: return "dry_run";
    case BridgeStatus::OffsetMismatch: return "offset_mismatch";
    case BridgeStatus::KrcFault: return "krc_fault";
    case BridgeStatus::DroppedDuplicate: return "dropped_duplicate";
    case BridgeStatus::DroppedOutOfOrder: return "dropped_out_of_order";
    case BridgeStatus::Malformed: return "malformed";
    case BridgeStatus::NotConfigured: return "not_configured";
  }
  return "unknown";
}

namespace {
bool inRange(double v, double lo, double hi) { return std::isfinite(v) && v > lo && v <= hi; }
}  // namespace

ConfigResult FriBridge::configure(const BridgeParams& p) {
  configured_ = false;
  if (!inRange(p.max_lin_speed, 0.0, 2.0))
    return rangeError("fri.max_lin_speed", p.max_lin_speed, "must be in (0, 2] (m/s)");
  if (!inRange(p.max_rot_speed, 0.0, 3.0))
    return rangeError("fri.max_rot_speed", p.max_rot_speed, "must be in (0, 3] (rad/s)");
  if (!inRange(p.cycle_time_s, 0.0, 0.1))
    return rangeError("fri.cycle_time_s", p.cycle_time_s, "must be in (0, 0.1] (s): the KRC's cycle, friOpen's argument");
  if (p.krc_port < 0 || p.krc_port > 65535)
    return rangeError("fri.udp.krc_port", p.krc_port, "must be in [0, 65535] (0 = any)");
  if (!inRange(p.max_desired_age_s, 0.0, 10.0))
    return rangeError("fri.max_desired_age_s", p.max_desired_age_s, "must be in (0, 10] (s)");
  if (!inRange(p.engage_max_trans, 0.0, 0.1))
    return rangeError("fri.engage_max_trans", p.engage_max_trans, "must be in (0, 0.1] (m)");
  if (!inRange(p.engage_max_rot, 0.0, 0.5))
    return rangeError("fri.engage_max_rot", p.engage_max_rot, "must be in (0, 0.5] (rad)");
  if (p.cart_offset != CartOffset::None && p.cart_offset != CartOffset::Composed &&
      p.cart_offset != CartOffset::Elementwise)
    return rangeError("fri.cart_offset", static_cast<int>(p.cart_offset), "must be none, composed or elementwise");
  if (!inRange(p.setpoint_max_dev, 0.0, 1.0))
    return rangeError("fri.setpoint_max_dev", p.setpoint_max_dev, "must be in (0, 1] (m)");
  if (!inRange(p.setpoint_max_dev_rot, 0.0, 3.2))
    return rangeError("fri.setpoint_max_dev_rot", p.setpoint_max_dev_rot, "must be in (0, 3.2] (rad)");
  if (p.resync_after < 1 || p.resync_after > 1000)
    return rangeError("fri.resync_after", p.resync_after, "must be in [1, 1000] (packets)");
  for (int i = 0; i < 6; ++i) {
    const double k = p.cart_stiffness[static_cast<std::size_t>(i)];
    const double kmax = i < 3 ? 5000.0 : 300.0;
    if (!(std::isfinite(k) && k >= 0.01 && k <= kmax))
      return rangeError("fri.cart_stiffness[" + std::to_string(i) + "]", k,
                        i < 3 ? "must be in [0.01, 5000] (N/m)" : "must be in [0.01, 300] (N m/rad)");
    const double d = p.cart_damping[static_cast<std::size_t>(i)];
    if (!(std::isfinite(d) && d >= 0.1 && d <= 1.0))
      return rangeError("fri.cart_damping[" + std::to_string(i) + "]", d, "must be in [0.1, 1.0] (normalised)");
  }
  params_ = p;
  clearStopRequest();
  limiter_.setLimits(p.max_lin_speed, p.max_rot_speed);
  configured_ = true;
  reset();
  return ConfigResult::success();
}

void FriBridge::reset() noexcept {
  stats_ = BridgeStats{};
  have_seq_ = false;
  last_seq_ = 0;
  backwards_run_ = 0;
  send_seq_ = 0;
  have_state_ = false;
  last_state_ = State::Off;
  last_quality_ = Quality::Unacceptable;
  have_command_ = false;
  engaged_ = false;
  was_in_cmd_ = false;
  last_cmd_powered_ = false;
  krc_fault_ = false;
  have_flags_ = false;
  cmd_flags_ = flags::kCartPose;
  sent_valid_.fill(false);
}

uint32_t FriBridge::flagsFor(uint16_t control) const noexcept {
  if (control != static_cast<uint16_t>(ControlStrategy::CartImpedance)) return flags::kJointPosition;
  uint32_t f = flags::kCartPose;
  if (params_.command_impedance) f |= flags::kCartStiffness | flags::kCartDamping;
  return f;
}

void FriBridge::fillReply(const MsrPacket& msr, const KDL::Frame& pose, BridgeOutput& out) noexcept {
  CmdPacket& c = out.cmd;
  c.head.send_seq = ++send_seq_;
  c.head.refl_seq = msr.head.send_seq;
  c.head.packet_size = static_cast<uint16_t>(kCmdPacketSize);
  c.head.datagram_id = kDatagramIdCmd;
  c.krl = krl_out_;
  RobotCommand& r = c.cmd;
  r.cmd_flags = cmd_flags_;
  fromFrame(pose, r.cart_pos);
  for (int j = 0; j < kNumJoints; ++j) {
    r.jnt_pos[j] = msr.data.cmd_jnt_pos[j] + msr.data.cmd_jnt_pos_fri_offset[j];
    r.add_jnt_trq[j] = 0.0f;
    r.jnt_stiffness[j] = 0.0f;
    r.jnt_damping[j] = 0.0f;
  }
  for (int i = 0; i < kCartVecDim; ++i) {
    r.add_tcp_ft[i] = 0.0f;
    r.cart_stiffness[i] = static_cast<float>(params_.cart_stiffness[static_cast<std::size_t>(i)]);
    r.cart_damping[i] = static_cast<float>(params_.cart_damping[static_cast<std::size_t>(i)]);
  }
  const std::size_t slot = static_cast<std::size_t>(send_seq_ % kRing);
  sent_pose_[slot] = pose;
  sent_seq_[slot] = send_seq_;
  sent_valid_[slot] = true;
  out.reply = true;
  out.commanded = pose;
  ++stats_.replies;
}

BridgeStatus FriBridge::stepDatagram(const uint8_t* data, std::size_t size, const PoseCommand& desired,
                                     double now_s, BridgeOutput& out) noexcept {
  out.packet_status = decodeMeasurement(data, size, msr_);
  if (out.packet_status != PacketStatus::Ok) {
    ++stats_.received;
    ++stats_.malformed;
    out.reply = false;
    out.state_changed = false;
    out.lost_before = 0;
    out.status = configured_ ? BridgeStatus::Malformed : BridgeStatus::NotConfigured;
    return out.status;
  }
  return step(msr_, desired, now_s, out);
}

bool FriBridge::heldPose(const MsrPacket& msr, KDL::Frame& held) const noexcept {
  KDL::Frame measured;
  toFrame(msr.data.msr_cart_pos, measured);
  held = measured;
  if (!validFriPose(msr.data.cmd_cart_pos)) return true;  // no set point sent: the measured pose
  KDL::Frame sp;
  if (!readSetPoint(msr.data.cmd_cart_pos, msr.data.cmd_cart_pos_fri_offset, params_.cart_offset, sp)) return false;
  KDL::Vector axis;
  if (!((sp.p - measured.p).Norm() <= params_.setpoint_max_dev) ||
      !(rotationAngle(measured.M.Inverse() * sp.M, axis) <= params_.setpoint_max_dev_rot))
    return false;
  held = sp;
  return true;
}

uint8_t FriBridge::checkConfig(const MsrPacket& msr) const noexcept {
  // The KRC's cycles are whole milliseconds sent as float seconds: 1e-5 s
  // tells 1 ms from 2 ms and ignores the float's rounding (1e-10 s).
  constexpr double kCycleTol = 1e-5;
  const auto off = [&](float t) {
    return !(std::fabs(static_cast<double>(t) - params_.cycle_time_s) <= kCycleTol);
  };
  uint8_t m = 0;
  if (off(msr.intf.desired_msr_sample_time) || off(msr.intf.desired_cmd_sample_time)) m |= mismatch::kCycle;
  if (params_.krc_port != 0 && peer_port_ != 0 && peer_port_ != params_.krc_port) m |= mismatch::kPort;
  if (msr.robot.control != static_cast<uint16_t>(ControlStrategy::CartImpedance)) m |= mismatch::kControl;
  return m;
}

void FriBridge::fillRobotState(const MsrPacket& msr, double now_s, bool msr_valid, BridgeOutput& out) const noexcept {
  tactile::RobotState& r = out.robot;
  r.time_s = now_s;
  const State st = stateOf(msr);
  r.mode = st == State::Cmd ? RobotMode::Command : (st == State::Mon ? RobotMode::Monitor : RobotMode::Off);
  r.quality = static_cast<int>(qualityOf(msr));
  r.power_on = powerOn(msr);
  r.cartesian_impedance = msr.robot.control == static_cast<uint16_t>(ControlStrategy::CartImpedance);
  r.config_ok = out.mismatch == 0;
  r.dry_run = dry_run_;
  r.commandable = r.mode == RobotMode::Command && r.power_on && qualityOf(msr) >= Quality::Ok &&
                  r.cartesian_impedance && (cmd_flags_ & flags::kCartPose) != 0 && r.config_ok && !dry_run_ &&
                  msr_valid;
  r.link_status = static_cast<int>(out.status);
  for (int j = 0; j < kNumJoints && j < kArmJoints; ++j)
    r.q[static_cast<std::size_t>(j)] = static_cast<double>(msr.data.msr_jnt_pos[j]);
  KDL::Frame held;
  if (msr_valid && !(out.mismatch & mismatch::kOffset) && heldPose(msr, held)) toPose(held, r.setpoint);
  else r.setpoint = kNoPose;
}

BridgeStatus FriBridge::step(const MsrPacket& msr, const PoseCommand& desired, double now_s,
                             BridgeOutput& out) noexcept {
  out.mismatch = 0;
  out.limits = 0;
  out.krl_program = msr.krl.int_data[0];
  if (configured_ && params_.stop_krc_on_servo_fault && !stop_requested_ && watchdogStatus(desired.status)) {
    requestStop();  // a latched servo fault: the KRL program ends (friStop), this reply on
    stop_cause_ = desired.status;
  }
  out.stop_requested = stop_requested_;
  out.krc_cycle_s = static_cast<double>(msr.intf.desired_msr_sample_time);
  const BridgeStatus st = stepPacket(msr, desired, now_s, out);
  if (st != BridgeStatus::DroppedDuplicate && st != BridgeStatus::DroppedOutOfOrder && st != BridgeStatus::Malformed &&
      st != BridgeStatus::NotConfigured)
    fillRobotState(msr, now_s, validFriPose(msr.data.msr_cart_pos), out);
  return st;
}

BridgeStatus FriBridge::stepPacket(const MsrPacket& msr, const PoseCommand& desired, double now_s,
                                   BridgeOutput& out) noexcept {
  out.reply = false;
  out.state_changed = false;
  out.lost_before = 0;
  ++stats_.received;
  if (!configured_) return out.status = BridgeStatus::NotConfigured;
  if (msr.intf.state > static_cast<uint16_t>(State::Cmd) ||
      msr.intf.quality > static_cast<uint16_t>(Quality::Perfect)) {
    ++stats_.malformed;
    out.packet_status = msr.intf.state > 2 ? PacketStatus::BadState : PacketStatus::BadQuality;
    return out.status = BridgeStatus::Malformed;
  }
  if (!acceptSequence(msr, out)) return out.status;
  trackState(msr, out);

  const bool msr_valid = validFriPose(msr.data.msr_cart_pos);
  // What the arm holds outside CMD: the KRC's set point (cmdCartPos, with
  // cmdCartPosFriOffset where valid), else the measured pose. Echoed there and
  // where a (re)entry into CMD starts: neither the set point nor a pressing
  // contact's force jumps.
  KDL::Frame held = KDL::Frame::Identity();
  const bool held_read = !msr_valid || heldPose(msr, held);
  const double krc_T = static_cast<double>(msr.intf.desired_cmd_sample_time);
  const double T = (std::isfinite(krc_T) && krc_T > 0.0 && krc_T <= 0.1) ? krc_T : params_.cycle_time_s;
  out.mismatch = checkConfig(msr);
  if (!held_read) out.mismatch |= mismatch::kOffset;
  // Command flags: chosen outside CMD (or on a session's first packet), never changed in CMD.
  if (out.state != State::Cmd || !have_flags_) {
    cmd_flags_ = flagsFor(msr.robot.control);
    have_flags_ = true;
  }

  if (out.state != State::Cmd || !powerOn(msr)) return echoOutsideCmd(msr, held, msr_valid, out);

  // ---- CMD, powered ----
  was_in_cmd_ = true;
  if (msr.robot.control != static_cast<uint16_t>(ControlStrategy::CartImpedance) ||
      !(cmd_flags_ & flags::kCartPose))
    return strategyHold(msr, held, msr_valid, out);
  if (!startFromHeldCommand(msr, held, msr_valid)) return out.status = BridgeStatus::MeasurementInvalid;
  if (!holdStatus(desired, now_s, msr_valid, out)) return followDesired(msr, desired, T, out);
  ++stats_.holds;  // hold: repeat the last command unchanged
  fillReply(msr, limiter_.current(), out);
  return out.status;
}

bool FriBridge::acceptSequence(const MsrPacket& msr, BridgeOutput& out) noexcept {
  // ---- sequence check (16-bit wrap-around) ----
  const uint16_t seq = msr.head.send_seq;
  if (have_seq_) {
    const int d = seqDelta(last_seq_, seq);
    if (d <= 0) {
      if (d == 0) {
        ++stats_.duplicates;
        out.status = BridgeStatus::DroppedDuplicate;
        return false;
      }
      if (++backwards_run_ < params_.resync_after) {
        ++stats_.out_of_order;
        out.status = BridgeStatus::DroppedOutOfOrder;
        return false;
      }
      ++stats_.resyncs;  // the KRC restarted its counter: accept the new sequence
    } else {
      out.lost_before = static_cast<uint16_t>(d - 1);
      stats_.lost += static_cast<uint64_t>(d - 1);
    }
  }
  have_seq_ = true;
  last_seq_ = seq;
  backwards_run_ = 0;
  ++stats_.accepted;
  return true;
}

void FriBridge::trackState(const MsrPacket& msr, BridgeOutput& out) noexcept {
  // ---- state and quality ----
  const State state = stateOf(msr);
  const Quality quality = qualityOf(msr);
  out.state = state;
  out.quality = quality;
  out.state_changed = !have_state_ || state != last_state_ || quality != last_quality_;
  have_state_ = true;
  last_state_ = state;
  last_quality_ = quality;
  // The KRC's own stop (MAXFORCE, CPMAXDELTA, a drive error): command mode
  // left and the drives braked in one step, or robot.error set.
  const bool cmd_powered = state == State::Cmd && powerOn(msr);
  if ((last_cmd_powered_ && state != State::Cmd && !powerOn(msr)) || msr.robot.error != 0) krc_fault_ = true;
  if (cmd_powered && msr.robot.error == 0) krc_fault_ = false;
  last_cmd_powered_ = cmd_powered;
}

BridgeStatus FriBridge::echoOutsideCmd(const MsrPacket& msr, const KDL::Frame& held, bool msr_valid,
                                       BridgeOutput& out) noexcept {
  // MON / OFF / power off: echo the held pose; (re)entering CMD passes the start gate again.
  engaged_ = false;
  if (out.mismatch & mismatch::kCycle) {  // named in MON too: never silent
    out.status = BridgeStatus::CycleMismatch;
  } else if (out.mismatch & mismatch::kPort) {
    out.status = BridgeStatus::PortMismatch;
  } else if (out.mismatch & mismatch::kOffset) {
    out.status = BridgeStatus::OffsetMismatch;
  } else if (out.mismatch & mismatch::kControl) {
    out.status = BridgeStatus::WrongStrategy;
  } else if (krc_fault_) {
    out.status = BridgeStatus::KrcFault;
  } else if (out.state != State::Cmd && was_in_cmd_) {
    out.status = BridgeStatus::LeftCmd;
  } else if (!powerOn(msr)) {
    out.status = BridgeStatus::PowerOff;
  } else {
    out.status = BridgeStatus::Monitor;
  }
  if (!msr_valid) {
    have_command_ = false;
    return out.status = BridgeStatus::MeasurementInvalid;
  }
  limiter_.reset(held);
  have_command_ = true;
  fillReply(msr, held, out);
  return out.status;
}

BridgeStatus FriBridge::strategyHold(const MsrPacket& msr, const KDL::Frame& held, bool msr_valid,
                                     BridgeOutput& out) noexcept {
  out.status = BridgeStatus::WrongStrategy;
  engaged_ = false;
  if (!msr_valid) {
    have_command_ = false;
    return out.status = BridgeStatus::MeasurementInvalid;
  }
  if (!(cmd_flags_ & flags::kCartPose) || !have_command_) {
    // joint flags: the KRC's joint set point (jntPos); the Cartesian field
    // carries the held pose, from where a later Cartesian session starts
    limiter_.reset(held);
    have_command_ = true;
  } else {
    ++stats_.holds;  // Cartesian flags kept in CMD: repeat the last command
  }
  fillReply(msr, limiter_.current(), out);
  return out.status;
}

bool FriBridge::startFromHeldCommand(const MsrPacket& msr, const KDL::Frame& held, bool msr_valid) noexcept {
  if (!have_command_) {
    if (!msr_valid) return false;
    limiter_.reset(held);  // first command ever: start where the robot is held
    have_command_ = true;
  } else if (params_.rewind_on_refl && msr.head.refl_seq != send_seq_) {
    // The KRC did not get our latest command(s): continue from the one it holds.
    const uint16_t refl = msr.head.refl_seq;
    const int behind = seqDelta(refl, send_seq_);
    const std::size_t slot = static_cast<std::size_t>(refl % kRing);
    if (behind > 0 && behind < kRing && sent_valid_[slot] && sent_seq_[slot] == refl) {
      limiter_.reset(sent_pose_[slot]);
      ++stats_.rewinds;
    }
  }
  return true;
}

bool FriBridge::holdStatus(const PoseCommand& desired, double now_s, bool msr_valid, BridgeOutput& out) noexcept {
  const double age = now_s - desired.time_s;
  if (!msr_valid) {
    out.status = BridgeStatus::MeasurementInvalid;
  } else if (out.mismatch & (mismatch::kCycle | mismatch::kPort | mismatch::kOffset)) {
    out.status = (out.mismatch & mismatch::kCycle)  ? BridgeStatus::CycleMismatch
                 : (out.mismatch & mismatch::kPort) ? BridgeStatus::PortMismatch
                                                    : BridgeStatus::OffsetMismatch;
    engaged_ = false;
  } else if (out.quality < Quality::Ok) {
    out.status = BridgeStatus::QualityLow;
    engaged_ = false;  // the servo held meanwhile: the gate again before following
  } else if (dry_run_) {
    out.status = BridgeStatus::DryRun;
    engaged_ = false;
  } else if (desired.status == ServoStatus::NotConfigured || desired.status == ServoStatus::WaitingForPose ||
             !validPose(desired.pose)) {
    out.status = BridgeStatus::DesiredInvalid;
    engaged_ = false;
  } else if (!(std::fabs(age) <= params_.max_desired_age_s)) {
    out.status = BridgeStatus::DesiredStale;
    engaged_ = false;
  } else {
    return false;
  }
  return true;
}

BridgeStatus FriBridge::followDesired(const MsrPacket& msr, const PoseCommand& desired, double T,
                                      BridgeOutput& out) noexcept {
  KDL::Frame target;
  toFrame(desired.pose, target);
  if (!engaged_) {
    // Start gate: follow only a desired pose within one program step of the
    // pose held now (the held pose at the start of the session/CMD).
    KDL::Vector axis;
    const KDL::Frame& from = limiter_.current();
    const double d = (target.p - from.p).Norm();
    const double a = rotationAngle(from.M.Inverse() * target.M, axis);
    engaged_ = d <= params_.engage_max_trans && a <= params_.engage_max_rot;
  }
  if (!engaged_) {
    out.status = BridgeStatus::DesiredFar;
    ++stats_.holds;
    fillReply(msr, limiter_.current(), out);
    return out.status;
  }
  const uint8_t limited = limiter_.step(target, T);
  out.limits = limited;
  if (limited) ++stats_.limited;
  if (limited & limit::kMaxLinSpeed) ++stats_.limited_lin_speed;
  if (limited & limit::kMaxRotSpeed) ++stats_.limited_rot_speed;
  out.status = limited ? BridgeStatus::Limited : BridgeStatus::Commanding;
  fillReply(msr, limiter_.current(), out);
  return out.status;
}

}  // namespace fri
}  // namespace tactile
