#include "tactile_sim_lwr/taxel_response.hpp"

#include "tactile_sim_lwr/sim_schema.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace tactile {
namespace sim {

namespace {
ConfigResult checkMonotone(const std::array<double, 4>& c, const std::string& key) {
  if (!(c[1] > 0.0) || !std::isfinite(c[1]))
    return rangeError(key + "[1]", c[1], "must be > 0 (N/count) for the simulated sensor (monotone response)");
  for (int k = 2; k < 4; ++k)
    if (!(c[static_cast<std::size_t>(k)] >= 0.0) || !std::isfinite(c[static_cast<std::size_t>(k)]))
      return rangeError(key + "[" + std::to_string(k) + "]", c[static_cast<std::size_t>(k)],
                        "must be >= 0 for the simulated sensor (monotone convex response)");
  if (!(c[0] >= 0.0) || !std::isfinite(c[0])) return rangeError(key + "[0]", c[0], "must be >= 0 (N)");
  return ConfigResult::success();
}

// The parameters' ranges: the calibration (the reader's checks, and a
// monotone response the simulated sensor can invert), the noise, the effects.
ConfigResult checkParams(const TaxelResponseParams& p) {
  Calibration probe;  // the same validation as the reader's
  ConfigResult r = probe.configure(p.calibration);
  if (!r) return r;
  if (!(p.noise_counts >= 0.0) || p.noise_counts > 1000.0)
    return rangeError("sensor.noise_counts", p.noise_counts, "must be in [0, 1000] counts");
  if (!(p.threshold >= 0.0) || !std::isfinite(p.threshold)) return rangeError("sensor.threshold", p.threshold, "must be >= 0 (N)");
  const CalibrationParams& c = p.calibration;
  if (!(r = checkMonotone(c.coeffs, "calibration.coeffs"))) return r;
  if (c.use_border && !(r = checkMonotone(c.border_coeffs, "calibration.border_coeffs"))) return r;
  for (std::size_t i = 0; i < c.taxels.size(); ++i)
    if (!(r = checkMonotone(c.taxels[i], "calibration.taxels[" + std::to_string(i) + "]"))) return r;
  const SensorEffects& e = p.effects;
  const int n = c.rows * c.cols;
  if (!(r = schema::checkRanges(sensorEffectsSchema(), e, "effects"))) return r;
  if (e.dead_taxels < 0 || e.dead_taxels > n)
    return rangeError("effects.dead_taxels", e.dead_taxels, "must be in [0, " + std::to_string(n) + "] (rows x cols)");
  for (std::size_t j = 0; j < e.dead_list.size(); ++j) {
    const auto& rc = e.dead_list[j];
    if (rc[0] < 0 || rc[0] >= c.rows || rc[1] < 0 || rc[1] >= c.cols)
      return ConfigResult::failure("effects.dead_taxels[" + std::to_string(j) + "] = [" + std::to_string(rc[0]) + ", " +
                                   std::to_string(rc[1]) + "] out of range: row in [0, " + std::to_string(c.rows - 1) +
                                   "], col in [0, " + std::to_string(c.cols - 1) + "]");
  }
  if (!(e.max_frame_rate_hz > 0.0) || e.max_frame_rate_hz > 1e5)
    return rangeError("effects.max_frame_rate_hz", e.max_frame_rate_hz, "must be in (0, 1e5] Hz");
  return ConfigResult::success();
}
}  // namespace

ConfigResult TaxelResponse::configure(const TaxelResponseParams& p) {
  ConfigResult r = checkParams(p);
  if (!r) return r;
  const CalibrationParams& c = p.calibration;
  const SensorEffects& e = p.effects;
  const int n = c.rows * c.cols;

  if (!(r = faults_.configure(p.faults, c.rows, c.cols, c.full_scale))) return r;

  params_ = p;
  n_ = n;
  rows_ = c.rows;
  cols_ = c.cols;
  for (int row = 0; row < c.rows; ++row)
    for (int col = 0; col < c.cols; ++col) {
      const std::size_t i = static_cast<std::size_t>(row * c.cols + col);
      const bool border = row == 0 || col == 0 || row == c.rows - 1 || col == c.cols - 1;
      coeffs_[i] = !c.taxels.empty() ? c.taxels[i] : (c.use_border && border ? c.border_coeffs : c.coeffs);
    }
  device_noise_ = 1e300;
  for (int i = 0; i < n_; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    threshold_counts_[k] = countsFor(i, p.threshold);
    device_noise_ = std::min(device_noise_, threshold_counts_[k] / kDeviceNoiseZ);
  }
  noise_ = e.device_noise ? device_noise_ : p.noise_counts;

  // The static per-taxel draws, from their own generator (the noise sequence
  // stays that of the seed whatever effects are on).
  std::mt19937_64 g(p.seed ^ 0x5EEDC0FFEE123457ULL);
  std::normal_distribution<double> nd(0.0, 1.0);
  gain_.fill(1.0);
  calib_err_.fill(0.0);
  dead_.fill(0);
  for (int i = 0; i < n_; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    if (e.gain_spread > 0.0) gain_[k] = std::max(0.05, 1.0 + e.gain_spread * nd(g));
  }
  for (int i = 0; i < n_; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    if (e.calibration_error > 0.0) calib_err_[k] = std::clamp(e.calibration_error * nd(g), -0.9, 0.9);
  }
  if (!e.dead_list.empty()) {
    for (const auto& rc : e.dead_list) dead_[static_cast<std::size_t>(rc[0] * c.cols + rc[1])] = 1;
  } else if (e.dead_taxels > 0) {  // partial Fisher-Yates: distinct seeded positions
    std::array<int, kMaxTaxels> idx{};
    for (int i = 0; i < n_; ++i) idx[static_cast<std::size_t>(i)] = i;
    for (int j = 0; j < e.dead_taxels; ++j) {
      std::uniform_int_distribution<int> u(j, n_ - 1);
      std::swap(idx[static_cast<std::size_t>(j)], idx[static_cast<std::size_t>(u(g))]);
      dead_[static_cast<std::size_t>(idx[static_cast<std::size_t>(j)])] = 1;
    }
  }
  layer_on_ = e.crosstalk > 0.0 || e.hysteresis > 0.0 || e.creep_fraction > 0.0;
  taxel_on_ = e.gain_spread > 0.0 || e.calibration_error > 0.0 || e.dead_taxels > 0 || !e.dead_list.empty();

  for (int i = 0; i < n_; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    // Below n_silent = threshold - 10 sigma - 1 counts a taxel gets no noise
    // draw and rounds below the threshold: it reads 0. The force of n_silent,
    // through the taxel's gain and calibration error: n = g p^-1(f / (1 + e)).
    const double n_silent = threshold_counts_[k] - 10.0 * noise_ - 1.0;
    silent_force_[k] = n_silent > 0.0 ? (1.0 + calib_err_[k]) * forceFor(i, n_silent / gain_[k]) : 0.0;
    if (dead_[k]) silent_force_[k] = 1e300;  // never reads
  }

  // The stuck faults given in N: the counts the reader's calibration maps to that force.
  faults_.resolveForces([this](int i, double f) { return countsFor(i, f); });

  delay_ = e.wts_transfer_delay_s;
  ring_.clear();
  if (delay_ > 0.0) {
    // Frames in flight: at most delay * rate + 1, plus one for the rounding of the delivery tick.
    const auto cap = static_cast<std::size_t>(std::ceil(delay_ * e.max_frame_rate_hz)) + 2;
    ring_.assign(cap, RawTactileFrame{});
  }
  reseed(p.seed);
  return ConfigResult::success();
}

void TaxelResponse::reseed(uint64_t seed) {
  rng_.seed(seed);
  normal_.reset();
  hyst_.fill(0.0);
  creep_.fill(0.0);
  creep_in_.fill(0.0);
  have_last_ = false;
  last_t_ = 0.0;
  head_ = 0;
  count_ = 0;
  overruns_ = 0;
  faults_.reset();
}

double TaxelResponse::forceFor(int i, double n) const {
  const auto& k = coeffs_[static_cast<std::size_t>(i)];
  return k[0] + n * (k[1] + n * (k[2] + n * k[3]));
}

double TaxelResponse::countsFor(int i, double force) const {
  const auto& k = coeffs_[static_cast<std::size_t>(i)];
  if (!(force > k[0])) return 0.0;  // NaN, <= 0 or below the offset
  // Monotone convex polynomial: Newton from the linear guess (>= the root)
  // converges monotonically from above.
  const double target = force - k[0];
  double n = std::min(target / k[1], 1e6);
  for (int it = 0; it < 60; ++it) {
    const double f = n * (k[1] + n * (k[2] + n * k[3])) - target;
    const double df = k[1] + n * (2.0 * k[2] + 3.0 * n * k[3]);
    const double step = f / df;
    n -= step;
    if (std::fabs(step) < 1e-9) break;
  }
  return n < 0.0 ? 0.0 : n;
}

void TaxelResponse::layer(const TactileFrame& forces, double t) {
  const SensorEffects& e = params_.effects;
  // 1. Load spreading to the 4-neighbours (total conserved: a border taxel
  //    keeps the share of its missing neighbours).
  if (e.crosstalk > 0.0) {
    const double c = e.crosstalk;
    for (int r = 0; r < rows_; ++r)
      for (int col = 0; col < cols_; ++col) {
        const int i = r * cols_ + col;
        const double f = forces.force[static_cast<std::size_t>(i)];
        double out = f, in = 0.0;
        if (r > 0) { out -= c * f; in += c * forces.force[static_cast<std::size_t>(i - cols_)]; }
        if (r + 1 < rows_) { out -= c * f; in += c * forces.force[static_cast<std::size_t>(i + cols_)]; }
        if (col > 0) { out -= c * f; in += c * forces.force[static_cast<std::size_t>(i - 1)]; }
        if (col + 1 < cols_) { out -= c * f; in += c * forces.force[static_cast<std::size_t>(i + 1)]; }
        load_[static_cast<std::size_t>(i)] = out + in;
      }
  } else {
    for (int i = 0; i < n_; ++i) load_[static_cast<std::size_t>(i)] = forces.force[static_cast<std::size_t>(i)];
  }
  // 2. Hysteresis: relative play band [(1 - h) x, (1 + h) x].
  if (e.hysteresis > 0.0) {
    const double lo = 1.0 - e.hysteresis, hi = 1.0 + e.hysteresis;
    for (int i = 0; i < n_; ++i) {
      const std::size_t k = static_cast<std::size_t>(i);
      const double x = load_[k] > 0.0 ? load_[k] : 0.0;  // NaN and negative loads: none
      hyst_[k] = std::min(std::max(hyst_[k], lo * x), hi * x);
      load_[k] = hyst_[k];
    }
  }
  // 3. Creep: z' = (a y - z) / tau, exact for y held since the last acquisition.
  if (e.creep_fraction > 0.0) {
    const double dt = have_last_ && t > last_t_ ? t - last_t_ : 0.0;
    const double w = dt > 0.0 ? 1.0 - std::exp(-dt / e.creep_tau_s) : 0.0;  // one exp per frame
    const double a = e.creep_fraction;
    for (int i = 0; i < n_; ++i) {
      const std::size_t k = static_cast<std::size_t>(i);
      creep_[k] += (a * creep_in_[k] - creep_[k]) * w;
      const double y = load_[k] >= 0.0 ? load_[k] : 0.0;
      creep_in_[k] = y;
      load_[k] = y + creep_[k];
    }
  }
  last_t_ = t;
  have_last_ = true;
}

int TaxelResponse::respond(const TactileFrame& forces, double t, RawTactileFrame& raw) {
  const CalibrationParams& c = params_.calibration;
  raw.time_s = t;
  raw.rows = static_cast<uint16_t>(c.rows);
  raw.cols = static_cast<uint16_t>(c.cols);
  const double fs = c.full_scale;
  const double* load = forces.force.data();
  if (layer_on_) {
    layer(forces, t);
    load = load_.data();
  }
  const double sigma = noise_;
  // Faults of the electronics (none: scale 1, offset 0): the calibration's
  // scale on the load, the zero's drift on the counts.
  double scale = 1.0, offset = 0.0;
  if (faults_.electronics()) {
    scale = faults_.loadScale(t);
    offset = faults_.zeroOffsetCounts(t);
  }
  const bool shifted = offset != 0.0;  // an unloaded taxel may fire: no silent shortcut
  int maxc = 0;
  for (int i = 0; i < n_; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    const double f = scale * load[k];
    if (shifted ? dead_[k] != 0 : !(f >= silent_force_[k])) {  // reads 0 whatever the noise (no draw); dead taxels too
      raw.counts[k] = 0;
      continue;
    }
    double n = taxel_on_ ? gain_[k] * countsFor(i, f / (1.0 + calib_err_[k])) : countsFor(i, f);
    n += offset;
    if (sigma > 0.0 && n + 10.0 * sigma >= threshold_counts_[k]) n += sigma * normal_(rng_);
    n = std::round(n);
    if (n < 0.0) n = 0.0;
    if (n > fs) n = fs;
    if (n < threshold_counts_[k]) n = 0.0;
    raw.counts[k] = static_cast<uint16_t>(n);
    if (static_cast<int>(n) > maxc) maxc = static_cast<int>(n);
  }
  if (faults_.counts()) {  // stuck, dead, saturated: after the electronics
    faults_.applyCounts(t, threshold_counts_.data(), raw);
    maxc = 0;
    for (int i = 0; i < n_; ++i) maxc = std::max(maxc, static_cast<int>(raw.counts[static_cast<std::size_t>(i)]));
  }
  return maxc;
}

bool TaxelResponse::respondAndEmit(const TactileFrame& forces, double t, RawTactileFrame& raw) {
  if (!faults_.streams()) {
    respond(forces, t, raw);
    return true;
  }
  respond(forces, t, scratch_);
  if (!emit(scratch_)) return false;
  raw = scratch_;
  return true;
}

bool TaxelResponse::acquire(const TactileFrame& forces, double t, RawTactileFrame& raw) {
  if (!(delay_ > 0.0)) return respondAndEmit(forces, t, raw);
  const std::size_t cap = ring_.size();
  if (count_ == cap) {  // full: the oldest frame is lost
    head_ = (head_ + 1) % cap;
    --count_;
    ++overruns_;
  }
  respond(forces, t, ring_[(head_ + count_) % cap]);
  ++count_;
  return false;
}

bool TaxelResponse::deliver(double now, RawTactileFrame& raw) {
  if (count_ == 0) return false;
  bool any = false;
  const std::size_t cap = ring_.size();
  while (count_ > 0 && ring_[head_].time_s + delay_ <= now + 1e-9) {
    RawTactileFrame& arrived = ring_[head_];
    if (!faults_.streams() || emit(arrived)) {  // the stream's faults as it reaches the reader
      raw = arrived;
      any = true;
    }
    head_ = (head_ + 1) % cap;
    --count_;
  }
  return any;
}

}  // namespace sim
}  // namespace tactile
