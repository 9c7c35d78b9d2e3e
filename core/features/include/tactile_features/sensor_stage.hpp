// The sensor stage of the loop: raw 12-bit counts -> calibrated frame (App. A,
// tactile::Calibration) -> contact features (Sec. 3, App. B,
// tactile::FeatureExtractor). The one implementation used by
// tactile::FeatureComponent (RTT) and by the headless runner (tactile_sim):
// they only move data to and from it.
//
// RTT-free, allocation-free, exception-free per step; configuration allocates.
//
// configure() sets features.taxel_noise from the calibration: noise_counts
// times the slope dF/dn at the firing threshold (features.contact_threshold),
// the noise figure of the alpha_z test and of the sub-threshold estimate
// (extractor.hpp). A rejected tare request (calibration.max_tare) keeps the
// previous tare and is reported as FeatureStatus::TareRejected on every
// frame with usable features until a tare succeeds or reset().
#pragma once

#include "tactile_features/calibration.hpp"
#include "tactile_features/extractor.hpp"
#include "tactile_types/config_result.hpp"
#include "tactile_types/types.hpp"

namespace tactile {

class SensorStage {
 public:
  ConfigResult configure(const FeatureParams& features, const CalibrationParams& calibration);

  /// Forget the extractor's history (start of a run) and any pending tare.
  void reset();
  /// The next raw frame becomes the tare offset of every taxel (App. A).
  void requestTare() { tare_requested_ = true; }

  /// One raw frame: calibration, then features. `frame` is written when the
  /// calibration succeeded (`frame_valid`); on a wrong frame size (or before
  /// configure) `out` carries the status and no stale numbers.
  FeatureStatus step(const RawTactileFrame& raw, TactileFrame& frame, ContactFeatures& out, bool& frame_valid);
  /// An already calibrated frame -> features.
  FeatureStatus stepCalibrated(const TactileFrame& frame, ContactFeatures& out);

  const Calibration& calibration() const { return calibration_; }
  const FeatureExtractor& extractor() const { return extractor_; }

 private:
  Calibration calibration_;
  FeatureExtractor extractor_;
  bool tare_requested_ = false;
  bool tare_rejected_ = false;
};

}  // namespace tactile
