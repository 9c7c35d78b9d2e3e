// The declared `features:` and `calibration:` blocks of a sensor's parameter
// file (tactile_types/schema.hpp): each key with its member, unit, range and
// meaning. The readers (params_io.cpp), the range checks of
// FeatureExtractor::configure and Calibration::configure and the key tables
// of docs/formats.md (`tactile_sim schema sensor`) come from them.
#pragma once

#include <string>

#include "tactile_features/calibration.hpp"
#include "tactile_features/extractor.hpp"
#include "tactile_types/schema.hpp"

namespace tactile {

/// features: every key but `threshold` (a number or "otsu": params_io.cpp).
const schema::Block<FeatureParams>& featuresSchema();

/// calibration:'s whole-number and scalar keys as the file gives them
/// (CalibrationParams holds the counts as uint16_t); the coefficient lists
/// are read by params_io.cpp.
struct CalibrationFile {
  int full_scale = CalibrationParams{}.full_scale;
  int max_tare = CalibrationParams{}.max_tare;
  double noise_counts = CalibrationParams{}.noise_counts;
  static CalibrationFile of(const CalibrationParams& p) {
    return CalibrationFile{p.full_scale, p.max_tare, p.noise_counts};
  }
};
const schema::Block<CalibrationFile>& calibrationSchema();

/// The key table of the sensor's blocks (Markdown): what `tactile_sim schema
/// sensor` prints and docs/formats.md shows.
std::string sensorSchemaMarkdown();

}  // namespace tactile
