// Raw 12-bit counts -> newtons, per taxel (paper App. A, Fig. A.15).
//
// Per taxel i:   n_i = max(0, raw_i - tare_i)
//                f_i = c0_i + c1_i*n_i + c2_i*n_i^2 + c3_i*n_i^3   (N), clamped >= 0
// A linear calibration is c = {0, k, 0, 0}. Border taxels are stiffer (App. A:
// "the rubber at the corners is not as flexible as at the center"): give them
// their own coefficients with `border` or per-taxel with `taxels`.
// A taxel whose raw value is >= full_scale is counted as saturated.
// Counts below the tare read 0 (never negative). A tare request with any
// offset above max_tare is rejected (status TareRejected) and the previous
// tare is kept: the WTS's no-load offsets are a few counts, an offset that
// large is a load (or a fault) and would take that part of the range away
// for good -- at full scale, all of it.
// noise_counts is the sensor's 1-sigma count noise (App. A); noiseForce()
// turns it into newtons through the polynomial's slope dF/dn.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "tactile_types/config_result.hpp"
#include "tactile_types/types.hpp"

namespace tactile {

struct CalibrationParams {
  int rows = kDefaultRows;
  int cols = kDefaultCols;
  uint16_t full_scale = 4095;  ///< raw count at which a taxel saturates
  /// Polynomial used for every taxel unless overridden (N per count^k).
  std::array<double, 4> coeffs{0.0, 2.0 / 1000.0, 0.0, 0.0};
  /// If set (use_border = true), applies to taxels on the outer ring.
  bool use_border = false;
  std::array<double, 4> border_coeffs{0.0, 2.0 / 1000.0, 0.0, 0.0};
  /// Optional per-taxel table (rows*cols entries, row-major); overrides both.
  std::vector<std::array<double, 4>> taxels;
  /// Largest accepted tare offset (counts), in [0, full_scale]. Default 10 %
  /// of the 12-bit range.
  uint16_t max_tare = 409;
  /// The sensor's count noise, 1 sigma (counts), >= 0.
  double noise_counts = 0.0;
};

enum class CalibrationStatus : uint8_t {
  Ok = 0,
  Saturated = 1,
  TareRejected = 2,  ///< tare(): an offset above max_tare; the previous tare is kept
  BadDimensions = 10,
  NotConfigured = 11
};

class Calibration {
 public:
  ConfigResult configure(const CalibrationParams& params);

  /// Raw counts -> forces. Allocation-free; never throws.
  CalibrationStatus step(const RawTactileFrame& raw, TactileFrame& out) const;

  /// Store the current raw frame as tare offsets (the WTS "tare" command does
  /// the same on the device). Not for the 1 kHz path but allocation-free.
  CalibrationStatus tare(const RawTactileFrame& raw);
  void clearTare();

  /// 1-sigma noise in newtons of a taxel reading `force` (N): noise_counts
  /// times the largest slope dF/dn over the taxels' polynomials at the count
  /// that reads `force`. Not for the per-frame path (Newton per taxel).
  double noiseForce(double force) const;

  const CalibrationParams& params() const { return params_; }

 private:
  bool configured_ = false;
  CalibrationParams params_;
  std::array<std::array<double, 4>, kMaxTaxels> coeffs_{};
  std::array<uint16_t, kMaxTaxels> tare_{};
};

}  // namespace tactile
