#include "tactile_features/extractor.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace tactile {

ConfigResult FeatureExtractor::configure(const FeatureParams& p) {
  configured_ = false;
  if (p.rows < 1 || p.rows > kMaxRows)
    return rangeError("features.rows", p.rows, "must be in [1, " + std::to_string(kMaxRows) + "]");
  if (p.cols < 1 || p.cols > kMaxCols)
    return rangeError("features.cols", p.cols, "must be in [1, " + std::to_string(kMaxCols) + "]");
  if (!(p.pitch > 0.0) || !std::isfinite(p.pitch))
    return rangeError("features.pitch", p.pitch, "must be finite and > 0 (m)");
  if (!(p.c_z >= 0.0) || !std::isfinite(p.c_z))
    return rangeError("features.c_z", p.c_z, "must be finite and >= 0 (m/N)");
  if (!(p.threshold >= 0.0) || !std::isfinite(p.threshold))
    return rangeError("features.threshold", p.threshold, "must be finite and >= 0 (N)");
  if (!(p.contact_threshold >= 0.0) || !std::isfinite(p.contact_threshold))
    return rangeError("features.contact_threshold", p.contact_threshold, "must be finite and >= 0 (N)");
  if (!(p.edge_ratio >= 1.0) || !std::isfinite(p.edge_ratio))
    return rangeError("features.edge_ratio", p.edge_ratio, "must be finite and >= 1 (lambda1/lambda2)");
  if (!(p.edge_ratio_exit >= 1.0) || !(p.edge_ratio_exit <= p.edge_ratio))
    return rangeError("features.edge_ratio_exit", p.edge_ratio_exit,
                      "must be in [1, edge_ratio = " + std::to_string(p.edge_ratio) + "]");
  if (!(p.edge_min_length >= 0.0) || !std::isfinite(p.edge_min_length))
    return rangeError("features.edge_min_length", p.edge_min_length, "must be finite and >= 0 (m)");
  if (!(p.alpha_hysteresis >= 0.0) || !(p.alpha_hysteresis <= kPi / 4))
    return rangeError("features.alpha_hysteresis", p.alpha_hysteresis, "must be in [0, pi/4] (rad)");
  if (!(p.isotropy_tol >= 0.0) || !(p.isotropy_tol < 1.0))
    return rangeError("features.isotropy_tol", p.isotropy_tol, "must be in [0, 1)");

  params_ = p;
  const SensorGeometry g = p.geometry();
  for (int c = 0; c < p.cols; ++c) xs_[static_cast<std::size_t>(c)] = g.x(c);
  for (int r = 0; r < p.rows; ++r) ys_[static_cast<std::size_t>(r)] = g.y(r);
  reset();
  configured_ = true;
  return ConfigResult::success();
}

void FeatureExtractor::reset() {
  alpha_prev_ = 0.0;
  type_prev_ = ContactType::None;
  moments_ = Moments{};
  last_threshold_ = params_.threshold;
}

double FeatureExtractor::otsuThreshold(const double* values, int n) {
  if (n <= 0) return 0.0;
  if (n > kMaxTaxels) n = kMaxTaxels;
  std::array<double, kMaxTaxels> v;
  std::copy(values, values + n, v.begin());
  std::sort(v.begin(), v.begin() + n);
  double total = 0.0;
  for (int i = 0; i < n; ++i) total += v[static_cast<std::size_t>(i)];
  // Score every split {v <= v[k]} | {v > v[k]} between distinct values with the
  // between-class variance w0*w1*(mu0-mu1)^2; the first maximum wins (like
  // OpenCV, which keeps the lowest level on ties).
  double best = -1.0;
  double thr = v[0];
  double sum0 = 0.0;
  for (int k = 0; k < n - 1; ++k) {
    sum0 += v[static_cast<std::size_t>(k)];
    if (!(v[static_cast<std::size_t>(k)] < v[static_cast<std::size_t>(k + 1)])) continue;
    const double n0 = k + 1, n1 = n - n0;
    const double mu0 = sum0 / n0, mu1 = (total - sum0) / n1;
    const double w0 = n0 / n, w1 = n1 / n;
    const double s = w0 * w1 * (mu0 - mu1) * (mu0 - mu1);
    if (s > best) {
      best = s;
      thr = v[static_cast<std::size_t>(k)];
    }
  }
  return thr;
}

FeatureStatus FeatureExtractor::step(const TactileFrame& frame, ContactFeatures& out) {
  auto fail = [&](FeatureStatus s) {
    const double t = frame.time_s;
    const uint32_t q = frame.seq;
    out = ContactFeatures{};
    out.time_s = std::isfinite(t) ? t : 0.0;
    out.seq = q;
    out.status = s;
    return s;
  };
  if (!configured_) return fail(FeatureStatus::NotConfigured);
  if (frame.rows != params_.rows || frame.cols != params_.cols) return fail(FeatureStatus::BadDimensions);

  const int rows = params_.rows, cols = params_.cols;
  const int n = rows * cols;
  const double* f = frame.force.data();

  // Binarisation threshold (fixed or Otsu).
  double thr = params_.threshold;
  if (params_.threshold_mode == ThresholdMode::Otsu) {
    std::array<double, kMaxTaxels> clamped;
    for (int i = 0; i < n; ++i) clamped[static_cast<std::size_t>(i)] = f[i] > 0.0 ? f[i] : 0.0;
    thr = otsuThreshold(clamped.data(), n);
  }

  // One pass: raw moments up to second order (Eq. B.1), max taxel and the
  // binarised image (CoC). Row sums keep the multiplications per taxel low.
  // `raw` sums the unclamped inputs so that any NaN/Inf is caught at the end
  // (the clamp below would otherwise turn NaN into 0).
  double raw = 0.0;
  double m00 = 0, m10 = 0, m01 = 0, m20 = 0, m11 = 0, m02 = 0, fmax = 0;
  double bx = 0, by = 0;
  int area = 0;
  for (int r = 0; r < rows; ++r) {
    const double y = ys_[static_cast<std::size_t>(r)];
    const double* row = f + r * cols;
    double s0 = 0, s1 = 0, s2 = 0, sb = 0;
    int cnt = 0;
    for (int c = 0; c < cols; ++c) {
      const double x = xs_[static_cast<std::size_t>(c)];
      raw += row[c];
      const double v = row[c] > 0.0 ? row[c] : 0.0;
      s0 += v;
      s1 += x * v;
      s2 += x * x * v;
      fmax = v > fmax ? v : fmax;
      const bool on = v > thr;
      cnt += on;
      sb += on ? x : 0.0;
    }
    m00 += s0;
    m10 += s1;
    m01 += y * s0;
    m20 += s2;
    m11 += y * s1;
    m02 += y * y * s0;
    bx += sb;
    by += y * cnt;
    area += cnt;
  }
  last_threshold_ = thr;
  if (!std::isfinite(raw) || !std::isfinite(m00) || !std::isfinite(m20 + m02 + m11))
    return fail(FeatureStatus::InvalidInput);  // NaN/Inf input, or overflow of finite inputs

  out = ContactFeatures{};
  out.time_s = frame.time_s;
  out.seq = frame.seq;
  out.force = m00;                  // f = sum of taxel forces
  out.d_z = params_.c_z * m00;      // Eq. 2: dz = C_z * f_z
  out.max_taxel = fmax;
  out.area = static_cast<uint16_t>(area);

  Moments mo;
  mo.m00 = m00;
  mo.m10 = m10;
  mo.m01 = m01;
  if (m00 > 0.0) {
    const double cx = m10 / m00, cy = m01 / m00;  // Eq. B.2, B.3
    // Second central moments normalised by M00 (pressure-weighted covariance).
    // Positions are O(1e-2 m), so the cancellation in m20/m00 - cx^2 costs
    // ~1e-16 * 1e-4 m^2: far below any eigenvalue that matters.
    mo.mu20 = std::max(0.0, m20 / m00 - cx * cx);
    mo.mu11 = m11 / m00 - cx * cy;
    mo.mu02 = std::max(0.0, m02 / m00 - cy * cy);
    out.cop_x = cx;
    out.cop_y = cy;
    if (area > 0) {
      out.coc_x = bx / area;
      out.coc_y = by / area;
    } else {
      out.coc_x = cx;
      out.coc_y = cy;
    }
    // Eq. 3: DZMP_x = CoP_y - CoC_y, DZMP_y = CoP_x - CoC_x.
    out.dzmp_x = out.cop_y - out.coc_y;
    out.dzmp_y = out.cop_x - out.coc_x;

    // PCA of the 2x2 covariance (Eq. B.4, B.5), closed form.
    const double a = mo.mu20, b = mo.mu11, c = mo.mu02;
    const double mean = 0.5 * (a + c);
    const double half = 0.5 * (a - c);
    const double rad = std::sqrt(half * half + b * b);
    double l1 = mean + rad;
    double l2 = mean - rad;
    if (l2 < 0.0) l2 = 0.0;  // rounding on a rank-1 covariance
    out.lambda1 = l1;
    out.lambda2 = l2;

    double alpha = alpha_prev_;
    if (l1 > 0.0 && (l1 - l2) > params_.isotropy_tol * (l1 + l2)) {
      // Principal axis angle from x_s; 0.5*atan2 lies in (-pi/2, pi/2].
      const double wrapped = 0.5 * std::atan2(2.0 * b, a - c);
      alpha = wrapped;
      // Branch hysteresis near +-pi/2 (see header): keep the representative
      // closest to the previous angle while it stays inside the band.
      const double h = params_.alpha_hysteresis;
      if (h > 0.0) {
        double best = wrapped;
        for (double cand : {wrapped - kPi, wrapped + kPi})
          if (std::fabs(cand - alpha_prev_) < std::fabs(best - alpha_prev_)) best = cand;
        if (std::fabs(best) <= 0.5 * kPi + h) alpha = best;
      }
    }
    out.alpha_z = alpha;
  }
  moments_ = mo;

  // Contact detection and type (Sec. 3.3, Eq. 5) with hysteresis.
  ContactType type = ContactType::None;
  if (m00 > 0.0 && fmax > params_.contact_threshold) {
    const double l1 = out.lambda1, l2 = out.lambda2;
    const double ratio = type_prev_ == ContactType::Edge ? params_.edge_ratio_exit : params_.edge_ratio;
    const bool long_enough = 12.0 * l1 >= params_.edge_min_length * params_.edge_min_length;
    type = (l1 > 0.0 && l1 >= ratio * l2 && long_enough) ? ContactType::Edge : ContactType::Point;
  }
  out.contact = type;
  type_prev_ = type;
  if (type != ContactType::None) alpha_prev_ = out.alpha_z;

  if (type == ContactType::None)
    out.status = FeatureStatus::NoContact;
  else if (frame.saturated_count > 0)
    out.status = FeatureStatus::Saturated;
  else
    out.status = FeatureStatus::Ok;
  return out.status;
}

}  // namespace tactile
