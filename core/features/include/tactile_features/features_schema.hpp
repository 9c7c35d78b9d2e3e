// The declared `features:` block of a sensor's parameter file
// (tactile_types/schema.hpp): each key with its member, unit, range and
// meaning. The reader (params_io.cpp), FeatureExtractor::configure's range
// checks and the key table of docs/formats.md (`tactile_sim schema sensor`)
// come from it.
#pragma once

#include <string>

#include "tactile_features/extractor.hpp"
#include "tactile_types/schema.hpp"

namespace tactile {

/// features: every key but `threshold` (a number or "otsu": params_io.cpp).
const schema::Block<FeatureParams>& featuresSchema();

/// The key table of the sensor's blocks (Markdown): what `tactile_sim schema
/// sensor` prints and docs/formats.md shows.
std::string sensorSchemaMarkdown();

}  // namespace tactile
