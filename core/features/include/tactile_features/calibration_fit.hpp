// Fitting the WTS0614's calibration (App. A, Fig. A.15) from a recording of
// the sensor under known loads: the offline half of tactile::Calibration
// (calibration.hpp). The tool is tactile_calibrate (tools/tactile_calibrate.cpp);
// the procedure, the CSV format and the measured accuracy are in
// docs/calibration.md.
//
// RECORDING (CSV, one frame per line, a header line first):
//     time_s, f_ref_n, raw_0, ..., raw_{rows*cols-1}
// raw_i: the taxel's raw 12-bit count, row-major in the {s} layout (the order
// of RawTactileFrame::counts, `wts_read --raw`). f_ref_n: the known total
// normal force on the pad in that frame (N, pressing > 0): a reference F/T
// sensor's force along the pad normal, or m g of a weight resting on the pad.
// Frames with |f_ref_n| <= unloaded_max_n are unloaded: they give the tare and
// the noise. Blank lines and lines starting with '#' are skipped.
//
// MODEL. Per frame j the calibrated forces must add up to the reference:
//     sum_i p_i(n_ij) = f_j,   n_ij = raw_ij - tare_i   (counts above the tare)
//     p_i(n) = c1_i n + c2_i n^2 + ... + cd_i n^d        (c0 = 0, d = degree 1..3)
// which is linear in the coefficients: least squares over the loaded frames,
// solved on the normal equations (LDLT) in normalised counts u = n / full_scale
// (every column O(1)). The coefficients are shared by groups of taxels:
//   shared   : one polynomial for every taxel (d unknowns);
//   border   : one for the interior, one for the outer ring (2d unknowns; App.
//              A: "the rubber at the corners is not as flexible as at the
//              center", the border taxels are stiffer);
//   per_taxel: one per taxel (rows*cols*d unknowns; needs loads at many spots).
//              Ridge toward the border model's fit (the prior, fitted first):
//              minimise |A c - f|^2 + sum_ik lambda_k (c_ik - prior_ik)^2 with
//              lambda_k = ridge x the mean over taxels of the diagonal entry of
//              A^T A of power k (the average excitation). A taxel loaded as
//              much as the average moves freely (its coefficients shrink
//              toward the prior by ~ridge = 0.1 %); one never loaded keeps
//              the prior (listed in CalibrationFit::at_prior); in between the
//              data and the prior share the weight by their excitation.
// Constraint (nonnegative, default on): c1, c2, c3 >= 0, a monotone convex
// force-vs-count curve. The simulated sensor (sim TaxelResponse) requires it
// to invert the polynomial, and a piezoresistive cell whose counts saturate
// with the load has that shape. Solved as a bounded least-squares problem
// (Lawson-Hanson active set on the normal equations; when the unconstrained
// solution already satisfies it, that solution is returned unchanged).
// A fitted c1 of 0 (the constraint active on the slope) is an error: the
// lightest loads are missing.
//
// WHICH COUNTS ENTER. tare_i = the mean raw count of taxel i over the unloaded
// frames, noise_i = their standard deviation, floored at min_noise_counts (a
// silent taxel reads a constant). A tared count enters the fit only above
// noise_sigmas x noise_i; below, it is 0: a quiet taxel's rectified noise
// (max(0, raw - tare) over ~80 idle taxels) would otherwise add a load-
// independent offset the c0 = 0 polynomial cannot absorb.
//
// FRAMES LEFT OUT (counted in the result, named in `notes`):
//   * saturated: a loaded frame with any raw count >= full_scale. That taxel's
//     count no longer follows the load, so the frame's sum is wrong: the frame
//     is dropped, not the taxel. Refused (error) when every loaded frame is
//     saturated.
//   * silent: a loaded frame where no taxel is above its noise (a load below
//     the WTS's firing threshold, or on a dead spot). Refused when every
//     loaded frame is silent.
//
// REPORT. Frame residual r_j = predicted - f_ref (N). Per taxel the residual
// is attributed by the taxel's share of the predicted force,
// r_ij = r_j p_i(n_ij) / sum_k p_k(n_kj), and reported as the RMS of r_ij over
// the frames in which taxel i was above its noise (N; NaN if never). A single
// taxel under the probe takes its frame's whole residual; a contact spread
// over several taxels splits it by load (the loaded taxels carry the error).
// Also: RMS and max |r_j| (N), RMS in % of the load range (0 .. the largest
// f_ref used), residual sigma (RMS with the degrees of freedom), the
// condition number of the column-scaled design matrix (without the ridge) and
// of the regularised normal matrix, and the standard error of each fitted
// curve (curveStdError: sigma^2 (A^T A + Lambda)^-1, the data's share of the
// covariance; the ridge's bias is not in it).
//
// ERRORS (ConfigResult, each names the file, what is wrong and what to do):
// malformed line (line and column), NaN/Inf, wrong number of columns, raw
// outside [0, 4095], no unloaded frames (no tare), no loaded frames, negative
// loads (a reference with its z flipped), a tare above calibration.max_tare,
// every loaded frame saturated or silent, a dead taxel (never above its noise
// while every one of its 4-neighbours was loaded, > loaded_sigmas x noise, in
// some frame; named by row/col), fewer than degree + 1 distinct loads (loads
// closer than distinct_load_resolution x the largest are one load), a group of
// taxels never loaded (border model: the outer ring or the interior), an
// ill-conditioned problem, a zero slope.
//
// Offline: allocates, not for a per-cycle path.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "tactile_features/calibration.hpp"
#include "tactile_types/config_result.hpp"

namespace tactile {

/// A recording of the pad under known loads (the CSV above), in memory.
struct CalibrationRecording {
  std::string file;           ///< where it came from (messages)
  int rows = kDefaultRows;
  int cols = kDefaultCols;
  std::vector<double> time_s;  ///< per frame (s)
  std::vector<double> f_ref;   ///< per frame: the known total normal force (N, pressing > 0)
  std::vector<double> raw;     ///< frames x rows*cols raw counts, frame-major, row-major within
  std::vector<long> line;      ///< per frame: its line in the file (1-based)

  std::size_t frames() const { return f_ref.size(); }
  int taxels() const { return rows * cols; }
  double rawAt(std::size_t frame, int taxel) const {
    return raw[frame * static_cast<std::size_t>(taxels()) + static_cast<std::size_t>(taxel)];
  }
};

/// Parses a recording. `name` is used in messages (the file's path). Errors
/// name the line and column. rows x cols sets the expected column count.
ConfigResult readCalibrationRecording(std::istream& in, const std::string& name, int rows, int cols,
                                      CalibrationRecording& out);
ConfigResult readCalibrationRecording(const std::string& file, int rows, int cols, CalibrationRecording& out);

enum class CalibrationModel : uint8_t { Shared = 0, Border = 1, PerTaxel = 2 };
const char* toString(CalibrationModel m);
/// "shared" | "border" | "per_taxel" -> model; false if unknown.
bool parseCalibrationModel(const std::string& s, CalibrationModel& out);

struct CalibrationFitOptions {
  CalibrationModel model = CalibrationModel::Border;
  int degree = 3;                  ///< polynomial degree, 1..3 (c0 = 0 always)
  double unloaded_max_n = 0.05;    ///< N: |f_ref| <= this is an unloaded frame (tare); > 0
  double noise_sigmas = 4.0;       ///< a tared count is signal above this many noise sigmas, > 0
  double min_noise_counts = 1.0;   ///< floor of a taxel's noise sigma (counts), > 0
  double loaded_sigmas = 20.0;     ///< dead-taxel test: a neighbour is loaded above this many sigmas
  double ridge = 1e-3;             ///< per_taxel: weight of the prior relative to the mean excitation, >= 0
  double distinct_load_resolution = 0.01;  ///< loads within this fraction of the largest are one load, (0, 0.5)
  bool nonnegative = true;         ///< c1, c2, c3 >= 0 (monotone convex curve)
  double max_condition = 1e8;      ///< column-scaled design condition above this: ill-posed (error)
};

struct CalibrationFit {
  CalibrationParams params;        ///< the base parameters with the fitted coefficients
  CalibrationModel model = CalibrationModel::Border;
  int degree = 3;
  // Frames.
  std::size_t frames_total = 0;
  std::size_t frames_unloaded = 0;  ///< used for the tare and the noise
  std::size_t frames_loaded = 0;
  std::size_t frames_saturated = 0;  ///< loaded frames dropped: a raw count >= full_scale
  std::size_t frames_silent = 0;     ///< loaded frames dropped: no taxel above its noise
  std::size_t frames_used = 0;       ///< loaded frames in the fit
  int distinct_loads = 0;
  double load_max = 0.0;             ///< N: the largest f_ref used
  // Per taxel (rows*cols).
  std::vector<double> tare;          ///< counts: mean over the unloaded frames
  std::vector<double> noise;         ///< counts: 1-sigma (floored at min_noise_counts)
  std::vector<double> count_max;     ///< largest tared count used (0 if never above its noise)
  std::vector<double> count_min;     ///< smallest tared count above its noise used (0 if never)
  std::vector<int> taxel_frames;     ///< frames in which the taxel was above its noise
  std::vector<double> taxel_residual;  ///< N: RMS of the attributed residual (NaN if never loaded)
  std::vector<int> at_prior;         ///< per_taxel: taxels never loaded (they keep the prior)
  // Per used frame.
  std::vector<double> reference;     ///< f_ref (N)
  std::vector<double> predicted;     ///< sum of the fitted polynomials (N)
  std::vector<long> frame_line;      ///< its line in the recording
  // Summary.
  double rms_n = 0.0;                ///< RMS of predicted - reference (N)
  double rms_pct = 0.0;              ///< rms_n in % of load_max
  double max_abs_n = 0.0;            ///< largest |predicted - reference| (N)
  long max_abs_line = 0;             ///< its line
  double sigma_n = 0.0;              ///< residual sigma: sqrt(RSS / (frames - unknowns)) (N)
  double condition = 0.0;            ///< of the column-scaled design, no ridge (inf if rank deficient)
  double condition_regularised = 0.0;  ///< of the column-scaled normal matrix with the ridge
  int unknowns = 0;
  int constrained = 0;               ///< coefficients held at 0 by the c_k >= 0 constraint
  std::vector<std::string> notes;    ///< what was left out and why

  /// The fitted force of taxel i at `counts` tared counts (N, unclamped).
  double force(int taxel, double counts) const;
  /// Standard error of that value (N): sqrt(phi^T C phi), C = sigma_n^2 x the
  /// inverse of the (regularised) normal matrix.
  double curveStdError(int taxel, double counts) const;

  // Internal: the unknowns (normalised) and their covariance.
  std::vector<int> param_index;      ///< per taxel: index of its c1 among the unknowns
  std::vector<double> covariance;    ///< unknowns x unknowns, normalised units, row-major
};

/// Validates the options (errors name the option and its range).
ConfigResult checkCalibrationFitOptions(const CalibrationFitOptions& opt);

/// Fits the recording. `base` supplies rows/cols, full_scale, max_tare and
/// noise_counts (kept in the result). On failure `out` is unspecified.
ConfigResult fitCalibration(const CalibrationRecording& rec, const CalibrationParams& base,
                            const CalibrationFitOptions& opt, CalibrationFit& out);

/// The `calibration:` block (YAML text, keys of params_io.hpp) for `p`;
/// `comment` lines (without '#') go above the keys. per-taxel tables are
/// written when p.taxels is not empty, border_coeffs when p.use_border.
std::string calibrationYaml(const CalibrationParams& p, const std::vector<std::string>& comment);

/// The parameter file `params_text` (the contents of e.g. wts0614.yaml; empty:
/// none) with its top-level `calibration:` block replaced by `block` (appended
/// if it has none). Everything else (features, comments) is kept as written.
std::string replaceCalibrationBlock(const std::string& params_text, const std::string& block);

}  // namespace tactile
