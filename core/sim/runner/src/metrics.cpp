// The run's summary metrics from its rows (computeSummary).
#include "tactile_sim_runner/loop.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace tactile {
namespace sim {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// Time constant (s) of the low-pass on DZMP_y for the recovery time: the
/// programs' `aligned` filter_s, about 28 frames of the 140 Hz WTS.
constexpr double kRecoveryFilterS = 0.1;

bool phaseIn(const std::vector<std::string>& list, const std::string& name) {
  for (const auto& s : list)
    if (s == name) return true;
  return false;
}


// Phase entry time (first occurrence) of phase `name`; NaN if never entered.
double phaseEnterTime(const RunResult& out, const std::string& name) {
  for (const auto& p : out.phases)
    if (p.name == name) return p.t_enter;
  return kNaN;
}

// Contact losses: a contact that held for >= 50 ms and then stayed absent for
// >= 50 ms in a phase that needs it: single-frame flicker of a taxel at the
// firing threshold is not a loss. Times (each row counts one servo period),
// not row counts, so that the count does not depend on the servo rate.
int contactLossCount(const Scene& sc, const std::vector<LogRow>& rows) {
  int lost = 0;
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
        if (sc.servo.phases[static_cast<std::size_t>(r.phase)].requires_contact && contact_s >= hold_s) ++lost;
        counted = true;
        contact_s = 0;
      }
    }
  }
  return lost;
}

// Per row, the phase it is scored as: its own, or for the rows of a detour
// (the run leaving a scored phase and back in it within transient_s: the end
// rule's check returning to `explore` at a crest) the phase it left.
std::vector<int> scoredAs(const Scene& sc, const std::vector<LogRow>& rows,
                          const std::function<bool(int)>& scoredPhase) {
  std::vector<int> as(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) as[i] = rows[i].phase;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    if (rows[i].phase == rows[i - 1].phase || !scoredPhase(rows[i - 1].phase) || scoredPhase(rows[i].phase)) continue;
    std::size_t j = i;
    while (j < rows.size() && !scoredPhase(rows[j].phase)) ++j;
    if (j < rows.size() && rows[j].phase == rows[i - 1].phase && rows[j].t - rows[i].t < sc.metrics.transient_s)
      for (std::size_t k = i; k < j; ++k) as[k] = rows[i - 1].phase;
    i = j;
  }
  return as;
}

// The sums of one window of rows (Summary: the slide, the scored window).
struct Window {
  double sum_f = 0, sum_e2 = 0, max_f = 0, n = 0, in_band = 0;  // the true force, per row
  double t_force = 0, t_band = 0;     // each row standing for the time since the log's previous row
  double path = 0, duration = 0, t_contact = 0;  // between consecutive rows of the window
  const LogRow* prev = nullptr;       // the window's previous row if it is the log's previous row

  void add(const LogRow& r, double dt_row, double band_n) {
    sum_f += r.force_true;
    sum_e2 += (r.force_true - r.sd_force) * (r.force_true - r.sd_force);
    max_f = std::max(max_f, r.force_true);
    const bool band = std::fabs(r.force_true - r.sd_force) <= band_n;
    in_band += band ? 1.0 : 0.0;
    t_force += dt_row;
    t_band += band ? dt_row : 0.0;
    ++n;
    if (prev) {
      duration += r.t - prev->t;
      if (prev->true_in_contact && r.true_in_contact) {
        double d2 = 0;
        for (int k = 0; k < 3; ++k)
          d2 += (r.true_contact[k] - prev->true_contact[k]) * (r.true_contact[k] - prev->true_contact[k]);
        path += std::sqrt(d2);
        t_contact += r.t - prev->t;
      }
    }
    prev = &r;
  }
  double mean() const { return n ? sum_f / n : kNaN; }
  double max() const { return n ? max_f : kNaN; }
  double rms() const { return n ? std::sqrt(sum_e2 / n) : kNaN; }
  double inBand() const { return n ? in_band / n : kNaN; }
  double speed() const { return t_contact > 0 ? path / t_contact : kNaN; }
};

// Force metrics (true force: mean, max, RMS error, in-band fraction and time)
// and the true contact's path, duration and mean speed over the slide and over
// the scored window (Summary's header says what each is).
void forceAndPathMetrics(const Scene& sc, const std::vector<LogRow>& rows, Summary& s) {
  const std::function<bool(int)> scoredPhase = [&](int phase) {
    const PhaseParams& pp = sc.servo.phases[static_cast<std::size_t>(phase)];
    return sc.metrics.force_phases.empty() ? (pp.requires_contact && !pp.terminal)
                                           : phaseIn(sc.metrics.force_phases, pp.name);
  };
  const std::vector<int> as = scoredAs(sc, rows, scoredPhase);
  Window slide, scored;
  const LogRow* last = nullptr;  // the previous row, scored or not: a scored row stands for the time since it
  double phase_t0 = 0;
  int phase_cur = -1;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const LogRow& r = rows[i];
    if (as[i] != phase_cur) {
      phase_cur = as[i];
      phase_t0 = r.t;
    }
    const double dt_row = last ? r.t - last->t : 0.0;
    last = &r;
    if (!scoredPhase(as[i])) {
      slide.prev = scored.prev = nullptr;
      continue;
    }
    slide.add(r, dt_row, sc.metrics.force_band_n);
    if (r.t - phase_t0 < sc.metrics.transient_s) {
      scored.prev = nullptr;
      continue;
    }
    scored.add(r, dt_row, sc.metrics.force_band_n);
  }
  s.force_true_mean_n = scored.mean();
  s.force_true_max_n = scored.max();
  s.force_true_rms_error_n = scored.rms();
  s.force_true_in_band_fraction = scored.inBand();
  s.force_scored_s = scored.t_force;
  s.force_true_in_band_s = scored.t_band;
  s.path_length_m = scored.path;
  s.slide_speed_mps = scored.speed();
  s.scored_duration_s = scored.duration;
  s.slide_path_m = slide.path;
  s.slide_duration_s = slide.duration;
  s.slide_mean_speed_mps = slide.speed();
  s.slide_force_true_mean_n = slide.mean();
  s.slide_force_true_max_n = slide.max();
  s.slide_force_true_rms_error_n = slide.rms();
  s.slide_force_true_in_band_fraction = slide.inBand();
}

// When the fault that ended the run happened: the first row with the servo's
// fatal status (status servo_*), or the end of the run (sim_*: the physics
// step that failed); NaN for an ok run.
double faultTime(const std::vector<LogRow>& rows, const Summary& s) {
  if (s.status == "ok") return kNaN;
  for (const auto& r : rows)
    if (s.status == std::string("servo_") + toString(r.servo)) return r.t;
  return s.sim_time_s;
}

// Final DZMP_y: mean over the last 0.5 s of the rows in contact; NaN if none.
double finalDzmp(const std::vector<LogRow>& rows) {
  double sd = 0;
  double nd = 0;
  const double t_end = rows.empty() ? 0 : rows.back().t;
  for (const auto& r : rows)
    if (r.t >= t_end - 0.5 && r.f.contact != ContactType::None) {
      sd += r.f.dzmp_y;
      ++nd;
    }
  return nd ? sd / nd : kNaN;
}

// The scene's tray (the last one), nullptr without one.
const TrayParams* sceneTray(const Scene& sc) {
  const TrayParams* tray = nullptr;
  for (const auto& o : sc.world.objects)
    if (o.type == ObjectType::Tray) tray = &o.tray;
  return tray;
}

// DZMP recovery: from the start of the move until |DZMP_y| <= 0.5 mm for
// good, on DZMP_y low-passed with kRecoveryFilterS (first order, exact
// for the held samples), so that sensor noise (0.3 mm per frame at the
// device's level) does not read as an unbalanced tray. NaN if never settled.
double dzmpRecoveryTime(const std::vector<LogRow>& rows, double t_move) {
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
  return std::isnan(t_settled) ? kNaN : t_settled - t_move;
}

// Co-manipulation metrics (scenes with a tray; NaN without one): the tray's
// largest tilt, the DZMP recovery time and the translation along the
// sensor's x axis at the start of the move.
void trayMetrics(const Scene& sc, const std::vector<LogRow>& rows, Summary& s) {
  const TrayParams* tray = sceneTray(sc);
  if (!tray) {
    s.tray_angle_max_deg = kNaN;
    s.dzmp_recovery_time_s = kNaN;
    s.translation_x_m = kNaN;
    return;
  }
  const TrayParams& tp = *tray;
  double amax = 0;
  for (const auto& r : rows) amax = std::max(amax, std::fabs(r.tray_angle_deg));
  s.tray_angle_max_deg = amax;
  const double t_move = tp.move_start_s;
  s.dzmp_recovery_time_s = dzmpRecoveryTime(rows, t_move);
  // Translation along the sensor's initial x axis since the move.
  const LogRow* before = nullptr;
  for (const auto& r : rows)
    if (r.t <= t_move) before = &r;
  if (before && !rows.empty()) {
    const KDL::Vector xs = KDL::Rotation::RPY(before->act_rpy[0], before->act_rpy[1], before->act_rpy[2]).UnitX();
    const KDL::Vector d(rows.back().act[0] - before->act[0], rows.back().act[1] - before->act[1],
                        rows.back().act[2] - before->act[2]);
    s.translation_x_m = KDL::dot(d, xs);
  }
}

}  // namespace

void computeSummary(const Scene& sc, RunResult& out) {
  Summary& s = out.summary;
  const auto& rows = out.rows;
  s.alignment_time_s = (!sc.metrics.align_from.empty() && !sc.metrics.align_to.empty())
                           ? phaseEnterTime(out, sc.metrics.align_to) - phaseEnterTime(out, sc.metrics.align_from)
                           : kNaN;
  s.contact_lost_count = contactLossCount(sc, rows);
  forceAndPathMetrics(sc, rows, s);
  s.fault_time_s = faultTime(rows, s);
  s.dzmp_final_m = finalDzmp(rows);
  trayMetrics(sc, rows, s);
  checkCriteria(sc, s);
}

}  // namespace sim
}  // namespace tactile
