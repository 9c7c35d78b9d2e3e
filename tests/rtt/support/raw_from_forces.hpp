// Test helper: taxel forces -> raw counts through the inverse of a configured
// tactile::Calibration (App. A polynomial, border taxels included), so that a
// synthetic contact calibrates back to its forces with ANY parameter file.
// Integer bisection on the real calibration code (all taxels at once: 12
// calibrations of the whole frame, then the nearer of the two bracketing
// counts). A force beyond the full-scale value gives full_scale (saturated).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "tactile_features/calibration.hpp"
#include "tactile_types/types.hpp"

namespace tactile {
namespace test {

inline void rawFromForces(const Calibration& cal, const TactileFrame& forces, RawTactileFrame& raw) {
  const int n = forces.size();
  const int fs = cal.params().full_scale;
  std::array<int, kMaxTaxels> lo{}, hi{};
  raw.rows = forces.rows;
  raw.cols = forces.cols;
  TactileFrame f;
  for (int i = 0; i < n; ++i) {
    lo[static_cast<std::size_t>(i)] = 0;
    hi[static_cast<std::size_t>(i)] = fs;
  }
  // invariant: f(lo) <= F or lo == 0; f(hi) > F or hi == full_scale
  for (int it = 0; it < 13; ++it) {
    for (int i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      raw.counts[k] = static_cast<uint16_t>((lo[k] + hi[k]) / 2);
    }
    cal.step(raw, f);
    for (int i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      if (f.force[k] <= forces.force[k]) lo[k] = raw.counts[k];
      else hi[k] = raw.counts[k];
    }
  }
  TactileFrame f_lo, f_hi;
  for (int i = 0; i < n; ++i) raw.counts[static_cast<std::size_t>(i)] = static_cast<uint16_t>(lo[static_cast<std::size_t>(i)]);
  cal.step(raw, f_lo);
  for (int i = 0; i < n; ++i) raw.counts[static_cast<std::size_t>(i)] = static_cast<uint16_t>(hi[static_cast<std::size_t>(i)]);
  cal.step(raw, f_hi);
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const double F = forces.force[k];
    const bool use_hi = std::fabs(f_hi.force[k] - F) < std::fabs(f_lo.force[k] - F);
    raw.counts[k] = static_cast<uint16_t>(use_hi ? hi[k] : lo[k]);
  }
}

}  // namespace test
}  // namespace tactile
