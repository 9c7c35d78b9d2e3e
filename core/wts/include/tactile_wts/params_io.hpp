// YAML -> WtsParams. Keys mirror the struct fields (absent keys keep their value):
//
//   wts:
//     device: /dev/ttyACM0
//     rows: 6                 cols: 14
//     transpose: true         flip_rows: false      flip_cols: false   # protocol.hpp, CellMap
//     periodic_ms: 10         rle: false
//     command_timeout_ms: 300 reconnect_period_s: 0.5  restart_after_s: 1.0
//     check_matrix_info: true
//
// Errors name the file, the key path and the valid range, e.g.
//   "params.yaml: wts.periodic_ms = 5000: must be in [0, 1000] (0 = single-frame polling)".
#pragma once

#include <yaml-cpp/yaml.h>

#include "tactile_config/yaml_params.hpp"
#include "tactile_wts/driver.hpp"

namespace tactile {
namespace wts {

ConfigResult loadWtsParams(const YAML::Node& node, const config::Where& where, WtsParams& p);

}  // namespace wts
}  // namespace tactile
