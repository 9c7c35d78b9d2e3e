#include "tactile_features/calibration.hpp"

#include "tactile_features/features_schema.hpp"

#include <cmath>
#include <string>

namespace tactile {

namespace {
bool finiteCoeffs(const std::array<double, 4>& c) {
  for (double v : c)
    if (!std::isfinite(v)) return false;
  return true;
}
}  // namespace

ConfigResult Calibration::configure(const CalibrationParams& p) {
  configured_ = false;
  if (p.rows < 1 || p.rows > kMaxRows)
    return rangeError("calibration.rows", p.rows, "must be in [1, " + std::to_string(kMaxRows) + "]");
  if (p.cols < 1 || p.cols > kMaxCols)
    return rangeError("calibration.cols", p.cols, "must be in [1, " + std::to_string(kMaxCols) + "]");
  const ConfigResult declared = schema::checkRanges(calibrationSchema(), CalibrationFile::of(p), "calibration");
  if (!declared) return declared;
  if (!finiteCoeffs(p.coeffs)) return ConfigResult::failure("calibration.coeffs: must be finite");
  if (p.use_border && !finiteCoeffs(p.border_coeffs))
    return ConfigResult::failure("calibration.border_coeffs: must be finite");
  const std::size_t n = static_cast<std::size_t>(p.rows * p.cols);
  if (!p.taxels.empty() && p.taxels.size() != n)
    return rangeError("calibration.taxels (size)", p.taxels.size(),
                      "must be empty or rows*cols = " + std::to_string(n) + " entries");
  for (std::size_t i = 0; i < p.taxels.size(); ++i)
    if (!finiteCoeffs(p.taxels[i]))
      return ConfigResult::failure("calibration.taxels[" + std::to_string(i) + "]: must be finite");

  for (int r = 0; r < p.rows; ++r) {
    for (int c = 0; c < p.cols; ++c) {
      const std::size_t i = static_cast<std::size_t>(r * p.cols + c);
      const bool border = r == 0 || c == 0 || r == p.rows - 1 || c == p.cols - 1;
      if (!p.taxels.empty())
        coeffs_[i] = p.taxels[i];
      else if (p.use_border && border)
        coeffs_[i] = p.border_coeffs;
      else
        coeffs_[i] = p.coeffs;
    }
  }
  params_ = p;
  tare_.fill(0);
  configured_ = true;
  return ConfigResult::success();
}

CalibrationStatus Calibration::step(const RawTactileFrame& raw, TactileFrame& out) const {
  if (!configured_) return CalibrationStatus::NotConfigured;
  if (raw.rows != params_.rows || raw.cols != params_.cols) return CalibrationStatus::BadDimensions;
  out.time_s = raw.time_s;
  out.seq = raw.seq;
  out.rows = raw.rows;
  out.cols = raw.cols;
  const int n = params_.rows * params_.cols;
  uint16_t saturated = 0;
  for (int i = 0; i < n; ++i) {
    const uint16_t v = raw.counts[static_cast<std::size_t>(i)];
    if (v >= params_.full_scale) ++saturated;
    const uint16_t t = tare_[static_cast<std::size_t>(i)];
    const double x = v > t ? static_cast<double>(v - t) : 0.0;
    const auto& k = coeffs_[static_cast<std::size_t>(i)];
    const double f = x > 0.0 ? k[0] + x * (k[1] + x * (k[2] + x * k[3])) : 0.0;  // Horner
    out.force[static_cast<std::size_t>(i)] = f > 0.0 ? f : 0.0;
  }
  out.saturated_count = saturated;
  return saturated ? CalibrationStatus::Saturated : CalibrationStatus::Ok;
}

CalibrationStatus Calibration::tare(const RawTactileFrame& raw) {
  if (!configured_) return CalibrationStatus::NotConfigured;
  if (raw.rows != params_.rows || raw.cols != params_.cols) return CalibrationStatus::BadDimensions;
  const int n = params_.rows * params_.cols;
  for (int i = 0; i < n; ++i)
    if (raw.counts[static_cast<std::size_t>(i)] > params_.max_tare) return CalibrationStatus::TareRejected;
  for (int i = 0; i < n; ++i) tare_[static_cast<std::size_t>(i)] = raw.counts[static_cast<std::size_t>(i)];
  return CalibrationStatus::Ok;
}

double Calibration::noiseForce(double force) const {
  if (!configured_ || !(params_.noise_counts > 0.0)) return 0.0;
  double worst = 0.0;
  const int n = params_.rows * params_.cols;
  for (int i = 0; i < n; ++i) {
    const auto& k = coeffs_[static_cast<std::size_t>(i)];
    // Count that reads `force`: bisection on [0, full_scale] (monotone or not,
    // the first crossing is found well enough for a noise figure).
    double lo = 0.0, hi = params_.full_scale;
    auto poly = [&](double x) { return k[0] + x * (k[1] + x * (k[2] + x * k[3])); };
    if (poly(hi) <= force) {
      lo = hi;
    } else {
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        (poly(mid) < force ? lo : hi) = mid;
      }
    }
    const double slope = std::fabs(k[1] + lo * (2.0 * k[2] + 3.0 * lo * k[3]));
    if (slope > worst) worst = slope;
  }
  return params_.noise_counts * worst;
}

void Calibration::clearTare() { tare_.fill(0); }

}  // namespace tactile
