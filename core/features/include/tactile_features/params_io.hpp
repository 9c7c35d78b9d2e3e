// YAML <-> FeatureParams / CalibrationParams. Keys mirror the struct fields;
// angles in parameter files are in degrees where the key says so (`_deg`).
//
//   features:
//     rows: 6            cols: 14          pitch: 0.0034      c_z: 0.000555
//     threshold: 0.2     # N, or the string "otsu"
//     contact_threshold: 0.2
//     edge_ratio: 5.0    edge_ratio_exit: 4.0
//     alpha_hysteresis_deg: 10
//   calibration:
//     full_scale: 4095
//     coeffs: [0, 0.002, 0, 0]          # N = c0 + c1 n + c2 n^2 + c3 n^3
//     border_coeffs: [0, 0.0015, 0, 0]  # optional
#pragma once

#include <yaml-cpp/yaml.h>

#include "tactile_config/yaml_params.hpp"
#include "tactile_features/calibration.hpp"
#include "tactile_features/extractor.hpp"

namespace tactile {

/// Reads a `features:` mapping into `p` (absent keys keep their value) and
/// validates it by configuring a scratch extractor.
ConfigResult loadFeatureParams(const YAML::Node& node, const config::Where& where, FeatureParams& p);

/// Reads a `calibration:` mapping; rows/cols are taken from `rows`/`cols`.
ConfigResult loadCalibrationParams(const YAML::Node& node, const config::Where& where, int rows, int cols,
                                   CalibrationParams& p);

/// A sensor's parameter file (a map with `features:` and `calibration:`)
/// into `fp` and `cp`, both from their defaults; errors name the file and key.
ConfigResult loadSensorParamFile(const std::string& file, FeatureParams& fp, CalibrationParams& cp);

}  // namespace tactile
