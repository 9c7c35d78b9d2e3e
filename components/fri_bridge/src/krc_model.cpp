#include "tactile_fri/krc_model.hpp"

#include <algorithm>
#include <cmath>

namespace tactile {
namespace fri {

ConfigResult KrcModel::configure(const KrcModelParams& p) {
  if (!(std::isfinite(p.period_s) && p.period_s > 0.0 && p.period_s <= 0.1))
    return rangeError("krc.period_s", p.period_s, "must be in (0, 0.1] (s)");
  params_ = p;
  reset(KDL::Frame::Identity());
  return ConfigResult::success();
}

void KrcModel::reset(const KDL::Frame& pose) {
  stats_ = KrcModelStats{};
  seq_ = 0;
  last_remote_seq_ = last_seen_remote_seq_ = 0;
  have_remote_seq_ = false;
  have_applied_ = false;
  set_point_ = pose;
  last_applied_ = pose;
  msr_ = MsrPacket{};
  cmd_ = CmdPacket{};
}

void KrcModel::setState(State state, Quality quality, uint16_t power) {
  if (state != State::Cmd || power == 0) have_applied_ = false;  // re-entry is checked as an entry
  state_ = state;
  quality_ = quality;
  power_ = power;
}

void KrcModel::holdUnlessCommanding(const KDL::Frame& measured) {
  if (state_ != State::Cmd || power_ == 0) set_point_ = measured;
}

void KrcModel::buildMeasurement(const PlantState& plant, double t_s, MsrPacket& out) {
  MsrPacket& m = msr_;
  m.head.send_seq = ++seq_;
  m.head.refl_seq = last_remote_seq_;
  m.head.packet_size = static_cast<uint16_t>(kMsrPacketSize);
  m.head.datagram_id = kDatagramIdMsr;
  m.intf.timestamp = static_cast<uint32_t>(t_s * 1000.0);
  m.intf.state = static_cast<uint16_t>(state_);
  m.intf.quality = static_cast<uint16_t>(quality_);
  m.intf.desired_msr_sample_time = static_cast<float>(params_.period_s);
  m.intf.desired_cmd_sample_time = static_cast<float>(params_.period_s);
  m.intf.safety_limits = 0.0f;
  m.robot.power = power_;
  m.robot.control = static_cast<uint16_t>(params_.control);
  for (int j = 0; j < kNumJoints; ++j) {
    m.data.msr_jnt_pos[j] = static_cast<float>(plant.q[static_cast<std::size_t>(j)]);
    m.data.cmd_jnt_pos[j] = m.data.msr_jnt_pos[j];
    m.robot.temperature[j] = 30.0f;
  }
  fromFrame(plant.pose, m.data.msr_cart_pos);
  fromFrame(set_point_, m.data.cmd_cart_pos);
  fromWrench(plant.wrench, m.data.est_ext_tcp_ft);
  out = m;
}

ReplyResult KrcModel::handleReply(const uint8_t* buf, std::size_t n) {
  if (decodeCommand(buf, n, cmd_) != PacketStatus::Ok) {
    ++stats_.malformed_replies;
    return ReplyResult::Malformed;
  }
  if (have_remote_seq_ && seqDelta(last_seen_remote_seq_, cmd_.head.send_seq) != 1) ++stats_.remote_seq_errors;
  have_remote_seq_ = true;
  last_seen_remote_seq_ = cmd_.head.send_seq;
  if (cmd_.head.refl_seq != seq_) {
    ++stats_.stale_replies;  // reflects an older measurement: ignored, as the KRC does
    return ReplyResult::Stale;
  }
  last_remote_seq_ = cmd_.head.send_seq;  // reflected in the next measurement: the last command taken
  ++stats_.replies;
  bool finite = true;
  for (float v : cmd_.cmd.cart_pos) finite = finite && std::isfinite(v);
  if (!finite || !validFriPose(cmd_.cmd.cart_pos)) {
    ++stats_.nonfinite_commands;
    return ReplyResult::Matched;
  }
  KDL::Frame c;
  toFrame(cmd_.cmd.cart_pos, c);
  if (state_ == State::Cmd && power_ != 0) {
    if (params_.control != ControlStrategy::CartImpedance) {
      // joint strategies: this model only checks that the remote holds the joints
      if (!(cmd_.cmd.cmd_flags & flags::kJointPosition)) ++stats_.flag_errors;
      return ReplyResult::Matched;
    }
    if (!(cmd_.cmd.cmd_flags & flags::kCartPose)) {
      ++stats_.flag_errors;
      return ReplyResult::Matched;
    }
    if (quality_ >= Quality::Ok) {
      KDL::Vector axis;
      if (have_applied_) {
        stats_.max_cmd_step_m = std::max(stats_.max_cmd_step_m, (c.p - last_applied_.p).Norm());
        stats_.max_cmd_step_rad = std::max(stats_.max_cmd_step_rad, rotationAngle(last_applied_.M.Inverse() * c.M, axis));
      } else {
        KDL::Frame measured;
        toFrame(msr_.data.msr_cart_pos, measured);
        stats_.max_entry_offset_m = std::max(stats_.max_entry_offset_m, (c.p - measured.p).Norm());
        stats_.max_entry_offset_rad = std::max(stats_.max_entry_offset_rad, rotationAngle(measured.M.Inverse() * c.M, axis));
      }
      have_applied_ = true;
      last_applied_ = c;
      set_point_ = c;
      ++stats_.applied;
    }
  } else {
    // MON / power off: the remote must echo the measured pose (the one sent this cycle).
    KDL::Frame measured;
    toFrame(msr_.data.msr_cart_pos, measured);
    KDL::Vector axis;
    if ((c.p - measured.p).Norm() > 1e-5 || rotationAngle(measured.M.Inverse() * c.M, axis) > 1e-5)
      ++stats_.mon_echo_errors;
  }
  return ReplyResult::Matched;
}

}  // namespace fri
}  // namespace tactile
