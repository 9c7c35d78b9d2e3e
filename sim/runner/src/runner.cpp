#include "tactile_sim/runner.hpp"

#include <chrono>

#include "tactile_fri/params_io.hpp"
#include "tactile_fri/protocol.hpp"
#include <cmath>
#include <limits>

namespace tactile {
namespace sim {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::array<double, 3> rpyOf(const KDL::Rotation& R) {
  double r, p, y;
  R.GetRPY(r, p, y);
  return {r, p, y};
}

bool phaseIn(const std::vector<std::string>& list, const std::string& name) {
  for (const auto& s : list)
    if (s == name) return true;
  return false;
}

}  // namespace

ConfigResult Runner::configure(const Scene& scene) {
  ConfigResult r = validateScene(scene);
  if (!r) return r;
  scene_ = scene;
  WorldParams wp = scene.world;
  wp.seed = scene.seed;
  if (!(r = world_.configure(wp))) return ConfigResult::failure(scene.file + ": " + r.message());
  // Calibrate exactly as on the robot: the table that inverts the sensor's response.
  CalibrationParams cp = world_.calibration();
  if (!(r = calibration_.configure(cp))) return ConfigResult::failure(scene.file + ": calibration: " + r.message());
  if (!(r = extractor_.configure(scene.features))) return ConfigResult::failure(scene.file + ": " + r.message());
  ServoParams sp = scene.servo;
  sp.mode = scene.controller;
  if (!(r = servo_.configure(sp))) return ConfigResult::failure(scene.program_file + ": " + r.message());
  if (scene.through_fri) {
    fri::BridgeParams bp;
    fri::UdpParams up;
    if (!scene.fri_file.empty() && !(r = fri::loadBridgeParamsFile(scene.fri_file, bp, up))) return r;
    bp.nominal_period_s = 1.0 / scene.rates.sim;
    if (!(r = bridge_.configure(bp))) return ConfigResult::failure(scene.file + ": fri: " + r.message());
    fri_seq_ = fri_refl_ = 0;
    fri_have_applied_ = false;
  }
  return ConfigResult::success();
}

void Runner::run(RunResult& out, const std::function<void(double, double)>& progress) {
  const auto wall0 = std::chrono::steady_clock::now();
  const Scene& sc = scene_;
  out = RunResult{};
  for (int k = 0; k < servo_.phaseCount(); ++k) out.phase_names.push_back(servo_.phase(k).name);
  const double dt = 1.0 / sc.rates.sim;
  const long steps = std::lround(sc.duration * sc.rates.sim);
  out.rows.reserve(static_cast<std::size_t>(sc.duration * sc.rates.servo) + 16);
  out.contacts.reserve(out.rows.capacity());

  // Event clocks in integer ticks of the physics rate: no drift, exact rates
  // when they divide the physics rate, otherwise the nearest tick.
  double next_wts = 0, next_feat = 0, next_servo = 0;
  const double eps = 0.25 * dt;

  RawTactileFrame raw;
  TactileFrame frame;
  SensorTruth truth;
  ContactFeatures feats;  // NotConfigured until the first extraction: the servo holds
  bool have_frame = false;
  ServoOutput sout;
  SimState state = world_.state();
  Pose cmd = state.command_g;  // the initial command (dynamics may start at its equilibrium, off it)
  int last_phase = -1;
  int contact_run = 0, absent_run = 0;
  double t_last_servo = -1.0 / sc.rates.servo;
  bool first_contact_snap = false;
  Snapshot worst{0.0, "largest |DZMP_y|", TactileFrame{}};
  double worst_dzmp = -1.0;
  int done_rows = 0;
  Summary& sum = out.summary;
  sum.scene = sc.name;
  sum.controller = sc.controller == ControllerMode::Baseline ? "baseline" : "proposed";
  sum.seed = sc.seed;
  sum.fidelity = toString(sc.world.fidelity);
  long progress_every = std::max(1L, steps / 100);

  for (long i = 0; i < steps; ++i) {
    const double t = static_cast<double>(i) * dt;
    if (t + eps >= next_wts) {  // WTS acquisition (Table 2: 140 Hz)
      world_.acquire(raw, truth);
      calibration_.step(raw, frame);
      frame.time_s = t;
      have_frame = true;
      next_wts += 1.0 / sc.rates.wts;
    }
    if (t + eps >= next_feat) {  // feature extraction on the latest frame (200 Hz)
      if (have_frame) extractor_.step(frame, feats);
      next_feat += 1.0 / sc.rates.features;
    }
    if (t + eps >= next_servo) {  // tactile servo (100 Hz)
      ServoInput in;
      in.time_s = t;
      in.features = feats;
      in.flange_measured = state.flange_g;
      const ServoStatus st = servo_.step(in, t - t_last_servo, sout);
      t_last_servo = t;
      next_servo += 1.0 / sc.rates.servo;
      if (sout.valid) cmd = sout.command.pose;

      const int ph = servo_.phaseIndex();
      const PhaseParams& pp = servo_.phase(ph);
      if (ph != last_phase) {
        out.phases.push_back({pp.name, t});
        out.snapshots.push_back({t, "enter " + pp.name, frame});
        last_phase = ph;
      }
      if (!first_contact_snap && feats.contact != ContactType::None) {
        out.snapshots.push_back({t, "first contact", frame});
        first_contact_snap = true;
      }
      // A loss is a contact that held for >= 5 servo cycles and then stayed
      // absent for >= 5 cycles in a phase that needs it: single-frame
      // flicker of a taxel at the firing threshold is not a loss.
      if (feats.contact != ContactType::None) {
        ++contact_run;
        absent_run = 0;
      } else {
        ++absent_run;
        if (pp.requires_contact && absent_run == 5 && contact_run >= 5) ++sum.contact_lost_count;
        if (absent_run >= 5) contact_run = 0;
      }

      LogRow row;
      row.t = t;
      row.phase = ph;
      row.servo = st;
      row.contact = feats.contact;
      row.feature_status = feats.status;
      const KDL::Frame T_es = servo_.params().sensor_mount;
      const KDL::Frame T_cmd_s = toFrame(cmd) * T_es;
      const KDL::Frame& T_gs = state.T_gs;
      row.cmd = {T_cmd_s.p.x(), T_cmd_s.p.y(), T_cmd_s.p.z()};
      row.act = {T_gs.p.x(), T_gs.p.y(), T_gs.p.z()};
      row.cmd_rpy = rpyOf(T_cmd_s.M);
      row.act_rpy = rpyOf(T_gs.M);
      row.f = feats;
      row.s_d = pp.s_d;
      row.sd_force = pp.s_d(kZ) / servo_.params().c_z;
      row.force_true = -state.wrench_s[2];
      row.force_layer = state.normal_force;
      row.housing_force = state.housing_force;
      row.moment_x_true = state.wrench_s[3];
      row.moment_y_true = state.wrench_s[4];
      row.tray_angle_deg = state.tray_roll * 180.0 / kPi;
      row.true_contact = truth.contact_point_g;
      row.true_in_contact = truth.in_contact;
      row.u_s = sout.u_s;
      row.beta = sout.beta;
      row.feature_age = feats.status == FeatureStatus::NotConfigured ? kNaN : t - feats.time_s;
      out.rows.push_back(row);

      if (feats.contact == ContactType::Edge && std::fabs(feats.dzmp_y) > worst_dzmp) {
        worst_dzmp = std::fabs(feats.dzmp_y);
        worst.t = t;
        worst.frame = frame;
      }
      if (pp.requires_contact && feats.contact != ContactType::None) {
        const KDL::Vector p = T_gs * KDL::Vector(feats.cop_x, feats.cop_y, 0.0);
        out.contacts.push_back({t, {p.x(), p.y(), p.z()}, truth.contact_point_g});
      }
      if (st == ServoStatus::ForceCeiling) {
        sum.status = "servo_force_ceiling";
        sum.exit_code = 4;
        break;
      }
      // A terminal phase ends the run after one more second of holding.
      if (st == ServoStatus::Done && ++done_rows > static_cast<int>(sc.rates.servo)) break;
    }
    Pose applied = cmd;
    if (sc.through_fri) {
      PoseCommand desired = sout.command;
      desired.pose = cmd;
      desired.time_s = t;
      KDL::Frame f;
      if (friCycle(state, desired, t, dt, f, sum)) applied = toPose(f);
      else applied = state.command_g;  // no reply: the KRC keeps its last set point
    }
    const SimStatus ss = world_.step(applied, dt, state);
    if (fatal(ss)) {
      sum.status = std::string("sim_") + toString(ss);
      sum.exit_code = 3;
      break;
    }
    if (progress && i % progress_every == 0) progress(t, sc.duration);
  }
  if (progress) progress(state.time_s, sc.duration);
  if (worst_dzmp >= 0.0) out.snapshots.push_back(worst);
  out.snapshots.push_back({state.time_s, "end", frame});
  sum.sim_time_s = state.time_s;
  sum.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  sum.real_time_factor = sum.wall_time_s > 0 ? sum.sim_time_s / sum.wall_time_s : 0.0;
  computeSummary(out);
}

bool Runner::friCycle(const SimState& st, const PoseCommand& desired, double t, double dt, KDL::Frame& applied,
                      Summary& sum) {
  using namespace fri;
  // The simulated KRC: CMD at perfect quality under Cartesian impedance, the
  // world's measured state in the packet (what the real KRC sends each 1 ms).
  MsrPacket& m = msr_;
  m.head.send_seq = ++fri_seq_;
  m.head.refl_seq = fri_refl_;
  m.head.packet_size = static_cast<uint16_t>(kMsrPacketSize);
  m.head.datagram_id = kDatagramIdMsr;
  m.intf.timestamp = static_cast<uint32_t>(t * 1000.0);
  // The KRC starts in MON, then switches to CMD before the servo's second
  // cycle: the servo's first command is the measured pose, which passes the
  // bridge's start gate. (A servo that integrated further while the KRC was in
  // MON is refused by the gate: status desired_far, the arm holds.)
  const bool monitor = t < 0.005;
  m.intf.state = static_cast<uint16_t>(monitor ? State::Mon : State::Cmd);
  m.intf.quality = static_cast<uint16_t>(Quality::Perfect);
  m.intf.desired_msr_sample_time = static_cast<float>(dt);
  m.intf.desired_cmd_sample_time = static_cast<float>(dt);
  m.robot.power = 0x7F;
  m.robot.control = static_cast<uint16_t>(ControlStrategy::CartImpedance);
  for (int j = 0; j < kNumJoints; ++j) {
    m.data.msr_jnt_pos[j] = static_cast<float>(st.q(j));
    m.data.cmd_jnt_pos[j] = m.data.msr_jnt_pos[j];
  }
  fromFrame(st.T_ge, m.data.msr_cart_pos);
  fromFrame(fri_have_applied_ ? fri_applied_ : st.T_ge, m.data.cmd_cart_pos);
  std::size_t n = 0;
  if (encodeMeasurement(m, wire_.data(), wire_.size(), n) != PacketStatus::Ok) return false;
  BridgeOutput out;
  bridge_.stepDatagram(wire_.data(), n, desired, t, out);
  if (!out.reply) return false;
  if (encodeCommand(out.cmd, wire_.data(), wire_.size(), n) != PacketStatus::Ok) return false;
  if (decodeCommand(wire_.data(), n, cmd_) != PacketStatus::Ok) return false;
  fri_refl_ = cmd_.head.send_seq;
  ++sum.fri_replies;
  if (monitor) return false;  // MON: the KRC does not apply commands
  KDL::Frame c;
  fri::toFrame(cmd_.cmd.cart_pos, c);
  if (fri_have_applied_) {
    sum.fri_max_step_m = std::max(sum.fri_max_step_m, (c.p - fri_applied_.p).Norm());
    const KDL::Rotation dR = fri_applied_.M.Inverse() * c.M;
    double x, y, z, w;
    dR.GetQuaternion(x, y, z, w);
    sum.fri_max_step_rad = std::max(sum.fri_max_step_rad, 2.0 * std::atan2(std::sqrt(x * x + y * y + z * z), std::fabs(w)));
  }
  fri_applied_ = c;
  fri_have_applied_ = true;
  applied = c;
  return true;
}

void Runner::computeSummary(RunResult& out) const {
  Summary& s = out.summary;
  const auto& rows = out.rows;
  const Scene& sc = scene_;
  // Phase entry times (first occurrence).
  auto tEnter = [&](const std::string& name) {
    for (const auto& p : out.phases)
      if (p.name == name) return p.t_enter;
    return kNaN;
  };
  s.alignment_time_s = (!sc.metrics.align_from.empty() && !sc.metrics.align_to.empty())
                           ? tEnter(sc.metrics.align_to) - tEnter(sc.metrics.align_from)
                           : kNaN;

  // Force metrics over the servoing phases, after each phase's transient.
  double sum_f = 0, sum_e2 = 0, max_f = 0, path = 0, t_scored = 0;
  double n = 0, in_band = 0;
  const LogRow* prev = nullptr;
  double phase_t0 = 0;
  int phase_cur = -1;
  for (const auto& r : rows) {
    if (r.phase != phase_cur) {
      phase_cur = r.phase;
      phase_t0 = r.t;
    }
    const PhaseParams& pp = servo_.phase(r.phase);
    const bool scored = sc.metrics.force_phases.empty() ? (pp.requires_contact && !pp.terminal)
                                                        : phaseIn(sc.metrics.force_phases, pp.name);
    if (!scored || r.t - phase_t0 < sc.metrics.transient_s) {
      prev = nullptr;
      continue;
    }
    sum_f += r.force_true;
    sum_e2 += (r.force_true - r.sd_force) * (r.force_true - r.sd_force);
    max_f = std::max(max_f, r.force_true);
    in_band += std::fabs(r.force_true - r.sd_force) <= sc.metrics.force_band_n ? 1.0 : 0.0;
    ++n;
    if (prev && prev->true_in_contact && r.true_in_contact) {
      double d2 = 0;
      for (int k = 0; k < 3; ++k) d2 += (r.true_contact[k] - prev->true_contact[k]) * (r.true_contact[k] - prev->true_contact[k]);
      path += std::sqrt(d2);
      t_scored += r.t - prev->t;
    }
    prev = &r;
  }
  s.force_true_mean_n = n ? sum_f / n : kNaN;
  s.force_true_max_n = n ? max_f : kNaN;
  s.force_true_rms_error_n = n ? std::sqrt(sum_e2 / n) : kNaN;
  s.force_true_in_band_fraction = n ? in_band / n : kNaN;
  s.path_length_m = path;
  s.slide_speed_mps = t_scored > 0 ? path / t_scored : kNaN;

  // Final DZMP_y: mean over the last 0.5 s.
  double sd = 0;
  double nd = 0;
  const double t_end = rows.empty() ? 0 : rows.back().t;
  for (const auto& r : rows)
    if (r.t >= t_end - 0.5 && r.f.contact != ContactType::None) {
      sd += r.f.dzmp_y;
      ++nd;
    }
  s.dzmp_final_m = nd ? sd / nd : kNaN;

  // Co-manipulation metrics (scenes with a tray).
  if (world_.objects().hasTray()) {
    const TrayParams& tp = world_.objects().tray();
    double amax = 0;
    for (const auto& r : rows) amax = std::max(amax, std::fabs(r.tray_angle_deg));
    s.tray_angle_max_deg = amax;
    // DZMP recovery: from the start of the move until |DZMP_y| <= 0.5 mm for good.
    const double t_move = tp.move_start_s;
    double t_settled = kNaN;
    for (auto it = rows.rbegin(); it != rows.rend(); ++it) {
      if (it->t < t_move) break;
      if (std::fabs(it->f.dzmp_y) > 0.0005 || it->f.contact == ContactType::None) break;
      t_settled = it->t;
    }
    s.dzmp_recovery_time_s = std::isnan(t_settled) ? kNaN : t_settled - t_move;
    // Translation along the sensor's initial x axis since the move.
    const LogRow* before = nullptr;
    for (const auto& r : rows)
      if (r.t <= t_move) before = &r;
    if (before && !rows.empty()) {
      const KDL::Vector xs =
          KDL::Rotation::RPY(before->act_rpy[0], before->act_rpy[1], before->act_rpy[2]).UnitX();
      const KDL::Vector d(rows.back().act[0] - before->act[0], rows.back().act[1] - before->act[1],
                          rows.back().act[2] - before->act[2]);
      s.translation_x_m = KDL::dot(d, xs);
    }
  } else {
    s.tray_angle_max_deg = kNaN;
    s.dzmp_recovery_time_s = kNaN;
    s.translation_x_m = kNaN;
  }
}

}  // namespace sim
}  // namespace tactile
