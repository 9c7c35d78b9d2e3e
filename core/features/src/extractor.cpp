#include "tactile_features/extractor.hpp"
#include "tactile_features/features_schema.hpp"
#include "tactile_features/edge_line.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace tactile {

namespace {
// Standard normal quantile Phi^-1(p) for p in (0, 1): Newton on
// Phi(z) = erfc(-z / sqrt 2) / 2 from z = 0, bounded to [-8, 8]. No allocation.
double probit(double p) {
  if (!(p > 0.0)) return -8.0;
  if (!(p < 1.0)) return 8.0;
  double z = 0.0;
  for (int it = 0; it < 40; ++it) {
    const double cdf = 0.5 * std::erfc(-z / std::sqrt(2.0));
    const double pdf = std::exp(-0.5 * z * z) / std::sqrt(2.0 * kPi);
    if (!(pdf > 1e-300)) break;
    double step = (cdf - p) / pdf;
    if (step > 1.0) step = 1.0;
    if (step < -1.0) step = -1.0;
    z -= step;
    if (std::fabs(step) < 1e-10) break;
  }
  return std::max(-8.0, std::min(8.0, z));
}
}  // namespace

ConfigResult FeatureExtractor::configure(const FeatureParams& p) {
  configured_ = false;
  if (const ConfigResult r = schema::checkRanges(featuresSchema(), p, "features"); !r) return r;
  if (!(p.threshold >= 0.0) || !std::isfinite(p.threshold))
    return rangeError("features.threshold", p.threshold, "must be finite and >= 0 (N)");
  if (!(p.taxel_noise >= 0.0) || !std::isfinite(p.taxel_noise))  // set from calibration.noise_counts
    return rangeError("features.taxel_noise", p.taxel_noise, "must be finite and >= 0 (N, 1 sigma)");

  params_ = p;
  est_min_ = std::max(0.0, p.contact_threshold + p.taxel_noise * probit(p.censor_min_rate));
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
  last_regions_ = 0;
  last_subthreshold_ = 0.0;
  last_alpha_sigma_ = 0.0;
  fire_rate_.fill(0.0);
  last_time_ = 0.0;
  have_time_ = false;
}


// Firing taxels (> contact_threshold) grouped into regions: two firing taxels
// are connected when their Chebyshev distance is <= region_gap + 1. Returns
// the number of regions carrying >= region_min_force. Fixed arrays, no heap.
int FeatureExtractor::countRegions(const double* f, int rows, int cols) {
  std::array<int8_t, kMaxTaxels> seen;
  std::array<int16_t, kMaxTaxels> stack;
  const int n = rows * cols;
  const double t = params_.contact_threshold;
  // A silent taxel that fired recently (the sub-threshold estimate's rate
  // at least region_min_rate) is loaded near t: it joins regions like a firing one, so
  // a line load whose taxels the noise switches off is not "multiple".
  const bool rates = params_.censor_tau > 0.0 && params_.taxel_noise > 0.0;
  auto on = [&](int j) { return f[j] > t || (rates && fire_rate_[static_cast<std::size_t>(j)] >= params_.region_min_rate); };
  for (int i = 0; i < n; ++i) seen[static_cast<std::size_t>(i)] = 0;
  const int reach = params_.region_gap + 1;
  int regions = 0;
  for (int i = 0; i < n; ++i) {
    if (seen[static_cast<std::size_t>(i)] || !on(i)) continue;
    double force = 0.0;
    int top = 0;
    stack[0] = static_cast<int16_t>(i);
    seen[static_cast<std::size_t>(i)] = 1;
    ++top;
    while (top > 0) {
      const int k = stack[static_cast<std::size_t>(--top)];
      force += f[k] > 0.0 ? f[k] : 0.0;
      const int r = k / cols, c = k % cols;
      for (int rr = std::max(0, r - reach); rr <= std::min(rows - 1, r + reach); ++rr)
        for (int cc = std::max(0, c - reach); cc <= std::min(cols - 1, c + reach); ++cc) {
          const int j = rr * cols + cc;
          if (seen[static_cast<std::size_t>(j)] || !on(j)) continue;
          seen[static_cast<std::size_t>(j)] = 1;
          stack[static_cast<std::size_t>(top++)] = static_cast<int16_t>(j);
        }
    }
    if (force >= params_.region_min_force) ++regions;
  }
  return regions;
}

// The silent taxels that fire at a rate p >= censor_min_rate (default 1/2:
// more often than not): their maximum-likelihood load under the
// censored-Gaussian model (see header), t + sigma Phi^-1(p) clamped to
// [t + sigma Phi^-1(censor_min_rate), t + 3 sigma], written into img (flagged in
// `estimated`); returns their sum. Called only while some taxel fires.
double FeatureExtractor::subthresholdForce(const double* f, int n, double t, double* img, uint8_t* estimated) {
  const double sigma = params_.taxel_noise;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const double p = fire_rate_[static_cast<std::size_t>(i)];
    if (f[i] > 0.0 || !(p >= params_.censor_min_rate)) continue;
    double est = t + sigma * probit(p);
    est = est < est_min_ ? est_min_ : (est > t + 3.0 * sigma ? t + 3.0 * sigma : est);
    img[i] = est;
    estimated[i] = 1;
    sum += est;
  }
  return sum;
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

namespace {
// A failed frame: every numeric field zero, the frame's time (0 if not finite)
// and seq kept, status s; returns s.
FeatureStatus failFrame(const TactileFrame& frame, FeatureStatus s, ContactFeatures& out) {
  const double t = frame.time_s;
  const uint32_t q = frame.seq;
  out = ContactFeatures{};
  out.time_s = std::isfinite(t) ? t : 0.0;
  out.seq = q;
  out.status = s;
  return s;
}

// Validation pass over n readings: InvalidInput on NaN/Inf, OutOfRange beyond
// max_force (huge but finite), else Ok; fmax = the largest reading above
// kForceFloor (0 if none).
FeatureStatus validateReadings(const double* f, int n, double max_force, double& fmax) {
  bool finite = true;
  double absmax = 0.0;
  fmax = 0.0;
  for (int i = 0; i < n; ++i) {
    finite = finite && std::isfinite(f[i]);
    const double mag = std::fabs(f[i]);
    absmax = mag > absmax ? mag : absmax;
    fmax = f[i] > fmax && f[i] > FeatureExtractor::kForceFloor ? f[i] : fmax;
  }
  if (!finite) return FeatureStatus::InvalidInput;  // NaN/Inf input
  if (absmax > max_force) return FeatureStatus::OutOfRange;  // huge but finite
  return FeatureStatus::Ok;
}

// The frame's status once its features are valid: NoContact, Saturated or Ok.
FeatureStatus frameStatus(ContactType type, const TactileFrame& frame) {
  if (type == ContactType::None) return FeatureStatus::NoContact;
  if (frame.saturated_count > 0) return FeatureStatus::Saturated;
  return FeatureStatus::Ok;
}
}  // namespace

// Raw moments up to second order (Eq. B.1) and the binarised image's sums.
struct FeatureExtractor::RawMoments {
  double m00 = 0, m10 = 0, m01 = 0, m20 = 0, m11 = 0, m02 = 0;
  double bx = 0, by = 0;  ///< sums of the in-contact taxels' x and y (CoC)
  int area = 0;           ///< taxels in contact
  int loaded = 0;         ///< taxels carrying force (the moments' support)
};

// Firing rates of the sub-threshold estimate (time constant censor_tau in
// frame time). The first frame after reset, and a frame whose time stamp
// does not advance (no time base: nothing to average over), restart the
// average at the current firing state: no estimate rests on them.
void FeatureExtractor::updateFiringRates(const TactileFrame& frame, int n) {
  const double* f = frame.force.data();
  double a = 1.0;
  if (have_time_) {
    const double dt = frame.time_s - last_time_;
    a = (dt > 0.0 && std::isfinite(dt)) ? 1.0 - std::exp(-dt / params_.censor_tau) : 1.0;
  }
  if (std::isfinite(frame.time_s) && (!have_time_ || frame.time_s > last_time_)) {
    last_time_ = frame.time_s;
    have_time_ = true;
  }
  for (int i = 0; i < n; ++i) {
    double& pr = fire_rate_[static_cast<std::size_t>(i)];
    pr += a * ((f[i] > kForceFloor ? 1.0 : 0.0) - pr);
  }
}

// The image the moments are taken of: the readings (negative values and
// values below kForceFloor, denormals included, are 0) plus, while a taxel
// fires, the censored-model load of the silent taxels that fire at a rate
// >= censor_min_rate (header: "Taxels the noise switches off"), flagged in
// `estimated`. Sets last_subthreshold_.
void FeatureExtractor::buildImage(const double* f, int n, bool add_estimate, double* img, uint8_t* estimated) {
  for (int i = 0; i < n; ++i) {
    img[i] = f[i] > kForceFloor ? f[i] : 0.0;
    estimated[i] = 0;
  }
  last_subthreshold_ = 0.0;
  if (add_estimate) last_subthreshold_ = subthresholdForce(f, n, params_.contact_threshold, img, estimated);
}

// One pass: raw moments up to second order of image g (Eq. B.1) and the
// image binarised at thr (CoC; an estimated taxel is in contact). Row sums
// keep the multiplications per taxel low.
void FeatureExtractor::accumulateMoments(const double* g, const uint8_t* estimated, double thr, RawMoments& m) const {
  const int rows = params_.rows, cols = params_.cols;
  for (int r = 0; r < rows; ++r) {
    const double y = ys_[static_cast<std::size_t>(r)];
    const double* row = g + r * cols;
    const uint8_t* est = estimated + r * cols;
    double s0 = 0, s1 = 0, s2 = 0, sb = 0;
    int cnt = 0;
    for (int c = 0; c < cols; ++c) {
      const double x = xs_[static_cast<std::size_t>(c)];
      const double v = row[c];
      s0 += v;
      s1 += x * v;
      s2 += x * x * v;
      const bool on = v > thr || est[c] != 0;
      cnt += on;
      m.loaded += v > 0.0;
      sb += on ? x : 0.0;
    }
    m.m00 += s0;
    m.m10 += s1;
    m.m01 += y * s0;
    m.m20 += s2;
    m.m11 += y * s1;
    m.m02 += y * y * s0;
    m.bx += sb;
    m.by += y * cnt;
    m.area += cnt;
  }
}

// CoP, CoC, DZMP and the covariance's eigenvalues of a loaded frame
// (m.m00 > kForceFloor) into out, the central moments into mo.
void FeatureExtractor::contactGeometry(const RawMoments& m, ContactFeatures& out, Moments& mo) {
  const double cx = m.m10 / m.m00, cy = m.m01 / m.m00;  // Eq. B.2, B.3
  // Second central moments normalised by M00 (pressure-weighted covariance).
  // Positions are O(1e-2 m), so the cancellation in m20/m00 - cx^2 costs
  // ~1e-16 * 1e-4 m^2: far below any eigenvalue that matters.
  mo.mu20 = std::max(0.0, m.m20 / m.m00 - cx * cx);
  mo.mu11 = m.m11 / m.m00 - cx * cy;
  mo.mu02 = std::max(0.0, m.m02 / m.m00 - cy * cy);
  out.cop_x = cx;
  out.cop_y = cy;
  if (m.area > 0) {
    out.coc_x = m.bx / m.area;
    out.coc_y = m.by / m.area;
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
}

// 1-sigma noise of alpha_z (header: "alpha_z within the noise") for image g
// with mass m00 and centroid (cx, cy), central moments mo: +inf when the
// covariance is isotropic (lambda1 = lambda2), 0 without taxel noise.
double FeatureExtractor::alphaSigma(const double* g, double m00, double cx, double cy, const Moments& mo) const {
  const int rows = params_.rows, cols = params_.cols;
  const double a = mo.mu20, b = mo.mu11, c = mo.mu02;
  const double gx = a - c, gy = 2.0 * b;
  const double gn = std::sqrt(gx * gx + gy * gy);  // = lambda1 - lambda2
  if (!(gn > 0.0)) return std::numeric_limits<double>::infinity();
  double s = 0.0;
  if (params_.taxel_noise > 0.0) {
    const double nx = -gy / gn, ny = gx / gn;
    for (int r = 0; r < rows; ++r) {
      const double dy = ys_[static_cast<std::size_t>(r)] - cy;
      for (int cc = 0; cc < cols; ++cc) {
        if (!(g[r * cols + cc] > 0.0)) continue;
        const double dx = xs_[static_cast<std::size_t>(cc)] - cx;
        const double un = (dx * dx - dy * dy) * nx + 2.0 * dx * dy * ny;
        s += un * un;
      }
    }
  }
  return params_.taxel_noise * std::sqrt(s) / (2.0 * m00 * gn);
}

// The principal-axis angle of a loaded frame into alpha (the previous angle
// when it is not defined); true when defined: two or more loaded taxels, an
// anisotropic covariance and last_alpha_sigma_ <= alpha_max_sigma.
bool FeatureExtractor::principalAngle(const RawMoments& m, const ContactFeatures& out, const Moments& mo,
                                      double& alpha) const {
  alpha = alpha_prev_;
  const double l1 = out.lambda1, l2 = out.lambda2;
  // One loaded taxel has no direction: its covariance is zero up to
  // rounding (lambda1 ~ 1e-20 m^2) and the noise model, which scales with the
  // spread, cannot see that; the angle would be rounding noise.
  if (!(m.loaded >= 2 && l1 > 0.0 && (l1 - l2) > params_.isotropy_tol * (l1 + l2) &&
        last_alpha_sigma_ <= params_.alpha_max_sigma))
    return false;
  // Principal axis angle from x_s; 0.5*atan2 lies in (-pi/2, pi/2].
  const double wrapped = 0.5 * std::atan2(2.0 * mo.mu11, mo.mu20 - mo.mu02);
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
  return true;
}

// Contact detection and type (Sec. 3.3, Eq. 5) with hysteresis from the
// previous frame's type: None unless loaded and firing. Sets last_regions_.
ContactType FeatureExtractor::classifyContact(const double* f, bool loaded_and_firing, const ContactFeatures& out) {
  last_regions_ = 0;
  if (!loaded_and_firing) return ContactType::None;
  last_regions_ = countRegions(f, params_.rows, params_.cols);
  const double l1 = out.lambda1, l2 = out.lambda2;
  const double ratio = type_prev_ == ContactType::Edge ? params_.edge_ratio_exit : params_.edge_ratio;
  const bool long_enough = 12.0 * l1 >= params_.edge_min_length * params_.edge_min_length;
  if (last_regions_ >= 2) return ContactType::Multiple;
  return (l1 > 0.0 && l1 >= ratio * l2 && long_enough) ? ContactType::Edge : ContactType::Point;
}

FeatureStatus FeatureExtractor::step(const TactileFrame& frame, ContactFeatures& out) {
  if (!configured_) return failFrame(frame, FeatureStatus::NotConfigured, out);
  if (frame.rows != params_.rows || frame.cols != params_.cols)
    return failFrame(frame, FeatureStatus::BadDimensions, out);

  const int n = params_.rows * params_.cols;
  const double* f = frame.force.data();

  double fmax = 0.0;
  const FeatureStatus valid = validateReadings(f, n, params_.max_taxel_force, fmax);
  if (valid != FeatureStatus::Ok) return failFrame(frame, valid, out);
  const bool firing = fmax > params_.contact_threshold;

  const bool censor = params_.censor_tau > 0.0 && params_.taxel_noise > 0.0;
  if (censor) updateFiringRates(frame, n);

  std::array<double, kMaxTaxels> img;
  std::array<uint8_t, kMaxTaxels> estimated;
  buildImage(f, n, censor && firing, img.data(), estimated.data());
  const double* g = img.data();

  // Binarisation threshold (fixed or Otsu).
  double thr = params_.threshold;
  if (params_.threshold_mode == ThresholdMode::Otsu) thr = otsuThreshold(g, n);

  RawMoments m;
  accumulateMoments(g, estimated.data(), thr, m);
  last_threshold_ = thr;
  if (!std::isfinite(m.m00) || !std::isfinite(m.m20 + m.m02 + m.m11))
    return failFrame(frame, FeatureStatus::OutOfRange, out);  // overflow of finite inputs (max_taxel_force too large)
  const bool has_mass = m.m00 > kForceFloor;

  out = ContactFeatures{};
  out.time_s = frame.time_s;
  out.seq = frame.seq;
  out.force = m.m00;                // f = sum of taxel forces (with the sub-threshold estimate)
  out.d_z = params_.c_z * m.m00;    // Eq. 2: dz = C_z * f_z
  out.max_taxel = fmax;
  out.area = static_cast<uint16_t>(m.area);

  Moments mo;
  mo.m00 = m.m00;
  mo.m10 = m.m10;
  mo.m01 = m.m01;
  bool alpha_ok = false;
  double alpha_new = alpha_prev_;
  last_alpha_sigma_ = std::numeric_limits<double>::infinity();
  if (has_mass) {
    contactGeometry(m, out, mo);
    last_alpha_sigma_ = alphaSigma(g, m.m00, out.cop_x, out.cop_y, mo);
    alpha_ok = principalAngle(m, out, mo, alpha_new);
  }
  moments_ = mo;

  const ContactType type = classifyContact(f, has_mass && firing, out);
  out.contact = type;
  type_prev_ = type;
  // alpha_z: a new value only when defined above the noise and the contact
  // is one region; otherwise the last defined value, flagged undefined.
  out.alpha_defined = alpha_ok && (type == ContactType::Point || type == ContactType::Edge);
  out.alpha_z = out.alpha_defined ? alpha_new : alpha_prev_;
  if (out.alpha_defined) alpha_prev_ = out.alpha_z;

  if (type == ContactType::Edge) {
    // The edge line's curvature: columns with 2-3 firing rows, at least 5 of
    // them spanning 4 pitches or more (edge_line.hpp).
    EdgeLinePoints pts;
    const EdgeLineParams lp{params_.contact_threshold, 3};
    const int np = edgeLinePoints(frame, params_.geometry(), lp, pts);
    edgeLineCurvature(pts, np, 5, 3.5 * params_.pitch, out.curvature);
  }

  out.status = frameStatus(type, frame);
  return out.status;
}

}  // namespace tactile
