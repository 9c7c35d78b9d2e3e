// The simulated sensors' fault schedule (tactile_sim_faults/sensor_faults.hpp):
// validation, and the per-cycle application to a frame and to the wrench.
#include "tactile_sim_faults/sensor_faults.hpp"

#include <cmath>

#include "tactile_sim_faults/fault_schema.hpp"

#include <algorithm>
#include <sstream>

namespace tactile {
namespace sim {

namespace {

struct Name {
  SensorFault kind;
  const char* name;
};
constexpr Name kNames[] = {{SensorFault::Stale, "stale"},
                           {SensorFault::Disconnect, "disconnect"},
                           {SensorFault::Nan, "nan"},
                           {SensorFault::Saturated, "saturated"},
                           {SensorFault::Stuck, "stuck"},
                           {SensorFault::Dead, "dead"},
                           {SensorFault::TareCreep, "tare_creep"},
                           {SensorFault::Repeat, "repeat"},
                           {SensorFault::Calibration, "calibration"},
                           {SensorFault::WrenchBias, "wrench_bias"},
                           {SensorFault::WrenchDrift, "wrench_drift"},
                           {SensorFault::WrenchFrame, "wrench_frame"},
                           {SensorFault::WrenchSign, "wrench_sign"},
                           {SensorFault::PadMass, "pad_mass"}};

bool windowFault(SensorFault k) {
  return k == SensorFault::Stale || k == SensorFault::Disconnect || k == SensorFault::Repeat;
}

std::string range(int a, int b) { return "[" + std::to_string(a) + ", " + std::to_string(b) + "]"; }

ConfigResult checkRegion(const std::string& key, const char* what, int a, int b, int n) {
  if (a < 0 || b >= n || a > b)
    return ConfigResult::failure(key + " = " + range(a, b) + ": must be [first, last] within " + range(0, n - 1) +
                                 " with first <= last (the pad's " + what + ", from 0)");
  return ConfigResult::success();
}

}  // namespace

const char* const kSensorFaultNames =
    "stale, disconnect, nan, saturated, stuck, dead, tare_creep, repeat, calibration, wrench_bias, wrench_drift, "
    "wrench_frame, wrench_sign or pad_mass";

const char* toString(SensorFault f) {
  if (f == SensorFault::None) return "none";
  for (const Name& n : kNames)
    if (n.kind == f) return n.name;
  return "?";
}

bool parseSensorFault(const std::string& s, SensorFault& out) {
  if (s.empty() || s == "none") {
    out = SensorFault::None;
    return true;
  }
  for (const Name& n : kNames)
    if (s == n.name) {
      out = n.kind;
      return true;
    }
  return false;
}

// The declared ranges (faultSchema: start_s, duration_s, each kind's numbers
// and the wrench's axes), then what the declaration cannot say: the region
// within the pad, the stuck reading within its full scale.
ConfigResult SensorFaultSchedule::check(const FaultSpec& f, int index) const {
  const std::string at = "faults[" + std::to_string(index) + "]";
  const std::string key = at + ".";
  if (f.kind == SensorFault::None) return ConfigResult::failure(key + "kind: required (" + kSensorFaultNames + ")");
  if (!std::isfinite(f.start_s)) return rangeError(key + "start_s", f.start_s, "must be >= 0 s (simulated time)");
  if (f.kind == SensorFault::WrenchFrame && f.axes == WrenchAxes::Base)
    return ConfigResult::failure(key + "axes = base: must be flange or sensor (the wrong axes)");
  ConfigResult r = schema::checkRanges(faultSchema(), f, at);
  if (!r) return r;
  if (f.kind == SensorFault::Stuck) {
    if ((f.counts >= 0.0) == (f.force_n >= 0.0))
      return ConfigResult::failure(key + "counts / force_n: give exactly one (counts per taxel, or N over the region)");
    if (f.counts >= 0.0 && !(f.counts <= full_scale_))
      return rangeError(key + "counts", f.counts, "must be in [0, " + std::to_string(full_scale_) + "] counts per taxel");
    if (f.force_n >= 0.0 && !(f.force_n <= 1000.0))
      return rangeError(key + "force_n", f.force_n, "must be in [0, 1000] N over the region");
  }
  if (f.kind == SensorFault::Stuck || f.kind == SensorFault::Dead) {
    if (!(r = checkRegion(key + "rows", "rows", f.row0, f.row1, rows_))) return r;
    return checkRegion(key + "cols", "columns", f.col0, f.col1, cols_);
  }
  return ConfigResult::success();
}

ConfigResult SensorFaultSchedule::configure(const std::vector<FaultSpec>& faults, int rows, int cols,
                                            uint16_t full_scale) {
  if (rows < 1 || cols < 1 || rows * cols > kMaxTaxels)
    return ConfigResult::failure("faults: a pad of " + std::to_string(rows) + " x " + std::to_string(cols) +
                                 " taxels is not supported");
  if (faults.size() > static_cast<std::size_t>(kMaxFaults))
    return rangeError("faults", faults.size(), "at most " + std::to_string(kMaxFaults) + " faults");
  n_ = 0;
  rows_ = rows;
  cols_ = cols;
  full_scale_ = full_scale;
  for (const FaultSpec& f : faults) {
    const ConfigResult r = add(f);
    if (!r) {
      n_ = 0;
      classify();
      return r;
    }
  }
  classify();
  reset();
  return ConfigResult::success();
}

ConfigResult SensorFaultSchedule::add(const FaultSpec& in) {
  if (n_ >= kMaxFaults) return rangeError("faults", n_ + 1, "at most " + std::to_string(kMaxFaults) + " faults");
  FaultSpec f = in;
  if (f.row1 < 0) f.row1 = rows_ - 1;
  if (f.col1 < 0) f.col1 = cols_ - 1;
  const ConfigResult r = check(f, n_);
  if (!r) return r;
  const std::size_t k = static_cast<std::size_t>(n_);
  specs_[k] = f;
  stuck_[k].fill(0);
  if (f.kind == SensorFault::Stuck && f.counts >= 0.0)
    for (int row = f.row0; row <= f.row1; ++row)
      for (int c = f.col0; c <= f.col1; ++c)
        stuck_[k][static_cast<std::size_t>(row * cols_ + c)] = static_cast<uint16_t>(std::round(f.counts));
  ++n_;
  classify();
  return ConfigResult::success();
}

ConfigResult SensorFaultSchedule::configure(const std::string& kind, double start, double duration) {
  SensorFault k;
  if (!parseSensorFault(kind, k) ||
      !(k == SensorFault::None || k == SensorFault::Stale || k == SensorFault::Disconnect || k == SensorFault::Nan ||
        k == SensorFault::Saturated))
    return ConfigResult::failure("fault = '" + kind + "': must be '' (none), stale, disconnect, nan or saturated");
  if (k != SensorFault::None && !(std::isfinite(start) && start >= 0.0))
    return rangeError("fault_start", start, "must be >= 0 s (simulated time)");
  if ((k == SensorFault::Stale || k == SensorFault::Disconnect) && !(duration > 0.0 && duration <= 60.0))
    return rangeError("fault_duration", duration, "must be in (0, 60] s for stale and disconnect");
  std::vector<FaultSpec> list;
  if (k != SensorFault::None) {
    FaultSpec f;
    f.kind = k;
    f.start_s = start;
    f.duration_s = windowFault(k) ? duration : 0.0;
    list.push_back(f);
  }
  return configure(list, rows_, cols_, full_scale_);
}

void SensorFaultSchedule::classify() {
  electronics_ = counts_on_ = streams_ = wrench_ = repeat_ = false;
  for (int k = 0; k < n_; ++k) {
    const SensorFault f = specs_[static_cast<std::size_t>(k)].kind;
    electronics_ = electronics_ || f == SensorFault::Calibration || f == SensorFault::TareCreep;
    counts_on_ = counts_on_ || f == SensorFault::Stuck || f == SensorFault::Dead || f == SensorFault::Saturated;
    streams_ = streams_ || windowFault(f) || f == SensorFault::Nan;
    repeat_ = repeat_ || f == SensorFault::Repeat;
    wrench_ = wrench_ || wrenchFault(f);
  }
}

void SensorFaultSchedule::reset() {
  shot_.fill(0);
  shots_ = 0;
  fired_ = false;
  link_ = SensorLink::NewFrame;
  last_action_ = FaultAction::Deliver;
  have_held_ = false;
}

double SensorFaultSchedule::loadScale(double t) {
  double s = 1.0;
  for (int k = 0; k < n_; ++k) {
    const FaultSpec& f = specs_[static_cast<std::size_t>(k)];
    if (f.kind == SensorFault::Calibration && f.active(t)) {
      s *= f.scale;
      fired_ = true;
    }
  }
  return s;
}

double SensorFaultSchedule::zeroOffsetCounts(double t) {
  double o = 0.0;
  for (int k = 0; k < n_; ++k) {
    const FaultSpec& f = specs_[static_cast<std::size_t>(k)];
    if (f.kind == SensorFault::TareCreep && f.active(t)) {
      o += f.counts_per_min * (t - f.start_s) / 60.0;
      fired_ = true;
    }
  }
  return o;
}

void SensorFaultSchedule::applyCounts(double t, const double* threshold_counts, RawTactileFrame& raw) {
  const int cols = raw.cols;
  for (int k = 0; k < n_; ++k) {
    const std::size_t kk = static_cast<std::size_t>(k);
    const FaultSpec& f = specs_[kk];
    if (f.kind == SensorFault::Saturated) {
      if (shot_[kk] || t < f.start_s) continue;
      shot_[kk] = 1;
      ++shots_;
      fired_ = true;
      saturateFrame(raw, full_scale_);
      continue;
    }
    if ((f.kind != SensorFault::Stuck && f.kind != SensorFault::Dead) || !f.active(t)) continue;
    fired_ = true;
    for (int r = f.row0; r <= f.row1 && r < raw.rows; ++r)
      for (int c = f.col0; c <= f.col1 && c < cols; ++c) {
        const std::size_t i = static_cast<std::size_t>(r * cols + c);
        uint16_t v = f.kind == SensorFault::Stuck ? stuck_[kk][i] : 0;
        if (threshold_counts != nullptr && v < threshold_counts[i]) v = 0;
        raw.counts[i] = v;
      }
  }
}

FaultAction SensorFaultSchedule::stream(RawTactileFrame& raw) {
  const double t = raw.time_s;
  bool withhold = false, down = false, repeat = false, nan = false;
  for (int k = 0; k < n_; ++k) {
    const std::size_t kk = static_cast<std::size_t>(k);
    const FaultSpec& f = specs_[kk];
    if (windowFault(f.kind) && f.active(t)) {
      fired_ = true;
      withhold = withhold || f.kind != SensorFault::Repeat;
      down = down || f.kind == SensorFault::Disconnect;
      repeat = repeat || f.kind == SensorFault::Repeat;
    } else if (f.kind == SensorFault::Nan && !shot_[kk] && t >= f.start_s) {
      shot_[kk] = 1;
      ++shots_;
      fired_ = true;
      nan = true;
    }
  }
  link_ = down ? SensorLink::Disconnected : link_ == SensorLink::Disconnected ? SensorLink::Reconnected : SensorLink::NewFrame;
  if (withhold) return last_action_ = FaultAction::Withhold;
  const std::size_t n = static_cast<std::size_t>(raw.rows) * raw.cols;
  last_action_ = nan ? FaultAction::NanFrame : FaultAction::Deliver;
  if (repeat && have_held_) {
    std::copy_n(held_.begin(), n, raw.counts.begin());
    if (!nan) last_action_ = FaultAction::Repeat;
  } else if (repeat_) {
    std::copy_n(raw.counts.begin(), n, held_.begin());
    have_held_ = true;
  }
  return last_action_;
}

void SensorFaultSchedule::wrenchAt(double t, WrenchFaultTerms& out) const {
  out = WrenchFaultTerms{};
  for (int k = 0; k < n_; ++k) {
    const FaultSpec& f = specs_[static_cast<std::size_t>(k)];
    if (!wrenchFault(f.kind) || !f.active(t)) continue;
    out.any = true;
    for (std::size_t i = 0; i < 3; ++i) {
      if (f.kind == SensorFault::WrenchBias) out.offset_n[i] += f.bias_n[i];
      if (f.kind == SensorFault::WrenchDrift) out.offset_n[i] += f.drift_n_per_min[i] * (t - f.start_s) / 60.0;
    }
    if (f.kind == SensorFault::WrenchFrame) out.axes = f.axes;
    if (f.kind == SensorFault::WrenchSign) out.negate = !out.negate;
    if (f.kind == SensorFault::PadMass) out.mass_kg += f.mass_kg;
  }
}

bool SensorFaultSchedule::linkDown(double t) const {
  for (int k = 0; k < n_; ++k) {
    const FaultSpec& f = specs_[static_cast<std::size_t>(k)];
    if (f.kind == SensorFault::Disconnect && f.active(t)) return true;
  }
  return false;
}

bool SensorFaultSchedule::stalled(double t) const {
  for (int k = 0; k < n_; ++k) {
    const FaultSpec& f = specs_[static_cast<std::size_t>(k)];
    if (f.kind == SensorFault::Stale && f.active(t)) return true;
  }
  return false;
}

}  // namespace sim
}  // namespace tactile
