// The simulated WTS0614's electronics: true taxel forces (N) -> raw 12-bit
// counts, by inverting the calibration the real sensor is read with (App. A,
// Fig. A.15: the per-taxel polynomial f(n) = c0 + c1 n + c2 n^2 + c3 n^3 of
// components/features/params/wts0614.yaml's `calibration:` block, border and
// per-taxel coefficients included). So tactile::Calibration configured from
// the same file maps the counts back to the forces (up to noise and
// quantisation), exactly as on the robot.
//
// Per taxel: n = p^-1(f) (Newton, monotone: c1 > 0, c2, c3 >= 0), Gaussian
// noise (noise_counts, 1 sigma, seeded), rounding (12-bit quantisation),
// clamping to [0, full_scale] (saturation), and 0 below the device's firing
// threshold (counts of `threshold` N). A taxel more than 10 sigma below its
// threshold reads 0 without a noise draw (deterministic for a seed).
//
// RTT-free; respond() does not allocate or throw.
#pragma once

#include <array>
#include <cstdint>
#include <random>

#include "tactile_features/calibration.hpp"
#include "tactile_types/config_result.hpp"
#include "tactile_types/types.hpp"

namespace tactile {
namespace sim {

struct TaxelResponseParams {
  CalibrationParams calibration;  ///< the sensor's calibration (the file's `calibration:` block)
  double noise_counts = 6.0;      ///< 1 sigma (counts), [0, 1000]
  double threshold = 0.2;         ///< N: firing threshold, >= 0
  uint64_t seed = 1;              ///< noise seed
};

class TaxelResponse {
 public:
  /// Validates (errors name the key and the range) and tabulates thresholds.
  ConfigResult configure(const TaxelResponseParams& params);
  const TaxelResponseParams& params() const { return params_; }

  /// Noise-free inverse of taxel i's calibration: force (N) -> counts (real, >= 0).
  double countsFor(int i, double force) const;
  /// Taxel i's calibration polynomial at `counts` (N).
  double forceFor(int i, double counts) const;

  /// Forces (the frame's own rows x cols must match the calibration) -> raw
  /// frame stamped `t`. Returns the largest count. Allocation-free.
  int respond(const TactileFrame& forces, double t, RawTactileFrame& raw);

  void reseed(uint64_t seed) {
    rng_.seed(seed);
    normal_.reset();
  }

 private:
  TaxelResponseParams params_;
  int n_ = 0;
  std::array<std::array<double, 4>, kMaxTaxels> coeffs_{};
  std::array<double, kMaxTaxels> threshold_counts_{};
  std::array<double, kMaxTaxels> silent_force_{};  ///< below this force a taxel reads 0 (no draw)
  std::mt19937_64 rng_{1};
  std::normal_distribution<double> normal_{0.0, 1.0};
};

}  // namespace sim
}  // namespace tactile
