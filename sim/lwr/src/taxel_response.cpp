#include "tactile_sim/taxel_response.hpp"

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
}  // namespace

ConfigResult TaxelResponse::configure(const TaxelResponseParams& p) {
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
  params_ = p;
  n_ = c.rows * c.cols;
  for (int row = 0; row < c.rows; ++row)
    for (int col = 0; col < c.cols; ++col) {
      const std::size_t i = static_cast<std::size_t>(row * c.cols + col);
      const bool border = row == 0 || col == 0 || row == c.rows - 1 || col == c.cols - 1;
      coeffs_[i] = !c.taxels.empty() ? c.taxels[i] : (c.use_border && border ? c.border_coeffs : c.coeffs);
    }
  for (int i = 0; i < n_; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    threshold_counts_[k] = countsFor(i, p.threshold);
    // Below n_silent = threshold - 10 sigma - 1 counts a taxel gets no noise
    // draw and rounds below the threshold: it reads 0. The force of n_silent.
    const double n_silent = threshold_counts_[k] - 10.0 * p.noise_counts - 1.0;
    silent_force_[k] = n_silent > 0.0 ? forceFor(i, n_silent) : 0.0;
  }
  reseed(p.seed);
  return ConfigResult::success();
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

int TaxelResponse::respond(const TactileFrame& forces, double t, RawTactileFrame& raw) {
  const CalibrationParams& c = params_.calibration;
  raw.time_s = t;
  raw.rows = static_cast<uint16_t>(c.rows);
  raw.cols = static_cast<uint16_t>(c.cols);
  const double fs = c.full_scale;
  int maxc = 0;
  for (int i = 0; i < n_; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    const double f = forces.force[k];
    if (!(f >= silent_force_[k])) {  // reads 0 whatever the noise (no draw)
      raw.counts[k] = 0;
      continue;
    }
    double n = countsFor(i, f);
    if (params_.noise_counts > 0.0 && n + 10.0 * params_.noise_counts >= threshold_counts_[k])
      n += params_.noise_counts * normal_(rng_);
    n = std::round(n);
    if (n < 0.0) n = 0.0;
    if (n > fs) n = fs;
    if (n < threshold_counts_[k]) n = 0.0;
    raw.counts[k] = static_cast<uint16_t>(n);
    if (static_cast<int>(n) > maxc) maxc = static_cast<int>(n);
  }
  return maxc;
}

}  // namespace sim
}  // namespace tactile
