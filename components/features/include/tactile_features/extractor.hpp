// Tactile feature extraction from image moments (paper Sec. 3, Sec. 3.3, App. B).
//
// Input: a calibrated frame (N per taxel) in the {s} layout of conventions.hpp.
// Output: ContactFeatures in {s}, SI units. Negative taxel values (tare noise)
// are treated as 0 before any moment is taken.
//
//   M00 = sum f_i,  M10 = sum x_i f_i,  M01 = sum y_i f_i          (Eq. B.1)
//   CoP = (M10/M00, M01/M00)                                      (Eq. B.2, B.3)
//   f   = M00,  d_z = C_z * f                                     (Eq. 2)
//   CoC = mean position of taxels with f_i > threshold            (Sec. 3.2)
//   DZMP_x = CoP_y - CoC_y,  DZMP_y = CoP_x - CoC_x               (Eq. 3)
//   Q   = [mu20 mu11; mu11 mu02] / M00   (pressure-weighted covariance, m^2)
//   lambda1 >= lambda2 = eig(Q);  alpha_z = angle of U1 from x_s  (Eq. B.4, B.5)
//   contact type: none if max f_i < contact_threshold, else edge when
//   lambda1 >= edge_ratio * lambda2 (Eq. 5) and sqrt(12 lambda1) >=
//   edge_min_length (a line that short is a blob), else point.
//
// Deliberate choices, each documented where implemented:
//  * Q is the pressure-weighted covariance (second central moments / M00),
//    not the unweighted sample covariance of Eq. B.4 over n = 84 pixels: the
//    weighted form is what "PCA of the tactile image" means for a grey image
//    and uses the same force weights as the moments of Eq. B.1-B.3.
//  * alpha_z is an axis angle, defined modulo pi. It is wrapped to
//    (-pi/2, pi/2]. To keep a slowly rotating edge from flipping between
//    +pi/2 and -pi/2 from one frame to the next, the extractor keeps the
//    previous branch while the angle stays within `alpha_hysteresis` beyond
//    +-pi/2 (output range (-pi/2 - h, pi/2 + h]); it re-wraps once the angle
//    leaves the band. h = 0 gives the plain wrap.
//  * When the contact is isotropic (lambda1 - lambda2 <= isotropy_tol *
//    (lambda1 + lambda2)) the principal direction is undefined; alpha_z then
//    keeps its previous value (0 after configure/reset), so it stays finite
//    and does not jitter with noise.
//  * The contact type has hysteresis: an edge stays an edge until
//    lambda1 < edge_ratio_exit * lambda2, with edge_ratio_exit <= edge_ratio.
//  * Otsu: exact Otsu over the frame's own values (every split between sorted
//    distinct values is scored with the between-class variance); no 8-bit
//    binning. On 8-bit-quantised data this gives the same partition as
//    OpenCV's THRESH_OTSU (tested).
#pragma once

#include <array>
#include <cstdint>

#include "tactile_types/config_result.hpp"
#include "tactile_types/sensor_geometry.hpp"
#include "tactile_types/types.hpp"

namespace tactile {

enum class ThresholdMode : uint8_t { Fixed = 0, Otsu = 1 };

struct FeatureParams {
  int rows = kDefaultRows;
  int cols = kDefaultCols;
  double pitch = kDefaultPitch;               ///< m, > 0
  double c_z = 1.0 / 1800.0;                  ///< m/N, >= 0 (Eq. 2)
  ThresholdMode threshold_mode = ThresholdMode::Fixed;
  double threshold = 0.2;                     ///< N, >= 0: binarisation for CoC
  double contact_threshold = 0.2;             ///< N, >= 0: any taxel above -> contact
  double edge_ratio = 5.0;                    ///< lambda1/lambda2 to enter "edge", >= 1
  double edge_ratio_exit = 4.0;               ///< ratio below which an edge becomes a point, in [1, edge_ratio]
  /// An edge must also be long: the length of a uniform line with the same
  /// spread, sqrt(12 lambda1), must reach this (m, >= 0). Without it a
  /// two-taxel blob (lambda2 = 0) would be an "edge". Default 2.5 pitches.
  double edge_min_length = 2.5 * kDefaultPitch;
  double alpha_hysteresis = 10.0 * kPi / 180; ///< rad, in [0, pi/4]
  double isotropy_tol = 1e-6;                 ///< relative eigenvalue gap below which alpha_z is held, in [0, 1)

  /// The taxel layout in {s} these parameters describe.
  SensorGeometry geometry() const { return SensorGeometry{rows, cols, pitch}; }
};

/// Intermediate moments, exposed for tests and tools.
struct Moments {
  double m00 = 0, m10 = 0, m01 = 0;
  double mu20 = 0, mu11 = 0, mu02 = 0;  ///< central, normalised by M00 (m^2)
};

class FeatureExtractor {
 public:
  ConfigResult configure(const FeatureParams& params);

  /// One frame -> features. Allocation-free, never throws, always sets
  /// out.status. On an invalid status every numeric field of `out` is zero and
  /// the internal history (alpha branch, contact type) is untouched.
  FeatureStatus step(const TactileFrame& frame, ContactFeatures& out);

  /// Forget the history (alpha branch, contact-type hysteresis).
  void reset();

  const FeatureParams& params() const { return params_; }
  const Moments& lastMoments() const { return moments_; }
  /// Binarisation threshold used for the last frame (N).
  double lastThreshold() const { return last_threshold_; }

  /// Taxel centre in {s} (m): SensorGeometry::x(col), y(row), tabulated.
  double taxelX(int col) const { return xs_[static_cast<std::size_t>(col)]; }
  double taxelY(int row) const { return ys_[static_cast<std::size_t>(row)]; }

  /// Exact Otsu threshold of n values (n <= kMaxTaxels): the returned t splits
  /// them into {v <= t} and {v > t}. Allocation-free.
  static double otsuThreshold(const double* values, int n);

 private:
  bool configured_ = false;
  FeatureParams params_;
  std::array<double, kMaxCols> xs_{};
  std::array<double, kMaxRows> ys_{};
  Moments moments_;
  double last_threshold_ = 0.0;
  double alpha_prev_ = 0.0;
  ContactType type_prev_ = ContactType::None;
};

}  // namespace tactile
