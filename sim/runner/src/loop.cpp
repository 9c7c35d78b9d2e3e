#include "tactile_sim/loop.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace tactile {
namespace sim {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Time constant (s) of the low-pass on DZMP_y for the recovery time: the
/// programs' `aligned` filter_s, about 28 frames of the 140 Hz WTS.
constexpr double kRecoveryFilterS = 0.1;

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

// ---- Schedule -----------------------------------------------------------------

ConfigResult Schedule::configure(const Rates& r, double duration_s) {
  for (auto [name, v] : {std::pair<const char*, double>{"rates.sim", r.sim}, {"rates.servo", r.servo},
                         {"rates.wts", r.wts}, {"rates.features", r.features}})
    if (!(v > 0.0) || !std::isfinite(v) || v > 1e6) return rangeError(name, v, "must be in (0, 1e6] Hz");
  for (auto [name, v] : {std::pair<const char*, double>{"rates.servo", r.servo}, {"rates.wts", r.wts},
                         {"rates.features", r.features}})
    if (v > r.sim + 1e-9) return rangeError(name, v, "must be <= rates.sim (the physics rate)");
  if (!(duration_s > 0.0) || !std::isfinite(duration_s)) return rangeError("duration", duration_s, "must be > 0 (s)");
  rates_ = r;
  dt_ = 1.0 / r.sim;
  period_ns_ = std::max<int64_t>(1, std::llround(1e9 / r.sim));
  steps_ = std::lround(duration_s * r.sim);
  reset();
  return ConfigResult::success();
}

void Schedule::reset() {
  i_ = 0;
  next_wts_ = next_feat_ = next_servo_ = 0.0;
}

StageFires Schedule::fires() const {
  const double t = time(), eps = 0.25 * dt_;
  StageFires f;
  f.wts = t + eps >= next_wts_;
  f.features = t + eps >= next_feat_;
  f.servo = t + eps >= next_servo_;
  return f;
}

void Schedule::advance() {
  const StageFires f = fires();
  if (f.wts) next_wts_ += 1.0 / rates_.wts;
  if (f.features) next_feat_ += 1.0 / rates_.features;
  if (f.servo) next_servo_ += 1.0 / rates_.servo;
  ++i_;
}

// ---- EndRule ------------------------------------------------------------------

EndReason EndRule::afterServo(ServoStatus st) {
  if (st == ServoStatus::ForceCeiling) return EndReason::ServoForceCeiling;
  if (st == ServoStatus::PhaseTimeout) return EndReason::ServoPhaseTimeout;
  if (st == ServoStatus::ArmStalled) return EndReason::ServoArmStalled;
  if (st == ServoStatus::ForceMismatch) return EndReason::ServoForceMismatch;
  if (st == ServoStatus::SurfaceTooCurved) return EndReason::ServoSurfaceTooCurved;
  // A terminal phase ends the run after one more second of holding.
  if (st == ServoStatus::Done && ++done_cycles_ > done_limit_) return EndReason::DoneHeld;
  return EndReason::None;
}

EndReason EndRule::afterPhysics(SimStatus st) {
  if (fatal(st)) return EndReason::SimFatal;
  if (st == SimStatus::NotConverged) {
    ++unconverged_total_;
    if (++unconverged_cycles_ >= unconverged_limit_) return EndReason::SimFatal;
  } else {
    unconverged_cycles_ = 0;
  }
  if (st == SimStatus::StepRejected) return EndReason::SimRejected;  // time stands still: it never recovers
  if (st != SimStatus::InvalidCommand) {
    invalid_cycles_ = 0;
    return EndReason::None;
  }
  return ++invalid_cycles_ >= invalid_limit_ ? EndReason::SimRejected : EndReason::None;
}

void applyEnd(EndReason reason, SimStatus sim_status, Summary& s) {
  switch (reason) {
    case EndReason::ServoForceCeiling:
      s.status = "servo_force_ceiling";
      s.exit_code = 4;
      break;
    case EndReason::ServoPhaseTimeout:
      s.status = "servo_phase_timeout";
      s.exit_code = 5;
      break;
    case EndReason::ServoArmStalled:
      s.status = "servo_arm_stalled";
      s.exit_code = 6;
      break;
    case EndReason::ServoForceMismatch:
      s.status = "servo_force_mismatch";
      s.exit_code = 7;
      break;
    case EndReason::ServoSurfaceTooCurved:
      s.status = "servo_surface_too_curved";
      s.exit_code = 8;
      break;
    case EndReason::SimFatal:
    case EndReason::SimRejected:
      s.status = std::string("sim_") + toString(sim_status);
      s.exit_code = 3;
      break;
    default:
      s.status = "ok";
      s.exit_code = 0;
  }
}

// ---- rows -------------------------------------------------------------------

void fillEstimatedWrench(const SimState& st, Wrench& out) {
  const KDL::Wrench w_s(KDL::Vector(st.wrench_s[0], st.wrench_s[1], st.wrench_s[2]),
                        KDL::Vector(st.wrench_s[3], st.wrench_s[4], st.wrench_s[5]));
  const KDL::Wrench w_g = st.T_gs.M * w_s;                  // {g} axes, about the sensor origin
  const KDL::Wrench w_e = w_g.RefPoint(st.T_ge.p - st.T_gs.p);  // about the flange origin
  out.time_s = st.time_s;
  out.w = {w_e.force.x(), w_e.force.y(), w_e.force.z(), w_e.torque.x(), w_e.torque.y(), w_e.torque.z()};
}

namespace {
// SplitMix64 (a counter-based generator): a standard normal from (seed, key, axis).
uint64_t splitmix(uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}
double normalAt(uint64_t seed, uint64_t key, uint64_t axis) {
  const uint64_t a = splitmix(seed ^ splitmix(key * 4 + axis));
  const uint64_t b = splitmix(a);
  const double u1 = (static_cast<double>(a >> 11) + 0.5) * 0x1.0p-53;  // (0, 1)
  const double u2 = static_cast<double>(b >> 11) * 0x1.0p-53;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);  // Box-Muller
}
}  // namespace

void EstimatedWrench::configure(const WrenchErrorParams& p, uint64_t seed) {
  p_ = p;
  seed_ = seed;
}

void EstimatedWrench::start(const SimState& initial) { p0_ = initial.T_ge.p; }

void EstimatedWrench::fill(const SimState& st, Wrench& out) const {
  fillEstimatedWrench(st, out);
  if (!p_.any()) return;
  const double dist = (st.T_ge.p - p0_).Norm();
  const uint64_t key = static_cast<uint64_t>(std::llround(st.time_s * 1e9));
  for (int i = 0; i < 3; ++i) {
    double e = p_.scale * out.w[i] + p_.bias_n[i] + p_.drift_n_per_m[i] * dist;
    if (p_.noise_n > 0.0) e += p_.noise_n * normalAt(seed_, key, static_cast<uint64_t>(i));
    out.w[i] += e;
  }
}

void fillTruth(const SimState& st, const SensorTruth& acq, SimTruth& out) {
  out.time_s = st.time_s;
  out.wrench_s = st.wrench_s;
  out.layer_force = st.normal_force;
  out.housing_force = st.housing_force;
  out.tray_pitch = st.tray_pitch;
  out.tray_roll = st.tray_roll;
  out.contact_point_g = acq.contact_point_g;
  out.in_contact = acq.in_contact;
  out.sensor_pose = st.sensor_g;
  out.sim_status = static_cast<int>(st.status);
}

LogRow makeRow(const Scene& sc, double t, int phase, ServoStatus status, const ContactFeatures& f,
               const Pose& cmd, const SimTruth& truth, const Vec6& u_s, int beta) {
  LogRow row;
  const PhaseParams& pp = sc.servo.phases[static_cast<std::size_t>(phase)];
  row.t = t;
  row.phase = phase;
  row.servo = status;
  row.contact = f.contact;
  row.feature_status = f.status;
  const KDL::Frame T_cmd_s = toFrame(cmd) * sc.servo.sensor_mount;
  const KDL::Frame T_gs = toFrame(truth.sensor_pose);
  row.cmd = {T_cmd_s.p.x(), T_cmd_s.p.y(), T_cmd_s.p.z()};
  row.act = {T_gs.p.x(), T_gs.p.y(), T_gs.p.z()};
  row.cmd_rpy = rpyOf(T_cmd_s.M);
  row.act_rpy = rpyOf(T_gs.M);
  row.f = f;
  row.s_d = pp.s_d;
  row.sd_force = pp.s_d(kZ) / sc.servo.c_z;
  row.force_true = -truth.wrench_s[2];
  row.force_layer = truth.layer_force;
  row.housing_force = truth.housing_force;
  row.moment_x_true = truth.wrench_s[3];
  row.moment_y_true = truth.wrench_s[4];
  row.tray_angle_deg = truth.tray_roll * 180.0 / kPi;
  row.true_contact = truth.contact_point_g;
  row.true_in_contact = truth.in_contact;
  row.u_s = u_s;
  row.beta = beta;
  row.feature_age = f.status == FeatureStatus::NotConfigured ? kNaN : t - f.time_s;
  return row;
}

std::vector<PhaseEntry> phaseEntries(const Scene& sc, const std::vector<LogRow>& rows) {
  std::vector<PhaseEntry> out;
  int last = -1;
  for (const auto& r : rows)
    if (r.phase != last) {
      out.push_back({sc.servo.phases[static_cast<std::size_t>(r.phase)].name, r.t});
      last = r.phase;
    }
  return out;
}

void computeSummary(const Scene& sc, RunResult& out) {
  Summary& s = out.summary;
  const auto& rows = out.rows;
  // Phase entry times (first occurrence).
  auto tEnter = [&](const std::string& name) {
    for (const auto& p : out.phases)
      if (p.name == name) return p.t_enter;
    return kNaN;
  };
  s.alignment_time_s = (!sc.metrics.align_from.empty() && !sc.metrics.align_to.empty())
                           ? tEnter(sc.metrics.align_to) - tEnter(sc.metrics.align_from)
                           : kNaN;

  // A loss is a contact that held for >= 50 ms and then stayed absent for
  // >= 50 ms in a phase that needs it: single-frame flicker of a taxel at the
  // firing threshold is not a loss. Times (each row counts one servo period),
  // not row counts, so that the count does not depend on the servo rate.
  s.contact_lost_count = 0;
  const double row_s = 1.0 / sc.rates.servo, hold_s = 0.05 - 1e-6;
  double contact_s = 0, absent_s = 0;
  bool counted = false;
  for (const auto& r : rows) {
    if (r.contact != ContactType::None) {
      contact_s += row_s;
      absent_s = 0;
      counted = false;
    } else {
      absent_s += row_s;
      if (!counted && absent_s >= hold_s) {
        if (sc.servo.phases[static_cast<std::size_t>(r.phase)].requires_contact && contact_s >= hold_s)
          ++s.contact_lost_count;
        counted = true;
        contact_s = 0;
      }
    }
  }

  // Force metrics over the servoing phases, after each phase's transient.
  double sum_f = 0, sum_e2 = 0, max_f = 0, path = 0, t_scored = 0;
  double n = 0, in_band = 0, t_force = 0, t_band = 0;
  const LogRow* prev = nullptr;
  const LogRow* last = nullptr;  // the previous row, scored or not: a scored row stands for the time since it
  double phase_t0 = 0;
  int phase_cur = -1;
  for (const auto& r : rows) {
    if (r.phase != phase_cur) {
      phase_cur = r.phase;
      phase_t0 = r.t;
    }
    const double dt_row = last ? r.t - last->t : 0.0;
    last = &r;
    const PhaseParams& pp = sc.servo.phases[static_cast<std::size_t>(r.phase)];
    const bool scored = sc.metrics.force_phases.empty() ? (pp.requires_contact && !pp.terminal)
                                                        : phaseIn(sc.metrics.force_phases, pp.name);
    if (!scored || r.t - phase_t0 < sc.metrics.transient_s) {
      prev = nullptr;
      continue;
    }
    sum_f += r.force_true;
    sum_e2 += (r.force_true - r.sd_force) * (r.force_true - r.sd_force);
    max_f = std::max(max_f, r.force_true);
    const bool band = std::fabs(r.force_true - r.sd_force) <= sc.metrics.force_band_n;
    in_band += band ? 1.0 : 0.0;
    t_force += dt_row;
    t_band += band ? dt_row : 0.0;
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
  s.force_scored_s = t_force;
  s.force_true_in_band_s = t_band;
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
  const TrayParams* tray = nullptr;
  for (const auto& o : sc.world.objects)
    if (o.type == ObjectType::Tray) tray = &o.tray;
  if (tray) {
    const TrayParams& tp = *tray;
    double amax = 0;
    for (const auto& r : rows) amax = std::max(amax, std::fabs(r.tray_angle_deg));
    s.tray_angle_max_deg = amax;
    // DZMP recovery: from the start of the move until |DZMP_y| <= 0.5 mm for
    // good, on DZMP_y low-passed with kRecoveryFilterS (first order, exact
    // for the held samples), so that sensor noise (0.3 mm per frame at the
    // device's level) does not read as an unbalanced tray.
    const double t_move = tp.move_start_s;
    double t_settled = kNaN;
    std::vector<double> lp(rows.size(), 0.0);
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const bool restart = i == 0 || rows[i - 1].f.contact == ContactType::None;
      const double a = restart ? 1.0 : 1.0 - std::exp(-(rows[i].t - rows[i - 1].t) / kRecoveryFilterS);
      lp[i] = restart ? rows[i].f.dzmp_y : lp[i - 1] + a * (rows[i].f.dzmp_y - lp[i - 1]);
    }
    for (std::size_t k = rows.size(); k-- > 0;) {
      const LogRow& r = rows[k];
      if (r.t < t_move) break;
      if (std::fabs(lp[k]) > 0.0005 || r.f.contact == ContactType::None) break;
      t_settled = r.t;
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
  checkCriteria(sc, s);
}

bool summaryMetric(const Summary& s, const std::string& name, double& v) {
  struct Entry {
    const char* name;
    double value;
  };
  const Entry table[] = {{"contact_lost_count", static_cast<double>(s.contact_lost_count)},
                         {"force_true_mean_n", s.force_true_mean_n},
                         {"force_true_max_n", s.force_true_max_n},
                         {"force_true_rms_error_n", s.force_true_rms_error_n},
                         {"force_true_in_band_fraction", s.force_true_in_band_fraction},
                         {"force_scored_s", s.force_scored_s},
                         {"force_true_in_band_s", s.force_true_in_band_s},
                         {"alignment_time_s", s.alignment_time_s},
                         {"path_length_m", s.path_length_m},
                         {"slide_speed_mps", s.slide_speed_mps},
                         {"dzmp_final_m", s.dzmp_final_m},
                         {"dzmp_recovery_time_s", s.dzmp_recovery_time_s},
                         {"translation_x_m", s.translation_x_m},
                         {"tray_angle_max_deg", s.tray_angle_max_deg},
                         {"sim_time_s", s.sim_time_s},
                         {"exit_code", static_cast<double>(s.exit_code)}};
  for (const Entry& e : table)
    if (name == e.name) {
      v = e.value;
      return true;
    }
  return false;
}

void checkCriteria(const Scene& sc, Summary& s) {
  s.criteria_failed.clear();
  for (const Criterion& c : sc.metrics.criteria) {
    double v = kNaN;
    char buf[160];
    if (!summaryMetric(s, c.metric, v)) {
      std::snprintf(buf, sizeof buf, "%s: not a summary metric", c.metric.c_str());
    } else if (!(v >= c.min)) {  // NaN fails too
      std::snprintf(buf, sizeof buf, "%s = %.6g < %.6g", c.metric.c_str(), v, c.min);
    } else if (!(v <= c.max)) {
      std::snprintf(buf, sizeof buf, "%s = %.6g > %.6g", c.metric.c_str(), v, c.max);
    } else {
      continue;
    }
    s.criteria_failed.emplace_back(buf);
  }
}

}  // namespace sim
}  // namespace tactile
