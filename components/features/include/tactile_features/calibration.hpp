// Raw 12-bit counts -> newtons, per taxel (paper App. A, Fig. A.15).
//
// Per taxel i:   n_i = max(0, raw_i - tare_i)
//                f_i = c0_i + c1_i*n_i + c2_i*n_i^2 + c3_i*n_i^3   (N), clamped >= 0
// A linear calibration is c = {0, k, 0, 0}. Border taxels are stiffer (App. A:
// "the rubber at the corners is not as flexible as at the center"): give them
// their own coefficients with `border` or per-taxel with `taxels`.
// A taxel whose raw value is >= full_scale is counted as saturated.
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
};

enum class CalibrationStatus : uint8_t { Ok = 0, Saturated = 1, BadDimensions = 10, NotConfigured = 11 };

class Calibration {
 public:
  ConfigResult configure(const CalibrationParams& params);

  /// Raw counts -> forces. Allocation-free; never throws.
  CalibrationStatus step(const RawTactileFrame& raw, TactileFrame& out) const;

  /// Store the current raw frame as tare offsets (the WTS "tare" command does
  /// the same on the device). Not for the 1 kHz path but allocation-free.
  CalibrationStatus tare(const RawTactileFrame& raw);
  void clearTare();

  const CalibrationParams& params() const { return params_; }

 private:
  bool configured_ = false;
  CalibrationParams params_;
  std::array<std::array<double, 4>, kMaxTaxels> coeffs_{};
  std::array<uint16_t, kMaxTaxels> tare_{};
};

}  // namespace tactile
