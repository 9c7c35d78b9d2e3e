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
//  * alpha_z within the noise. alpha_z = 1/2 atan2(g_y, g_x) with
//    g = (mu20 - mu02, 2 mu11), |g| = lambda1 - lambda2 (Eq. B.4, B.5). With
//    independent noise sigma_i (N) on each taxel i of the image (weights
//    w_i = f_i / M00, offsets d_i from the CoP), to first order
//      dg/df_i = (u_i - g) / M00,  u_i = (dx_i^2 - dy_i^2, 2 dx_i dy_i)
//    (the CoP shift drops out: sum w_i d_i = 0), so
//      sigma_alpha^2 = sum_i sigma_i^2 ((u_i - g) . n)^2 / (4 M00^2 |g|^2),
//    n the unit normal of g. alpha_z is *defined* (out.alpha_defined) when
//    sigma_alpha <= alpha_max_sigma, i.e. when lambda1 - lambda2 stands out
//    of its own noise; sigma_i = taxel_noise for every taxel of the image
//    (the silent ones read exactly 0 below the device's threshold). taxel_noise is the
//    count noise times the calibration's slope dF/dn at the firing threshold
//    (SensorStage::configure); at higher loads the slope of the WTS0614
//    polynomial grows (x3.5 at full scale), where |g| M00 grows faster.
//    With taxel_noise = 0 the test is the relative gap > isotropy_tol.
//    When undefined, and for a multiple contact, alpha_z keeps its previous
//    defined value (0 after configure/reset): finite, no frame-to-frame
//    jumps, and the servo does not drive the alpha_z row from it.
//  * Separate contacts. The firing taxels (> contact_threshold) are grouped
//    into regions (connected when at most region_gap silent taxels apart,
//    Chebyshev distance; a silent taxel that fired recently -- firing rate
//    >= region_min_rate, see "Taxels the noise switches off" -- counts as
//    firing). Two or more regions carrying >= region_min_force each give
//    ContactType::Multiple: their joint moments would make one long
//    "edge" between them. All moments stay those of the whole image (f is the
//    total force); alpha_z is undefined; the servo uses no edge Jacobian.
//    region_min_rate is a time: a taxel that fired steadily and fell silent
//    stops joining after censor_tau ln(1 / region_min_rate) (0.39 s at 0.1 s
//    and 0.02). From one image a gap in an edge (the pad over it unloaded)
//    and a line load sagging below the threshold (the pad still loaded there)
//    look the same; the sagging taxels fire now and then (noise, the load's
//    ripple), the gap's never. Larger values find a gap sooner (it must stay
//    silent that long under the pad: ~0.5 s for a 10 mm gap at 10 mm/s) and
//    split a sagging line more often (docs/simulator.md, "A gap under the pad").
//  * Taxels the noise switches off (censoring by the device's firing
//    threshold t = contact_threshold). A taxel with load f reads 0 below t;
//    with count noise sigma (taxel_noise) it fires with probability
//    p = Phi((f - t) / sigma), and its reading is 0 in a fraction 1 - p of
//    the frames. For a line load near t per taxel (a 5 N edge over two rows
//    of 14 taxels is ~0.2 N per taxel) the measured force then drops with
//    the noise, and the servo, which holds the measured force, presses the
//    true force up (5x noise: 6.2 N true for 5 N measured, out of 5 +- 1).
//    Each taxel keeps its firing rate p (exponential average of "fired",
//    time constant censor_tau in seconds of frame time, so independent of
//    the frame rate). While some taxel fires, a silent taxel with
//    p >= 1/2 -- its maximum-likelihood load t + sigma Phi^-1(p) is at or
//    above t: a noise-free sensor would report it -- is given that load,
//    clamped to [t, t + 3 sigma], and counts as "in contact" for the CoC.
//    The image the features are taken from is the readings plus these
//    estimates: f = M00 (Eq. 2, B.1), CoP, CoC and the PCA see what the
//    noise-free sensor would, and the noise no longer biases f down.
//    Taxels below t on average stay 0 while silent, as without noise (when
//    the noise makes one fire, its reading counts: a small bias up): the
//    truncation bias of the firing threshold itself (docs/simulator.md, "Known bias of the paper's force")
//    is not undone.
//    Delay: only the estimates lag; a taxel that stops firing is estimated
//    for censor_tau ln 2 (69 ms at 0.1 s) at most, readings count at once.
//    A silent taxel with p >= region_min_rate also joins contact regions (above).
//  * Bad values: NaN/Inf -> InvalidInput; a finite value beyond
//    +-max_taxel_force -> OutOfRange (nothing propagated, history kept);
//    values below kForceFloor (1e-200 N) -- denormals included -- and
//    negative values (tare noise) are 0; a contact needs M00 > kForceFloor.
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

/// Firing rate below which a silent taxel is not counted as loaded:
/// p = Phi(-3), a load t - 3 sigma or less resting on a firing event more
/// than about censor_tau * ln(1/p) ~ 6.6 censor_tau old.
constexpr double kMinFiringRate = 0.00135;

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

  /// 1-sigma noise of one firing taxel (N), >= 0: the sensor's count noise
  /// through the calibration's slope at the firing threshold (SensorStage sets
  /// it from calibration.noise_counts). 0 = noise-free: alpha_z is then
  /// undefined only below isotropy_tol and there is no sub-threshold estimate.
  double taxel_noise = 0.0;
  /// alpha_z is defined when its 1-sigma noise, propagated from taxel_noise
  /// through Eq. B.4/B.5, is at most this (rad), > 0.
  double alpha_max_sigma = 0.05;
  /// Time constant (s) of each taxel's firing-rate estimate behind the
  /// sub-threshold force estimate, >= 0; 0 switches that estimate off.
  double censor_tau = 0.1;
  /// A silent taxel is given its maximum-likelihood load when its firing
  /// rate is at least this, in [0.01, 0.99]. 1/2 = "a noise-free sensor
  /// would report it" (the estimate is then >= the firing threshold).
  double censor_min_rate = 0.5;
  /// Contact regions: firing taxels separated by at most `region_gap` silent
  /// taxels belong to one region (a noise dropout does not split a contact);
  /// in [0, 4].
  int region_gap = 1;
  /// A region counts as a separate contact when it carries at least this (N), > 0.
  double region_min_force = 0.5;
  /// A silent taxel joins contact regions while its firing rate is at least
  /// this, in [kMinRate, 0.99] (see "Separate contacts" above). The default,
  /// kMinRate, joins anything that fired within ~6.6 censor_tau.
  double region_min_rate = kMinFiringRate;
  /// A finite taxel value beyond +-this (N) is not a reading of this sensor:
  /// status OutOfRange, nothing propagated. > 0.
  double max_taxel_force = 1000.0;

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
  /// Contact regions (>= region_min_force) found in the last frame.
  int lastRegionCount() const { return last_regions_; }
  /// Sub-threshold force estimate added to f in the last frame (N).
  double lastSubthresholdForce() const { return last_subthreshold_; }
  /// 1-sigma noise of alpha_z in the last frame (rad; +inf when undefined by geometry).
  double lastAlphaSigma() const { return last_alpha_sigma_; }

  /// Values below this (N) are 0. No reading of a WTS is that small (one
  /// count is ~1e-4 N); above it every product in the moments (x^2 f with
  /// |x| >= pitch/2) is a normal double: no subnormal arithmetic, which is
  /// imprecise (and slow on x86), while loads down to 1e-190 N keep their
  /// exact geometry.
  static constexpr double kForceFloor = 1e-200;
  static constexpr double kMinRate = kMinFiringRate;

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
  int last_regions_ = 0;
  double last_subthreshold_ = 0.0;
  double last_alpha_sigma_ = 0.0;
  double est_min_ = 0.0;  ///< lowest sub-threshold estimate: t + sigma Phi^-1(censor_min_rate)
  // Sub-threshold estimate: per-taxel firing rate and the last frame time.
  std::array<double, kMaxTaxels> fire_rate_{};
  double last_time_ = 0.0;
  bool have_time_ = false;

  int countRegions(const double* f, int rows, int cols);
  double subthresholdForce(const double* f, int n, double t, double* img, uint8_t* estimated);

  // The steps of step(), in order (contracts in extractor.cpp).
  struct RawMoments;
  void updateFiringRates(const TactileFrame& frame, int n);
  void buildImage(const double* f, int n, bool add_estimate, double* img, uint8_t* estimated);
  void accumulateMoments(const double* g, const uint8_t* estimated, double thr, RawMoments& m) const;
  static void contactGeometry(const RawMoments& m, ContactFeatures& out, Moments& mo);
  double alphaSigma(const double* g, double m00, double cx, double cy, const Moments& mo) const;
  bool principalAngle(const RawMoments& m, const ContactFeatures& out, const Moments& mo, double& alpha) const;
  ContactType classifyContact(const double* f, bool loaded_and_firing, const ContactFeatures& out);
};

}  // namespace tactile
