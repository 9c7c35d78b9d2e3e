#include "tactile_fri/krc_model.hpp"

#include <cstdlib>

#include "tactile_fri/bridge.hpp"

#include <algorithm>
#include <cmath>

namespace tactile {
namespace fri {

const char* toString(KrcFault f) {
  switch (f) {
    case KrcFault::None: return "none";
    case KrcFault::MaxForce: return "maxforce";
    case KrcFault::CpMaxDelta: return "cpmaxdelta";
  }
  return "unknown";
}

namespace {
ConfigResult checkRule(const KrcQualityRule& r) {
  if (r.window < 1 || r.window > KrcQualityRule::kMaxWindow)
    return rangeError("krc.quality_rule.window", r.window, "must be in [1, 1000] (cycles)");
  if (!(r.late_fraction > 0.0 && r.late_fraction <= 1.0))
    return rangeError("krc.quality_rule.late_fraction", r.late_fraction, "must be in (0, 1] (share of the cycle)");
  if (!(r.perfect_max >= 0.0 && r.perfect_max <= 1.0))
    return rangeError("krc.quality_rule.perfect_max", r.perfect_max, "must be in [0, 1]");
  if (!(r.ok_max >= r.perfect_max && r.ok_max <= 1.0))
    return rangeError("krc.quality_rule.ok_max", r.ok_max, "must be in [perfect_max, 1]");
  if (!(r.bad_max >= r.ok_max && r.bad_max <= 1.0))
    return rangeError("krc.quality_rule.bad_max", r.bad_max, "must be in [ok_max, 1]");
  return ConfigResult::success();
}
ConfigResult checkLimitsParams(const KrcStiffnessLimits& l) {
  static const char* const kAxes[6] = {"X", "Y", "Z", "A", "B", "C"};
  for (std::size_t i = 0; i < 6; ++i) {
    if (!(std::isfinite(l.max_force[i]) && l.max_force[i] >= 0.0))
      return rangeError(std::string("krc.limits.max_force ") + kAxes[i], l.max_force[i], "must be >= 0 (N, N m; 0 = off)");
    if (!(std::isfinite(l.cp_max_delta[i]) && l.cp_max_delta[i] >= 0.0))
      return rangeError(std::string("krc.limits.cp_max_delta ") + kAxes[i], l.cp_max_delta[i],
                        "must be >= 0 (m, rad; 0 = off)");
  }
  return ConfigResult::success();
}
}  // namespace

ConfigResult KrcModel::configure(const KrcModelParams& p) {
  if (!(std::isfinite(p.period_s) && p.period_s > 0.0 && p.period_s <= 0.1))
    return rangeError("krc.period_s", p.period_s, "must be in (0, 0.1] (s)");
  if (ConfigResult r = checkRule(p.quality_rule); !r) return r;
  if (ConfigResult r = checkLimitsParams(p.limits); !r) return r;
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
  fault_ = KrcFault::None;
  // Before the remote answers, the KRC rates the link UNACCEPTABLE (with the rule).
  timing_quality_ = params_.quality_rule.enabled ? Quality::Unacceptable : Quality::Perfect;
  // Before the remote's first answer every cycle of the window counts as missed.
  answer_ring_.fill(0);
  for (uint32_t i = 0; i < params_.quality_rule.window; ++i) answer_ring_[i] = 1;
  ring_bad_ = params_.quality_rule.window;
  ring_pos_ = 0;
  set_point_ = pose;
  krl_pose_ = pose;
  last_applied_ = pose;
  msr_ = MsrPacket{};
  cmd_ = CmdPacket{};
}

void KrcModel::setState(State state, Quality quality, uint16_t power) {
  script_state_ = state;
  script_quality_ = quality;
  script_power_ = power;
  applyState();
}

void KrcModel::applyState() {
  State state = script_state_;
  const Quality quality = std::min(script_quality_, timing_quality_);
  uint16_t power = script_power_;
  if ((refused_ || stop_requested_ || fault_ != KrcFault::None) && state == State::Cmd)
    state = State::Mon;  // left CMD: refused flags, friStop, or the KRC's fault
  if (fault_ != KrcFault::None) power = 0;  // the drives braked until the operator acknowledges
  if (params_.quality_rule.enabled && state == State::Cmd) {
    if (state_ == State::Cmd && quality < Quality::Ok) {
      state = State::Mon;  // the KRC leaves command mode below OK
      ++stats_.quality_drops;
    } else if (state_ != State::Cmd && quality != Quality::Perfect) {
      state = State::Mon;  // friStart (again) only at PERFECT
    }
  }
  if (state != State::Cmd || power == 0) have_applied_ = false;  // re-entry is checked as an entry
  state_ = state;
  quality_ = quality;
  power_ = power;
}

void KrcModel::noteAnswer(bool answered, double latency_s) {
  const KrcQualityRule& r = params_.quality_rule;
  const bool late = answered && latency_s > r.late_fraction * params_.period_s;
  if (!answered) ++stats_.answers_missed;
  if (late) ++stats_.answers_late;
  const uint8_t bad = (!answered || late) ? 1 : 0;
  ring_bad_ = ring_bad_ - answer_ring_[ring_pos_] + bad;
  answer_ring_[ring_pos_] = bad;
  ring_pos_ = (ring_pos_ + 1) % r.window;
  if (!r.enabled) return;
  const double share = static_cast<double>(ring_bad_) / static_cast<double>(r.window);
  timing_quality_ = share <= r.perfect_max ? Quality::Perfect
                    : share <= r.ok_max    ? Quality::Ok
                    : share <= r.bad_max   ? Quality::Bad
                                           : Quality::Unacceptable;
  applyState();
}

void KrcModel::checkLimits(const PlantState& plant) {
  // $STIFFNESS.MAXFORCE / CPMAXDELTA: watched while the KRC commands the arm
  // under Cartesian impedance (command mode, drives on).
  const KrcStiffnessLimits& l = params_.limits;
  if (fault_ != KrcFault::None || state_ != State::Cmd || power_ == 0 ||
      params_.control != ControlStrategy::CartImpedance || !l.any())
    return;
  // MAXFORCE bounds each component of estExtTcpFT as the KRC reports it: in
  // the axes of $STIFFNESS.FRAMETYPE (a per-component limit, so the axes
  // matter: 15 N along base z is 15 N along tool x when the flange points
  // sideways).
  const std::array<double, 6> w = wrenchInFrame(plant.wrench, params_.wrench_frame, plant.pose.M);
  KrcFault f = KrcFault::None;
  for (std::size_t i = 0; i < 6; ++i)
    if (l.max_force[i] > 0.0 && std::fabs(w[i]) > l.max_force[i]) f = KrcFault::MaxForce;
  if (f == KrcFault::None) {
    // The deviation in base axes: translation, then the rotation vector of
    // set point -> measured about z (A), y (B), x (C).
    const KDL::Vector dp = plant.pose.p - set_point_.p;
    const KDL::Vector rv = (plant.pose.M * set_point_.M.Inverse()).GetRot();
    const double d[6] = {dp.x(), dp.y(), dp.z(), rv.z(), rv.y(), rv.x()};
    for (std::size_t i = 0; i < 6; ++i)
      if (l.cp_max_delta[i] > 0.0 && std::fabs(d[i]) > l.cp_max_delta[i]) f = KrcFault::CpMaxDelta;
  }
  if (f == KrcFault::None) return;
  fault_ = f;
  ++stats_.faults;
  set_point_ = krl_pose_ = plant.pose;  // braked where it stands
  ever_applied_ = true;                 // the KRC keeps that set point
  applyState();                         // monitor mode, drives off, from this measurement on
}

void KrcModel::holdUnlessCommanding(const KDL::Frame& measured) {
  // Before any command: the arm rests where it is. Afterwards the KRC keeps
  // the set point it has (friStop, a low quality, the drives braked): a
  // pressing contact keeps its force.
  if ((state_ != State::Cmd || power_ == 0) && !ever_applied_) set_point_ = krl_pose_ = measured;
}

void KrcModel::buildMeasurement(const PlantState& plant, double t_s, MsrPacket& out) {
  checkLimits(plant);
  ++stats_.quality_cycles[static_cast<std::size_t>(quality_) & 3u];
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
    applyState();
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
