#include "tactile_features/sensor_stage.hpp"

namespace tactile {

ConfigResult SensorStage::configure(const FeatureParams& fp, const CalibrationParams& cp) {
  ConfigResult r = calibration_.configure(cp);
  if (!r) return r;
  FeatureParams f = fp;
  f.taxel_noise = calibration_.noiseForce(fp.contact_threshold);
  if (!(r = extractor_.configure(f))) return r;
  if (cp.rows != fp.rows || cp.cols != fp.cols)
    return ConfigResult::failure("calibration is " + std::to_string(cp.rows) + " x " + std::to_string(cp.cols) +
                                 " taxels but features.rows x cols is " + std::to_string(fp.rows) + " x " +
                                 std::to_string(fp.cols) + ": must match");
  tare_requested_ = false;
  tare_rejected_ = false;
  return ConfigResult::success();
}

void SensorStage::reset() {
  extractor_.reset();
  tare_requested_ = false;
  tare_rejected_ = false;
}

FeatureStatus SensorStage::step(const RawTactileFrame& raw, TactileFrame& frame, ContactFeatures& out,
                                bool& frame_valid) {
  if (tare_requested_) {
    const CalibrationStatus ts = calibration_.tare(raw);
    if (ts == CalibrationStatus::Ok) tare_rejected_ = false;
    if (ts == CalibrationStatus::TareRejected) tare_rejected_ = true;
    tare_requested_ = false;
  }
  const CalibrationStatus cs = calibration_.step(raw, frame);
  frame_valid = cs == CalibrationStatus::Ok || cs == CalibrationStatus::Saturated;
  if (frame_valid) {
    extractor_.step(frame, out);
    // A rejected tare outranks Ok/NoContact/Saturated (all usable); invalid stays invalid.
    if (tare_rejected_ && usable(out.status)) out.status = FeatureStatus::TareRejected;
    return out.status;
  }
  // Wrong frame size (or not configured): report it, never stale features.
  out = ContactFeatures();
  out.time_s = raw.time_s;
  out.seq = raw.seq;
  out.status = cs == CalibrationStatus::BadDimensions ? FeatureStatus::BadDimensions : FeatureStatus::NotConfigured;
  return out.status;
}

FeatureStatus SensorStage::stepCalibrated(const TactileFrame& frame, ContactFeatures& out) {
  return extractor_.step(frame, out);
}

}  // namespace tactile
