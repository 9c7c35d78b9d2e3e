#include "tactile_sim_lwr/pad_sensor.hpp"
#include "tactile_sim_lwr/sim_schema.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>

#include "tactile_sim_lwr/lwr_arm.hpp"  // toFrame, validPose

namespace tactile {
namespace sim {

ConfigResult PadSensor::configure(const PadParams& p) {
  auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!validPose(p.mount)) return ConfigResult::failure("pad.mount: position must be finite and the quaternion a unit quaternion (|q| within 1e-3 of 1)");
  if (p.rows < 1 || p.rows > kMaxRows) return rangeError("pad.rows", p.rows, "must be in [1, " + std::to_string(kMaxRows) + "]");
  if (p.cols < 1 || p.cols > kMaxCols) return rangeError("pad.cols", p.cols, "must be in [1, " + std::to_string(kMaxCols) + "]");
  if (!positive(p.pitch) || p.pitch > 0.05) return rangeError("pad.pitch", p.pitch, "must be in (0, 0.05] m");
  const ConfigResult declared = schema::checkRanges(sensorSchema(), p, "sensor");
  if (!declared) return declared;
  const double ax = p.cols * p.pitch, ay = p.rows * p.pitch;
  if (!(p.housing_size_x >= ax) || !std::isfinite(p.housing_size_x) || p.housing_size_x > 1.0)
    return rangeError("sensor.housing_size_x", p.housing_size_x,
                      "must be in [cols * pitch = " + std::to_string(ax) + ", 1] m");
  if (!(p.housing_size_y >= ay) || !std::isfinite(p.housing_size_y) || p.housing_size_y > 1.0)
    return rangeError("sensor.housing_size_y", p.housing_size_y,
                      "must be in [rows * pitch = " + std::to_string(ay) + ", 1] m");
  if (!positive(p.housing_spacing) || p.housing_spacing > 0.05)
    return rangeError("pad.housing_spacing", p.housing_spacing, "must be in (0, 0.05] m");
  if (!(p.depth_limit > p.housing_recess) || p.depth_limit > 1.0)
    return rangeError("pad.depth_limit", p.depth_limit, "must be in (housing_recess, 1] m");
  if (p.full_scale < 16 || p.full_scale > 4095) return rangeError("pad.full_scale", p.full_scale, "must be in [16, 4095] counts");
  if (!positive(p.response[0])) return rangeError("pad.response[0]", p.response[0], "must be > 0 (N/count)");
  if (!(p.response[1] >= 0.0) || !std::isfinite(p.response[1])) return rangeError("pad.response[1]", p.response[1], "must be >= 0 (N/count^2)");
  if (!(p.response[2] >= 0.0) || !std::isfinite(p.response[2])) return rangeError("pad.response[2]", p.response[2], "must be >= 0 (N/count^3)");
  if (!positive(p.border_sensitivity) || p.border_sensitivity > 1.0)
    return rangeError("pad.border_sensitivity", p.border_sensitivity, "must be in (0, 1]");

  // Layer samples (physics sampling), then the housing ring.
  int n = 0;
  const int k = p.physics_subsamples;
  const double h = p.pitch / k;
  for (int r = 0; r < p.rows; ++r)
    for (int c = 0; c < p.cols; ++c)
      for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j) {
          const double x = (c - (p.cols - 1) / 2.0) * p.pitch - 0.5 * p.pitch + (j + 0.5) * h;
          const double y = (r - (p.rows - 1) / 2.0) * p.pitch - 0.5 * p.pitch + (i + 0.5) * h;
          samples_[static_cast<std::size_t>(n++)] = Sample{x, y, 0.0, p.modulus * h * h, true};
        }
  const int nx = std::max(1, static_cast<int>(std::ceil(p.housing_size_x / p.housing_spacing - 1e-9)));
  const int ny = std::max(1, static_cast<int>(std::ceil(p.housing_size_y / p.housing_spacing - 1e-9)));
  const double hx = p.housing_size_x / nx, hy = p.housing_size_y / ny;
  int nh = 0;
  for (int i = 0; i < ny; ++i)
    for (int j = 0; j < nx; ++j) {
      const double x = -0.5 * p.housing_size_x + (j + 0.5) * hx;
      const double y = -0.5 * p.housing_size_y + (i + 0.5) * hy;
      if (std::fabs(x) < 0.5 * ax && std::fabs(y) < 0.5 * ay) continue;
      if (n >= kMaxSamples)
        return rangeError("pad.housing_spacing", p.housing_spacing, "too fine: more than " + std::to_string(kMaxSamples) + " samples");
      samples_[static_cast<std::size_t>(n++)] = Sample{x, y, -p.housing_recess, p.housing_modulus * hx * hy, false};
      ++nh;
    }
  params_ = p;
  {
    const int kk = std::max(p.subsamples, p.physics_subsamples);
    xrow_.assign(static_cast<std::size_t>(p.cols * kk), 0.0);
    zrow_.assign(static_cast<std::size_t>(p.cols * kk * kk), 0.0);
    wrow_.assign(static_cast<std::size_t>(p.cols * kk * kk), -1);
    sxrow_.assign(static_cast<std::size_t>(p.cols * kk), 0.0);
    syrow_.assign(static_cast<std::size_t>(p.cols * kk), 0.0);
  }
  n_samples_ = n;
  n_housing_ = nh;
  T_es_ = toFrame(p.mount);
  image_ = TactileFrame();
  image_.rows = static_cast<uint16_t>(p.rows);
  image_.cols = static_cast<uint16_t>(p.cols);
  // The taxel response: the inverse of the calibration (calibration()).
  TaxelResponseParams rp;
  rp.calibration = calibration();
  rp.noise_counts = p.noise_counts;
  rp.threshold = p.threshold;
  rp.seed = p.seed;
  ConfigResult rr = response_.configure(rp);
  if (!rr) return ConfigResult::failure("pad: " + rr.message());
  return ConfigResult::success();
}

double PadSensor::forceFor(int r, int c, double n) const { return response_.forceFor(r * params_.cols + c, n); }

double PadSensor::countsFor(int r, int c, double force) const { return response_.countsFor(r * params_.cols + c, force); }

tactile::CalibrationParams PadSensor::calibration() const { return calibrationOf(params_); }

tactile::CalibrationParams PadSensor::calibrationOf(const PadParams& p) {
  tactile::CalibrationParams c;
  if (p.use_calibration) c = p.calibration;
  c.rows = p.rows;
  c.cols = p.cols;
  if (p.use_calibration) return c;
  c.full_scale = p.full_scale;
  c.coeffs = {0.0, p.response[0], p.response[1], p.response[2]};
  c.use_border = true;
  const double s = p.border_sensitivity;
  c.border_coeffs = {0.0, p.response[0] / s, p.response[1] / s, p.response[2] / s};
  return c;
}

void PadSensor::rowDepths(const ObjectSet& objects, double y, const double* xs, int n, double* z, int* which, double* sx,
                          double* sy) const {
  // xs ascending: evaluate only [i0, i1), where rowSpan() allows z < 0.
  int i0 = n, i1 = n;
  double x0, x1;
  if (objects.rowSpan(y, x0, x1)) {
    i0 = 0;
    while (i0 < n && xs[i0] < x0) ++i0;
    i1 = i0;
    while (i1 < n && !(xs[i1] > x1)) ++i1;
  }
  const double inf = std::numeric_limits<double>::infinity();
  for (int i = 0; i < i0; ++i) z[i] = inf;
  for (int i = i1; i < n; ++i) z[i] = inf;
  if (sx != nullptr && sy != nullptr) {
    for (int i = 0; i < i0; ++i) sx[i] = sy[i] = 0.0;
    for (int i = i1; i < n; ++i) sx[i] = sy[i] = 0.0;
  }
  if (i1 > i0)
    objects.lowestZRow(y, xs + i0, i1 - i0, z + i0, which + i0, sx != nullptr ? sx + i0 : nullptr,
                       sy != nullptr ? sy + i0 : nullptr);
}

// The (z, wx, wy) rows of the contact wrench and stiffness (g = (0, 0, -1,
// -y, x, 0)) and the sliding columns, summed over the samples in contact.
struct PadSensor::ContactSums {
  double Fz = 0, Mx = 0, My = 0, Kzz = 0, Kzx = 0, Kzy = 0, Kxx = 0, Kxy = 0, Kyy = 0;
  double Kzsx = 0, Kxsx = 0, Kysx = 0, Kzsy = 0, Kxsy = 0, Kysy = 0, Kzwz = 0, Kxwz = 0, Kywz = 0;
};

// One layer sample row's masked sums over its active samples.
struct PadSensor::RowSums {
  // Masked moments over the row's samples: n, sum x, sum x^2, sum d, sum x d.
  struct Moments {
    double n = 0, x1 = 0, x2 = 0, d0 = 0, d1 = 0;
    void add(bool on, double d, double x) {
      const double w = on ? 1.0 : 0.0, dd = on ? d : 0.0;
      n += w;
      x1 += w * x;
      x2 += w * x * x;
      d0 += dd;
      d1 += dd * x;
    }
  };
  Moments all, trayed;
  double A1 = 0, A2 = 0, B1 = 0, B2 = 0, C2 = 0;  // slopes: sum sx, x sx, sy, x sy, x^2 sy
};

namespace {
// Every field of a contact evaluation zero (no contact).
void clearEval(ContactEval& out) {
  out.W_s.setZero();
  out.K_s.setZero();
  out.dW_dth.setZero();
  out.tau_tray.setZero();
  out.dtau_dth.setZero();
  out.dtau_ds.setZero();
  out.layer_force = out.housing_force = 0.0;
  out.active = 0;
}

// h_j(r) = -z_s . (a_j x r): penetration gained per unit tray angle (a_1 = x_g, a_2 = y_g).
double trayH1(const KDL::Vector& zs, const KDL::Vector& r) { return -KDL::dot(zs, KDL::Vector(1, 0, 0) * r); }
double trayH2(const KDL::Vector& zs, const KDL::Vector& r) { return -KDL::dot(zs, KDL::Vector(0, 1, 0) * r); }
}  // namespace

void PadSensor::addPointSample(const Sample& s, double zl, int which, int tray, const KDL::Frame& T_gs,
                               const KDL::Vector& B, ContactSums& c, ContactEval& out) const {
  const double d = s.z - zl;  // penetration into the layer (z = 0) or the housing (z = -recess)
  if (!(d > 0.0) || -zl > params_.depth_limit) return;
  const double f = s.k * d;
  ++out.active;
  if (s.layer) out.layer_force += f; else out.housing_force += f;
  const double gz = -1.0, gx = -s.y, gy = s.x;
  c.Fz += gz * f;
  c.Mx += gx * f;
  c.My += gy * f;
  c.Kzz += s.k;
  c.Kzx += s.k * gz * gx;
  c.Kzy += s.k * gz * gy;
  c.Kxx += s.k * gx * gx;
  c.Kxy += s.k * gx * gy;
  c.Kyy += s.k * gy * gy;
  if (which == tray && tray >= 0) {
    const KDL::Vector zs = T_gs.M.UnitZ();
    const KDL::Vector pg = T_gs * KDL::Vector(s.x, s.y, s.z);
    const KDL::Vector r = pg - B;
    // h_j = -z_s . (a_j x r): penetration gained per unit tray angle (a_1 = x_g, a_2 = y_g).
    const double h1 = -KDL::dot(zs, KDL::Vector(1, 0, 0) * r);
    const double h2 = -KDL::dot(zs, KDL::Vector(0, 1, 0) * r);
    const double g[6] = {0.0, 0.0, gz, gx, gy, 0.0};
    for (int a = 2; a < 5; ++a) {
      out.dW_dth(a, 0) += s.k * g[a] * h1;
      out.dW_dth(a, 1) += s.k * g[a] * h2;
      out.dtau_ds(0, a) += s.k * h1 * g[a];
      out.dtau_ds(1, a) += s.k * h2 * g[a];
    }
    out.tau_tray(0) -= h1 * f;
    out.tau_tray(1) -= h2 * f;
    out.dtau_dth(0, 0) -= s.k * h1 * h1;
    out.dtau_dth(0, 1) -= s.k * h1 * h2;
    out.dtau_dth(1, 0) -= s.k * h2 * h1;
    out.dtau_dth(1, 1) -= s.k * h2 * h2;
  }
}

void PadSensor::rowSums(const ObjectSet& objects, double y, int tray, RowSums& rs) const {
  const int nx = params_.cols * params_.physics_subsamples;
  const double lim = params_.depth_limit;
  const double* xs = xrow_.data();
  double* zb = zrow_.data();
  int* wb = wrow_.data();
  double* sxb = sxrow_.data();
  double* syb = syrow_.data();
  rowDepths(objects, y, xs, nx, zb, wb, sxb, syb);
  RowSums::Moments& all = rs.all;
  RowSums::Moments& trayed = rs.trayed;
  // One loop body, instantiated with and without the tray sums.
  auto sums = [&](auto with_tray) {
    for (int m = 0; m < nx; ++m) {
      const double d = -zb[m], x = xs[m];
      const bool on = (d > 0.0) & (d <= lim);  // bitwise: no control flow
      all.add(on, d, x);
      const double ax = on ? sxb[m] : 0.0, ay = on ? syb[m] : 0.0;  // select: unused slopes may be NaN
      rs.A1 += ax;
      rs.A2 += x * ax;
      rs.B1 += ay;
      rs.B2 += x * ay;
      rs.C2 += x * x * ay;
      if constexpr (decltype(with_tray)::value) trayed.add(on & (wb[m] == tray), d, x);
    }
  };
  if (tray < 0)
    sums(std::false_type{});
  else
    sums(std::true_type{});
}

void PadSensor::addRowSums(double ks, double y, const RowSums& rs, ContactSums& c) {
  const RowSums::Moments& all = rs.all;
  c.Fz -= ks * all.d0;
  c.Mx -= y * ks * all.d0;
  c.My += ks * all.d1;
  c.Kzz += ks * all.n;
  c.Kzx += ks * y * all.n;
  c.Kzy -= ks * all.x1;
  c.Kxx += ks * y * y * all.n;
  c.Kxy -= ks * y * all.x1;
  c.Kyy += ks * all.x2;
  // Sliding columns (x, y, wz of the sensor twist): the penetration field
  // moves under the sensor, dd/dx = -dz/dx = -s_x, dd/dy = -s_y,
  // dd/dwz = y s_x - x s_y, and K(a, b) = -sum ks g_a dd/db.
  c.Kzsx -= ks * rs.A1;
  c.Kxsx -= ks * y * rs.A1;
  c.Kysx += ks * rs.A2;
  c.Kzsy -= ks * rs.B1;
  c.Kxsy -= ks * y * rs.B1;
  c.Kysy += ks * rs.B2;
  c.Kzwz -= ks * (rs.B2 - y * rs.A1);
  c.Kxwz -= ks * y * (rs.B2 - y * rs.A1);
  c.Kywz += ks * (rs.C2 - y * rs.A2);
}

void PadSensor::addTrayRow(double ks, double y, const KDL::Frame& T_gs, const KDL::Vector& B, const RowSums& rs,
                           ContactEval& out) {
  const KDL::Vector zs = T_gs.M.UnitZ();
  const KDL::Vector Xs = T_gs.M.UnitX(), Ys = T_gs.M.UnitY();
  const double b1 = trayH1(zs, Xs), b2 = trayH2(zs, Xs);  // h_j(r) is linear in r: slope along x_s
  const KDL::Vector r0 = T_gs.p - B + y * Ys;
  const double a1 = trayH1(zs, r0), a2 = trayH2(zs, r0);
  const RowSums::Moments& t = rs.trayed;
  const double sh1 = a1 * t.n + b1 * t.x1, sh2 = a2 * t.n + b2 * t.x1;      // sum h_j
  const double sxh1 = a1 * t.x1 + b1 * t.x2, sxh2 = a2 * t.x1 + b2 * t.x2;  // sum x h_j
  const double g2[3] = {-ks * sh1, -y * ks * sh1, ks * sxh1};              // a = z, wx, wy
  const double g3[3] = {-ks * sh2, -y * ks * sh2, ks * sxh2};
  for (int a = 0; a < 3; ++a) {
    out.dW_dth(a + 2, 0) += g2[a];
    out.dW_dth(a + 2, 1) += g3[a];
    out.dtau_ds(0, a + 2) += g2[a];
    out.dtau_ds(1, a + 2) += g3[a];
  }
  out.tau_tray(0) -= ks * (a1 * t.d0 + b1 * t.d1);  // -sum h_j f, f = ks d
  out.tau_tray(1) -= ks * (a2 * t.d0 + b2 * t.d1);
  const double s11 = a1 * a1 * t.n + 2.0 * a1 * b1 * t.x1 + b1 * b1 * t.x2;
  const double s12 = a1 * a2 * t.n + (a1 * b2 + a2 * b1) * t.x1 + b1 * b2 * t.x2;
  const double s22 = a2 * a2 * t.n + 2.0 * a2 * b2 * t.x1 + b2 * b2 * t.x2;
  out.dtau_dth(0, 0) -= ks * s11;
  out.dtau_dth(0, 1) -= ks * s12;
  out.dtau_dth(1, 0) -= ks * s12;
  out.dtau_dth(1, 1) -= ks * s22;
}

void PadSensor::addLayer(const ObjectSet& objects, const KDL::Frame& T_gs, int tray, const KDL::Vector& B,
                         double fy0, double fy1, ContactSums& c, ContactEval& out) const {
  // Layer: per sample row (y fixed), lowestZ over the x range where an
  // object can be below the surface (rowDepths: ObjectSet::rowSpan +
  // lowestZRow; +inf elsewhere, which carries no force). Every layer sample
  // has the same stiffness ks and z = 0, so a row's contribution follows from
  // five branch-free sums over its active samples (n, sum x, sum x^2, sum d,
  // sum x d): with g = (0, 0, -1, -y, x, 0),
  //   F_z = -ks sum d, M_x = -y ks sum d, M_y = ks sum x d,
  //   K = ks sum g g^T: K_zz = ks n, K_zx = ks y n, K_zy = -ks sum x,
  //   K_xx = ks y^2 n, K_xy = -ks y sum x, K_yy = ks sum x^2.
  // The tray terms use the same sums over the tray's samples: the
  // penetration gained per unit tray angle, h_j = -z_s . (a_j x r), is
  // affine in x along the row (r = p_g(x, y) - B).
  const int rows = params_.rows, cols = params_.cols, k = params_.physics_subsamples;
  const double pitch = params_.pitch;
  const double ks = params_.modulus * (pitch / k) * (pitch / k);
  double* xs = xrow_.data();
  for (int col = 0; col < cols; ++col)
    for (int j = 0; j < k; ++j) xs[col * k + j] = samples_[static_cast<std::size_t>(col * k * k + j)].x;
  double nact = 0.0;
  for (int r = 0; r < rows; ++r) {
    const double yc = (r - (rows - 1) / 2.0) * pitch;
    if (yc + 0.5 * pitch < fy0 || yc - 0.5 * pitch > fy1) continue;
    for (int i = 0; i < k; ++i) {
      const double y = samples_[static_cast<std::size_t>(r * cols * k * k + i * k)].y;
      RowSums rs;
      rowSums(objects, y, tray, rs);
      if (rs.all.n == 0.0) continue;
      nact += rs.all.n;
      out.layer_force += ks * rs.all.d0;
      addRowSums(ks, y, rs, c);
      if (rs.trayed.n > 0.0) addTrayRow(ks, y, T_gs, B, rs, out);
    }
  }
  out.active += static_cast<int>(nact);
}

void PadSensor::addHousing(const ObjectSet& objects, const KDL::Frame& T_gs, int tray, const KDL::Vector& B,
                           const double (&fp)[4], ContactSums& c, ContactEval& out) const {
  // Housing ring (top face at -recess): only if something reaches below it.
  const double fx0 = fp[0], fx1 = fp[1], fy0 = fp[2], fy1 = fp[3];
  const int h0 = objects.lowestPoint() < -params_.housing_recess ? n_samples_ - n_housing_ : n_samples_;
  for (int i = h0; i < n_samples_; ++i) {
    const Sample& s = samples_[static_cast<std::size_t>(i)];
    if (s.x < fx0 || s.x > fx1 || s.y < fy0 || s.y > fy1) continue;
    int which;
    const double zl = objects.lowestZ(s.x, s.y, which);
    addPointSample(s, zl, which, tray, T_gs, B, c, out);
  }
}

void PadSensor::storeSums(const ContactSums& c, ContactEval& out) {
  out.W_s(2) = c.Fz;
  out.W_s(3) = c.Mx;
  out.W_s(4) = c.My;
  out.K_s(2, 2) = c.Kzz;
  out.K_s(2, 3) = out.K_s(3, 2) = c.Kzx;
  out.K_s(2, 4) = out.K_s(4, 2) = c.Kzy;
  out.K_s(3, 3) = c.Kxx;
  out.K_s(3, 4) = out.K_s(4, 3) = c.Kxy;
  out.K_s(4, 4) = c.Kyy;
  out.K_s(2, 0) = c.Kzsx;
  out.K_s(3, 0) = c.Kxsx;
  out.K_s(4, 0) = c.Kysx;
  out.K_s(2, 1) = c.Kzsy;
  out.K_s(3, 1) = c.Kxsy;
  out.K_s(4, 1) = c.Kysy;
  out.K_s(2, 5) = c.Kzwz;
  out.K_s(3, 5) = c.Kxwz;
  out.K_s(4, 5) = c.Kywz;
}

void PadSensor::evaluate(const ObjectSet& objects, const KDL::Frame& T_gs, ContactEval& out) const {
  clearEval(out);
  const int tray = objects.trayIndex();
  const KDL::Vector B = tray >= 0 ? objects.bearing() : KDL::Vector::Zero();
  double fp[4];  // footprint: x0, x1, y0, y1
  if (!objects.footprint(fp[0], fp[1], fp[2], fp[3])) return;  // nothing reaches below the surface
  ContactSums c;
  addLayer(objects, T_gs, tray, B, fp[2], fp[3], c, out);
  addHousing(objects, T_gs, tray, B, fp, c, out);
  storeSums(c, out);
}

void PadSensor::maxPenetration(const ObjectSet& objects, double& layer, double& housing, int& object) const {
  layer = housing = 0.0;
  object = -1;
  // Fine check over the image sampling (an object may sit between physics samples).
  const int k = std::max(params_.subsamples, params_.physics_subsamples);
  const double h = params_.pitch / k;
  for (int r = 0; r < params_.rows * k; ++r)
    for (int c = 0; c < params_.cols * k; ++c) {
      const double x = -0.5 * params_.cols * params_.pitch + (c + 0.5) * h;
      const double y = -0.5 * params_.rows * params_.pitch + (r + 0.5) * h;
      int which;
      const double d = -objects.lowestZ(x, y, which);
      if (d > layer && d <= params_.depth_limit) { layer = d; object = which; }
    }
  for (int i = 0; i < n_samples_; ++i) {
    const Sample& s = samples_[static_cast<std::size_t>(i)];
    if (s.layer) continue;
    int which;
    const double zl = objects.lowestZ(s.x, s.y, which);
    const double d = s.z - zl;
    if (d > housing && -zl <= params_.depth_limit) {
      housing = d;
      if (layer <= 0.0) object = which;
    }
  }
}

void PadSensor::acquire(const ObjectSet& objects, const KDL::Frame& T_gs, double t, RawTactileFrame& raw, SensorTruth& truth) {
  integrate(objects, T_gs, t, truth);
  respond(t, raw, truth);
}

void PadSensor::integrate(const ObjectSet& objects, const KDL::Frame& T_gs, double t, SensorTruth& truth) {
  // Same Winkler integral as integratePad() (elastic_pad.hpp; a test checks
  // they agree), but taxel cells outside the objects' footprint are skipped.
  const int rows = params_.rows, cols = params_.cols, K = params_.subsamples;
  const double pitch = params_.pitch, h = pitch / K, dA = h * h, kmod = params_.modulus;
  const double lim = params_.depth_limit;
  double fx0 = 0, fx1 = 0, fy0 = 0, fy1 = 0;
  const bool any = objects.footprint(fx0, fx1, fy0, fy1);
  image_.rows = static_cast<uint16_t>(rows);
  image_.cols = static_cast<uint16_t>(cols);
  image_.saturated_count = 0;
  // Per image sample row: lowestZ over the x range where an object can be
  // below the surface (ObjectSet::rowSpan, then the branch-free
  // ObjectSet::lowestZRow); samples outside read 0 exactly. The summation
  // order is unchanged (taxel by taxel), so is the result.
  const int nx = cols * K;
  double* xs = xrow_.data();
  for (int c = 0; c < cols; ++c) {
    const double xc = (c - (cols - 1) / 2.0) * pitch;
    for (int j = 0; j < K; ++j) xs[c * K + j] = xc - 0.5 * pitch + (j + 0.5) * h;
  }
  double* zb = zrow_.data();
  int* wb = wrow_.data();
  double F = 0, Mx = 0, My = 0;
  for (int r = 0; r < rows; ++r) {
    const double yc = (r - (rows - 1) / 2.0) * pitch;
    const bool row_in = any && yc + 0.5 * pitch >= fy0 && yc - 0.5 * pitch <= fy1;
    if (row_in)
      for (int i = 0; i < K; ++i) rowDepths(objects, yc - 0.5 * pitch + (i + 0.5) * h, xs, nx, zb + i * nx, wb + i * nx);
    for (int c = 0; c < cols; ++c) {
      const double xc = (c - (cols - 1) / 2.0) * pitch;
      double f = 0.0;
      if (row_in && xc + 0.5 * pitch >= fx0 && xc - 0.5 * pitch <= fx1) {
        // Branch-free: d outside (0, depth_limit] counts as 0.
        const double* xt = xs + c * K;
        for (int i = 0; i < K; ++i) {
          const double y = yc - 0.5 * pitch + (i + 0.5) * h;
          const double* z = zb + i * nx + c * K;
          double sd = 0.0, sxd = 0.0;
          for (int j = 0; j < K; ++j) {
            const double d = -z[j];
            const double dd = (d > 0.0) & (d <= lim) ? d : 0.0;
            sd += dd;
            sxd += xt[j] * dd;
          }
          const double df = kmod * dA * sd;
          f += df;
          Mx += y * df;
          My += kmod * dA * sxd;
        }
      }
      image_.force[static_cast<std::size_t>(r * cols + c)] = f;
      F += f;
    }
  }
  truth.layer.force = F;
  truth.layer.cop_x = F > 0 ? My / F : 0.0;
  truth.layer.cop_y = F > 0 ? Mx / F : 0.0;
  truth.layer.moment_x = Mx;
  truth.layer.moment_y = -My;
  image_.time_s = t;
  // Housing share (physics sampling of the ring).
  double Fh = 0, Mxh = 0, Myh = 0;
  const bool deep = any && objects.lowestPoint() < -params_.housing_recess;  // else no housing contact
  for (int i = n_samples_ - n_housing_; i < n_samples_ && deep; ++i) {
    const Sample& s = samples_[static_cast<std::size_t>(i)];
    if (s.layer || s.x < fx0 || s.x > fx1 || s.y < fy0 || s.y > fy1) continue;
    int which;
    const double zl = objects.lowestZ(s.x, s.y, which);
    const double d = s.z - zl;
    if (!(d > 0.0) || -zl > lim) continue;
    const double f = s.k * d;
    Fh += f;
    Mxh -= s.y * f;
    Myh += s.x * f;
  }
  truth.time_s = t;
  truth.housing_force = Fh;
  truth.wrench_s = {0.0, 0.0, -(truth.layer.force + Fh), -truth.layer.moment_x + Mxh, -truth.layer.moment_y + Myh, 0.0};
  truth.in_contact = truth.layer.force > 0.0;
  const KDL::Vector cp = T_gs * KDL::Vector(truth.layer.cop_x, truth.layer.cop_y, 0.0);
  truth.contact_point_g = {cp.x(), cp.y(), cp.z()};
  geometry_ = truth;
}

void PadSensor::acquireRepeat(double t, RawTactileFrame& raw, SensorTruth& truth) {
  integrateRepeat(t, truth);
  respond(t, raw, truth);
}

void PadSensor::integrateRepeat(double t, SensorTruth& truth) {
  truth = geometry_;
  truth.time_s = t;
  image_.time_s = t;
}

void PadSensor::respond(double t, RawTactileFrame& raw, SensorTruth& truth) {
  // Taxel response (App. A): counts, noise, 12-bit quantisation, saturation, threshold.
  truth.max_count = response_.respond(image_, t, raw);
}

}  // namespace sim
}  // namespace tactile
