// Weiss WTS0614 pad on the flange: geometry, elastic layer, rigid housing,
// taxel response (App. A) and the contact wrench/stiffness the arm feels.
//
// Geometry ({s}: origin at the centre of the sensing surface, x along the
// 14-taxel side, y along the 6-taxel side, z out of the surface):
//   * sensing area: rows x cols taxels at `pitch` (6 x 14 at 3.4 mm = 20.4 x
//     47.6 mm) covered by an elastic layer whose undeformed surface is z = 0;
//   * rigid housing: the rectangle housing_size_x x housing_size_y around the
//     sensing area (default 64 x 34 mm: the sensor module with its mounting
//     frame), its top face at z = -housing_recess (default 2 mm below the layer
//     surface: an edge of 3 mm radius across the whole pad reaches it at about
//     22 N). Contact there pushes the arm (stiff penalty, housing_modulus)
//     but produces no taxel signal: an edge that slides off the sensing area
//     and is pushed further meets the housing with no warning in the image.
//   Beyond the housing outline nothing touches (the flange and the arm links
//   are not contact bodies).
//
// Elastic layer (Winkler foundation, Eq. 2): pressure p = modulus * delta,
// delta = penetration of the object into the layer measured along z_s. Forces
// are along z_s only (frictionless, as assumed in Sec. 3.2). C_z, C_wx and C_wy
// of Eq. 2 are not parameters: they follow from the foundation. For an edge
// of rounding radius r across the pad, F = k L (4/3) sqrt(2 r) delta^1.5, so
// dF/dz = 1.5 F / delta. Default modulus 5e7 Pa/m: a 3 mm-radius bar over
// 47.6 mm pressed with 5 N sinks 0.74 mm (secant 6700 N/m, tangent 10^4 N/m;
// contact 4.2 mm wide, so the centre taxel row carries ~0.3 N per taxel,
// above the 0.2 N threshold). A softer layer (C_z = 1/1800 m/N as quoted for
// the paper's edge needs ~1e7 Pa/m) spreads a 5 N edge over two rows at
// < 0.2 N per taxel, i.e. an invisible edge: the default favours a visible
// contact. A non-uniform line load tilts the contact: the moments are
// k * integral of x^2 (about y_s) over the contact.
//
// Taxel response (App. A, Fig. A.15): the true taxel force f (N) maps to raw
// counts n through the inverse of a monotone cubic f(n) = c1 n + c2 n^2 + c3 n^3
// (centre taxels) and the same polynomial divided by `border_sensitivity` on
// the outer ring (weaker border taxels: fewer counts per newton). Gaussian
// noise (noise_counts, 1 sigma) is added, counts are rounded (12-bit) and
// clamped to [0, full_scale] (saturation), and a taxel whose calibrated value
// is below `threshold` (0.2 N) reads 0 (the device's firing threshold).
// calibration() returns the tactile::CalibrationParams that inverts this
// response exactly (up to noise and quantisation), so the runner calibrates
// exactly as on the real robot. With `use_calibration` the response is the
// inverse of the given calibration (the sensor's file) instead; either way
// the counts come from tactile::sim::TaxelResponse.
#pragma once

#include <array>
#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Core>
#include <kdl/frames.hpp>

#include "tactile_features/calibration.hpp"
#include "tactile_sim_contact/elastic_pad.hpp"
#include "tactile_sim_lwr/objects.hpp"
#include "tactile_sim_lwr/taxel_response.hpp"
#include "tactile_types/config_result.hpp"
#include "tactile_types/types.hpp"

namespace tactile {
namespace sim {

struct PadParams {
  /// {e}T{s}: mounting of the sensor on the flange. Default: surface 0.02 m
  /// beyond the flange along z_e, axes aligned.
  tactile::Pose mount{{0.0, 0.0, 0.02}, {0.0, 0.0, 0.0, 1.0}};
  int rows = kDefaultRows;
  int cols = kDefaultCols;
  double pitch = kDefaultPitch;     ///< m
  double modulus = 5.0e7;           ///< foundation modulus of the layer (Pa/m)
  double layer_thickness = 0.003;   ///< m; an object deeper than this at start is "inside the sensor"
  int subsamples = 4;               ///< K: K x K samples per taxel for the tactile image (acquire)
  int physics_subsamples = 2;       ///< samples per taxel side for the wrench the arm feels (step)
  double housing_size_x = 0.064;    ///< m, outline along x_s
  double housing_size_y = 0.034;    ///< m, outline along y_s
  double housing_recess = 0.002;    ///< m, housing top face below the layer surface
  double housing_modulus = 2.0e9;   ///< Pa/m, penalty modulus of the rigid housing
  double housing_spacing = 0.0034;  ///< m, sample spacing over the housing ring
  double depth_limit = 0.03;        ///< m; deeper "penetrations" are objects behind the sensor: ignored
  // Response (App. A)
  uint16_t full_scale = 4095;       ///< 12-bit
  std::array<double, 3> response{4.0e-4, 0.0, 2.0e-11};  ///< c1, c2, c3 of f(n) (N/count^k), centre taxels
  double border_sensitivity = 0.6;  ///< counts-per-newton ratio of the outer ring to the centre, (0, 1]
  double noise_counts = 6.0;        ///< Gaussian noise, 1 sigma (counts)
  double threshold = 0.2;           ///< N: taxels below read 0
  uint64_t seed = 1;                ///< noise seed
  /// When set, the response is the inverse of this calibration (the sensor's
  /// calibration file, e.g. wts0614.yaml's `calibration:` block; scenes set
  /// it from their features_file) instead of response/border_sensitivity.
  bool use_calibration = false;
  tactile::CalibrationParams calibration;
};

/// Ground truth of one acquisition (what an ATI Nano17 under the sensor
/// measures, App. A) plus the housing share and the contact point in {g}.
struct SensorTruth {
  double time_s = 0.0;
  PadTruth layer;                   ///< continuous pressure over the sensing area (force >= 0, {s})
  double housing_force = 0.0;       ///< N carried by the rigid housing
  /// Total wrench exerted by the objects on the sensor, in {s} about its
  /// origin, [fx fy fz mx my mz] (fz = -(layer + housing force)).
  std::array<double, 6> wrench_s{};
  std::array<double, 3> contact_point_g{};  ///< layer pressure centre on the surface, in {g}
  bool in_contact = false;          ///< layer force > 0
  int max_count = 0;                ///< largest raw count in the frame
};

/// Contact evaluation result for the physics (allocation-free).
struct ContactEval {
  Eigen::Matrix<double, 6, 1> W_s = Eigen::Matrix<double, 6, 1>::Zero();  ///< wrench on the sensor, {s} about origin
  /// -dW_s/d(sensor twist in {s}): rows (z, wx, wy) only (frictionless layer);
  /// columns (z, wx, wy) from the columns' compression (symmetric block),
  /// columns (x, y, wz) from the penetration field sliding under the sensor
  /// (surface slopes of the layer contact; the housing ring's are left out).
  /// The quasi-static Newton tangent.
  Eigen::Matrix<double, 6, 6> K_s = Eigen::Matrix<double, 6, 6>::Zero();
  // Tray coupling (zero without a tray): angles (pitch, roll).
  Eigen::Matrix<double, 6, 2> dW_dth = Eigen::Matrix<double, 6, 2>::Zero();  ///< dW_s/dtheta
  Eigen::Vector2d tau_tray = Eigen::Vector2d::Zero();   ///< contact torque on the tray about the bearing (x_g, y_g)
  Eigen::Matrix2d dtau_dth = Eigen::Matrix2d::Zero();   ///< d tau_tray / d theta
  Eigen::Matrix<double, 2, 6> dtau_ds = Eigen::Matrix<double, 2, 6>::Zero();  ///< d tau_tray / d(sensor twist in {s})
  double layer_force = 0.0, housing_force = 0.0;       ///< N (>= 0)
  int active = 0;                                       ///< samples in contact
};

class PadSensor {
 public:
  ConfigResult configure(const PadParams& params);
  const PadParams& params() const { return params_; }
  const KDL::Frame& mount() const { return T_es_; }

  /// Wrench, stiffness and tray coupling at the current object placement
  /// (objects.pose() already called with this sensor pose). T_gs is needed for
  /// the tray lever arms. Uses the physics sampling. Allocation-free.
  void evaluate(const ObjectSet& objects, const KDL::Frame& T_gs, ContactEval& out) const;

  /// Tactile image + ground truth at the current placement. Uses the image
  /// sampling (subsamples). Consumes noise from the internal generator.
  /// Allocation-free.
  void acquire(const ObjectSet& objects, const KDL::Frame& T_gs, double t, RawTactileFrame& raw, SensorTruth& truth);
  /// The same as acquire() with the objects and T_gs of the previous
  /// acquire() (the caller guarantees that nothing moved): the contact
  /// integral is reused, the response (noise, quantisation, threshold) is
  /// drawn anew. Bit-identical to a full acquire() at the same placement.
  void acquireRepeat(double t, RawTactileFrame& raw, SensorTruth& truth);
  /// The contact part of acquire() alone: the noise-free taxel forces
  /// (trueTaxelForces()) and the ground truth, no response (no noise drawn).
  void integrate(const ObjectSet& objects, const KDL::Frame& T_gs, double t, SensorTruth& truth);
  /// integrate() at the placement of the previous one (nothing moved).
  void integrateRepeat(double t, SensorTruth& truth);

  /// Largest penetration (m) into the layer and into the housing at the
  /// current placement, and the object responsible (-1 if none).
  void maxPenetration(const ObjectSet& objects, double& layer, double& housing, int& object) const;

  /// Calibration that inverts the response (for tactile::Calibration).
  tactile::CalibrationParams calibration() const;
  /// The calibration a pad with these parameters is read with (the given
  /// file's when use_calibration, else the inverse of response/border_sensitivity).
  static tactile::CalibrationParams calibrationOf(const PadParams& params);

  /// Noise-free forward response of taxel (r, c): force (N) -> counts (real).
  double countsFor(int r, int c, double force) const;
  /// The calibrated force of `counts` at taxel (r, c) (same polynomial as calibration()).
  double forceFor(int r, int c, double counts) const;

  void reseed(uint64_t seed) { response_.reseed(seed); }
  const TactileFrame& trueTaxelForces() const { return image_; }  ///< last acquire(): noise-free taxel forces (N)

 private:
  struct Sample {
    double x, y, z, k;  // position in {s}, stiffness modulus * dA (N/m)
    bool layer;
  };
  static constexpr int kMaxSamples = 4096;
  bool isBorder(int r, int c) const { return r == 0 || c == 0 || r == params_.rows - 1 || c == params_.cols - 1; }

  PadParams params_;
  KDL::Frame T_es_;
  std::array<Sample, kMaxSamples> samples_{};
  int n_samples_ = 0, n_housing_ = 0;
  TactileFrame image_;
  TaxelResponse response_;
  SensorTruth geometry_;  // contact part of the last acquire() (for acquireRepeat)
  // Row buffers (sized in configure(); mutable: scratch of the const evaluate()).
  mutable std::vector<double> xrow_, zrow_, sxrow_, syrow_;
  mutable std::vector<int> wrow_;
  /// lowestZ at (xs[i], y), i < n (xs ascending), +inf outside rowSpan().
  void rowDepths(const ObjectSet& objects, double y, const double* xs, int n, double* z, int* which,
                 double* sx = nullptr, double* sy = nullptr) const;
  void respond(double t, RawTactileFrame& raw, SensorTruth& truth);

  // The steps of evaluate(), in order.
  struct ContactSums;
  struct RowSums;
  /// The layer's contact: per sample row, rowSums, addRowSums and, on the tray, addTrayRow.
  void addLayer(const ObjectSet& objects, const KDL::Frame& T_gs, int tray, const KDL::Vector& B, double fy0,
                double fy1, ContactSums& c, ContactEval& out) const;
  /// rowDepths along one layer sample row at y, then its masked sums (tray samples apart when tray >= 0).
  void rowSums(const ObjectSet& objects, double y, int tray, RowSums& rs) const;
  /// One row's wrench, stiffness and sliding columns (layer stiffness ks per sample) into c.
  static void addRowSums(double ks, double y, const RowSums& rs, ContactSums& c);
  /// One row's tray terms (tau_tray and its derivatives) from the tray's samples.
  static void addTrayRow(double ks, double y, const KDL::Frame& T_gs, const KDL::Vector& B, const RowSums& rs,
                         ContactEval& out);
  /// The housing ring's samples in the footprint (x0, x1, y0, y1), one by one.
  void addHousing(const ObjectSet& objects, const KDL::Frame& T_gs, int tray, const KDL::Vector& B,
                  const double (&fp)[4], ContactSums& c, ContactEval& out) const;
  /// One sample at depth zl below object `which` (layer or housing) into c and out.
  void addPointSample(const Sample& s, double zl, int which, int tray, const KDL::Frame& T_gs, const KDL::Vector& B,
                      ContactSums& c, ContactEval& out) const;
  /// The sums into out's (z, wx, wy) rows of W_s and K_s.
  static void storeSums(const ContactSums& c, ContactEval& out);
};

}  // namespace sim
}  // namespace tactile
