#include "tactile_fri/bridge.hpp"

#include <cmath>
#include <string>

namespace tactile {
namespace fri {

bool PoseRateLimiter::step(const KDL::Frame& target, double dt) noexcept {
  bool limited = false;
  // Translation: |dp| <= v_max * dt.
  KDL::Vector dp = target.p - current_.p;
  const double dist = dp.Norm();
  const double max_dist = max_lin_ * dt;
  if (dist > max_dist) {
    dp = dp * (max_dist / dist);
    limited = true;
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
    limited = true;
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
  if (!inRange(p.nominal_period_s, 0.0, 0.1))
    return rangeError("fri.nominal_period_s", p.nominal_period_s, "must be in (0, 0.1] (s)");
  if (!inRange(p.max_desired_age_s, 0.0, 10.0))
    return rangeError("fri.max_desired_age_s", p.max_desired_age_s, "must be in (0, 10] (s)");
  if (!inRange(p.engage_max_trans, 0.0, 0.1))
    return rangeError("fri.engage_max_trans", p.engage_max_trans, "must be in (0, 0.1] (m)");
  if (!inRange(p.engage_max_rot, 0.0, 0.5))
    return rangeError("fri.engage_max_rot", p.engage_max_rot, "must be in (0, 0.5] (rad)");
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
  sent_valid_.fill(false);
}

void FriBridge::fillReply(const MsrPacket& msr, const KDL::Frame& pose, BridgeOutput& out, bool joint_hold) noexcept {
  CmdPacket& c = out.cmd;
  c.head.send_seq = ++send_seq_;
  c.head.refl_seq = msr.head.send_seq;
  c.head.packet_size = static_cast<uint16_t>(kCmdPacketSize);
  c.head.datagram_id = kDatagramIdCmd;
  c.krl = krl_out_;
  RobotCommand& r = c.cmd;
  r.cmd_flags = flags::kCartPose;
  if (params_.command_impedance) r.cmd_flags |= flags::kCartStiffness | flags::kCartDamping;
  if (joint_hold) r.cmd_flags = flags::kJointPosition;
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

BridgeStatus FriBridge::step(const MsrPacket& msr, const PoseCommand& desired, double now_s,
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

  // ---- sequence check (16-bit wrap-around) ----
  const uint16_t seq = msr.head.send_seq;
  if (have_seq_) {
    const int d = seqDelta(last_seq_, seq);
    if (d <= 0) {
      if (d == 0) {
        ++stats_.duplicates;
        return out.status = BridgeStatus::DroppedDuplicate;
      }
      if (++backwards_run_ < params_.resync_after) {
        ++stats_.out_of_order;
        return out.status = BridgeStatus::DroppedOutOfOrder;
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

  // ---- state and quality ----
  const State state = stateOf(msr);
  const Quality quality = qualityOf(msr);
  out.state = state;
  out.quality = quality;
  out.state_changed = !have_state_ || state != last_state_ || quality != last_quality_;
  have_state_ = true;
  last_state_ = state;
  last_quality_ = quality;

  const bool msr_valid = validFriPose(msr.data.msr_cart_pos);
  KDL::Frame measured = KDL::Frame::Identity();
  if (msr_valid) toFrame(msr.data.msr_cart_pos, measured);
  const double krc_T = static_cast<double>(msr.intf.desired_cmd_sample_time);
  const double T = (std::isfinite(krc_T) && krc_T > 0.0 && krc_T <= 0.1) ? krc_T : params_.nominal_period_s;

  if (state != State::Cmd || !powerOn(msr)) {
    // MON / OFF / power off: echo the measured pose; (re)entering CMD passes the start gate again.
    engaged_ = false;
    if (state != State::Cmd && was_in_cmd_) {
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
    limiter_.reset(measured);
    have_command_ = true;
    fillReply(msr, measured, out);
    return out.status;
  }

  // ---- CMD, powered ----
  was_in_cmd_ = true;
  if (msr.robot.control != static_cast<uint16_t>(ControlStrategy::CartImpedance)) {
    out.status = BridgeStatus::WrongStrategy;
    engaged_ = false;
    if (!msr_valid) {
      have_command_ = false;
      return out.status = BridgeStatus::MeasurementInvalid;
    }
    limiter_.reset(measured);  // should the strategy change to Cartesian, start from here
    have_command_ = true;
    fillReply(msr, measured, out, true);
    return out.status;
  }
  if (!have_command_) {
    if (!msr_valid) return out.status = BridgeStatus::MeasurementInvalid;
    limiter_.reset(measured);  // first command ever: start where the robot is
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
  const double age = now_s - desired.time_s;
  if (!msr_valid) {
    out.status = BridgeStatus::MeasurementInvalid;
  } else if (quality < Quality::Ok) {
    out.status = BridgeStatus::QualityLow;
  } else if (desired.status == ServoStatus::NotConfigured || desired.status == ServoStatus::WaitingForPose ||
             !validPose(desired.pose)) {
    out.status = BridgeStatus::DesiredInvalid;
    engaged_ = false;
  } else if (!(std::fabs(age) <= params_.max_desired_age_s)) {
    out.status = BridgeStatus::DesiredStale;
    engaged_ = false;
  } else {
    KDL::Frame target;
    toFrame(desired.pose, target);
    if (!engaged_) {
      // Start gate: follow only a desired pose within one program step of the
      // pose held now (the measured pose at the start of the session/CMD).
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
    const bool limited = limiter_.step(target, T);
    if (limited) ++stats_.limited;
    out.status = limited ? BridgeStatus::Limited : BridgeStatus::Commanding;
    fillReply(msr, limiter_.current(), out);
    return out.status;
  }
  ++stats_.holds;  // hold: repeat the last command unchanged
  fillReply(msr, limiter_.current(), out);
  return out.status;
}

}  // namespace fri
}  // namespace tactile
