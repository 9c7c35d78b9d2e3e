#include "tactile_fri/krc_model.hpp"

#include <cstdlib>

#include "tactile_fri/bridge.hpp"

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
  ever_applied_ = false;
  flags_ = 0;
  have_flags_ = false;
  refused_ = false;
  stop_requested_ = false;
  set_point_ = pose;
  krl_pose_ = pose;
  last_applied_ = pose;
  msr_ = MsrPacket{};
  cmd_ = CmdPacket{};
}

void KrcModel::setState(State state, Quality quality, uint16_t power) {
  if ((refused_ || stop_requested_) && state == State::Cmd) state = State::Mon;  // left CMD: refused flags, or friStop
  if (state != State::Cmd || power == 0) have_applied_ = false;  // re-entry is checked as an entry
  state_ = state;
  quality_ = quality;
  power_ = power;
}

void KrcModel::holdUnlessCommanding(const KDL::Frame& measured) {
  // Before any command: the arm rests where it is. Afterwards the KRC keeps
  // the set point it has (friStop, a low quality, the drives braked): a
  // pressing contact keeps its force.
  if ((state_ != State::Cmd || power_ == 0) && !ever_applied_) set_point_ = krl_pose_ = measured;
}

void KrcModel::buildMeasurement(const PlantState& plant, double t_s, MsrPacket& out) {
  MsrPacket& m = msr_;
  m.head.send_seq = ++seq_;
  m.head.refl_seq = last_remote_seq_;
  m.head.packet_size = static_cast<uint16_t>(kMsrPacketSize);
  m.head.datagram_id = kDatagramIdMsr;
  m.intf.timestamp = static_cast<uint32_t>(t_s * 1000.0);
  // $FRI_TO_INT[1]: the KRL program's step (krc/TactileServo.dat TS_ST_*)
  m.krl.int_data[0] = stop_requested_ ? krl::kProgramClosed
                                      : (state_ == State::Cmd ? krl::kProgramCommand : krl::kProgramMonitor);
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
  writeSetPoint(krl_pose_, set_point_, params_.cart_offset, m.data.cmd_cart_pos, m.data.cmd_cart_pos_fri_offset);
  fromWrenchIn(plant.wrench, params_.wrench_frame, plant.pose.M, m.data.est_ext_tcp_ft);  // $STIFFNESS.FRAMETYPE
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
  if (cmd_.krl.int_data[0] == krl::kRequestStop && !stop_requested_) {
    // the KRL program honours the RT PC's request: friStop from the next
    // cycle on (setState), this reply is taken as any other
    stop_requested_ = true;
  }
  bool finite = true;
  for (float v : cmd_.cmd.cart_pos) finite = finite && std::isfinite(v);
  if (!finite || !validFriPose(cmd_.cmd.cart_pos)) {
    ++stats_.nonfinite_commands;
    return ReplyResult::Matched;
  }
  KDL::Frame c;
  toFrame(cmd_.cmd.cart_pos, c);
  // Command flags: free outside CMD, fixed in CMD (a session starting in CMD
  // fixes them with its first reply).
  if (state_ != State::Cmd || !have_flags_) {
    flags_ = cmd_.cmd.cmd_flags;
    have_flags_ = true;
  } else if (cmd_.cmd.cmd_flags != flags_) {
    ++stats_.flag_changes;
    ++stats_.flag_errors;
    refused_ = true;
    state_ = State::Mon;
    have_applied_ = false;
    return ReplyResult::Matched;
  }
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
      } else {  // entering CMD: against the set point the KRC held (cmdCartPos)
        stats_.max_entry_offset_m = std::max(stats_.max_entry_offset_m, (c.p - set_point_.p).Norm());
        stats_.max_entry_offset_rad = std::max(stats_.max_entry_offset_rad, rotationAngle(set_point_.M.Inverse() * c.M, axis));
      }
      have_applied_ = true;
      ever_applied_ = true;
      last_applied_ = c;
      set_point_ = c;
      ++stats_.applied;
    }
  } else {
    // MON / power off: the remote must echo the KRC's set point (sent this cycle).
    const KDL::Frame& held = set_point_;
    KDL::Vector axis;
    if ((c.p - held.p).Norm() > 1e-5 || rotationAngle(held.M.Inverse() * c.M, axis) > 1e-5)
      ++stats_.mon_echo_errors;
  }
  return ReplyResult::Matched;
}


ConfigResult KrcScript::parse(const std::string& spec, const std::string& where) {
  std::vector<KrcEvent> ev;
  std::size_t pos = 0;
  double last_t = 0.0;
  while (pos < spec.size()) {
    std::size_t comma = spec.find(',', pos);
    if (comma == std::string::npos) comma = spec.size();
    std::string item = spec.substr(pos, comma - pos);
    pos = comma + 1;
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (item.empty()) continue;
    const std::size_t colon = item.find(':');
    const auto bad = [&](const std::string& why) {
      return ConfigResult::failure(where + ": '" + item + "': " + why +
                                   " (items TIME:WORD, TIME in s increasing, WORD friOpen | friStart | friStop | "
                                   "friClose | quality=UNACCEPTABLE|BAD|OK|PERFECT | power=off|on)");
    };
    if (colon == std::string::npos) return bad("no ':'");
    char* end = nullptr;
    const std::string ts = item.substr(0, colon);
    const double t = std::strtod(ts.c_str(), &end);
    if (ts.empty() || *end != '\0' || !std::isfinite(t) || t < 0.0) return bad("the time must be a number >= 0 s");
    if (!ev.empty() && t < last_t) return bad("times must not decrease");
    last_t = t;
    const std::string w = item.substr(colon + 1);
    KrcEvent e;
    e.t_s = t;
    if (w == "friOpen") e.kind = KrcEvent::Kind::FriOpen;
    else if (w == "friStart") e.kind = KrcEvent::Kind::FriStart;
    else if (w == "friStop") e.kind = KrcEvent::Kind::FriStop;
    else if (w == "friClose") e.kind = KrcEvent::Kind::FriClose;
    else if (w.rfind("quality=", 0) == 0) {
      e.kind = KrcEvent::Kind::Quality;
      if (!parseQuality(w.substr(8).c_str(), e.quality)) return bad("unknown quality");
    } else if (w == "power=off" || w == "power=on") {
      e.kind = KrcEvent::Kind::Power;
      e.power = w == "power=on";
    } else {
      return bad("unknown word");
    }
    ev.push_back(e);
  }
  if (!ev.empty() && ev.front().kind != KrcEvent::Kind::FriOpen)
    return ConfigResult::failure(where + ": the script must begin with friOpen (the KRC sends nothing before it)");
  events_ = ev;
  return ConfigResult::success();
}

KrcScript::At KrcScript::at(double t_s) const {
  At a;
  if (events_.empty()) {  // command mode from the start
    a.open = true;
    a.state = State::Cmd;
    return a;
  }
  for (const KrcEvent& e : events_) {
    if (e.t_s > t_s) break;
    switch (e.kind) {
      case KrcEvent::Kind::FriOpen: a.open = true, a.state = State::Mon; break;
      case KrcEvent::Kind::FriStart: if (a.open) a.state = State::Cmd; break;  // friStart needs an open link
      case KrcEvent::Kind::FriStop: if (a.open) a.state = State::Mon; break;
      case KrcEvent::Kind::FriClose: a.open = false, a.state = State::Off; break;
      case KrcEvent::Kind::Quality: a.quality = e.quality; break;
      case KrcEvent::Kind::Power: a.power = e.power; break;
    }
  }
  return a;
}

void robotStateOf(const KrcScript::At& krc, double t_s, tactile::RobotState& out) {
  out.time_s = t_s;
  out.mode = !krc.open || krc.state == State::Off ? RobotMode::Off
                                                  : (krc.state == State::Cmd ? RobotMode::Command : RobotMode::Monitor);
  out.quality = static_cast<int>(krc.quality);
  out.power_on = krc.power;
  out.cartesian_impedance = true;
  out.config_ok = true;
  out.dry_run = false;
  out.commandable = out.mode == RobotMode::Command && krc.power && krc.quality >= Quality::Ok;
  out.link_status = static_cast<int>(out.commandable ? BridgeStatus::Commanding : BridgeStatus::Monitor);
}

}  // namespace fri
}  // namespace tactile
