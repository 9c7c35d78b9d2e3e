// Reading one fault of the simulated sensors' schedule (tactile_sim_faults/sensor_faults.hpp)
// from YAML: an entry of a scene's `faults:` list (tactile_sim_runner/scene.hpp,
// docs/formats.md "Faults") or of `wts_sim --fault`. Errors name the file
// and the entry's key (`faults[2].rows: ...`); the ranges are checked by
// SensorFaultSchedule::configure(). Not on a per-cycle path.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

#include "tactile_config/yaml_params.hpp"
#include "tactile_sim_faults/sensor_faults.hpp"
#include "tactile_types/config_result.hpp"

namespace tactile {
namespace sim {

/// One fault from a YAML map {kind: .., start_s: .., duration_s: .., and the
/// kind's own keys}; unknown keys, kinds and unparsable values fail. `nan`
/// is refused (the RTT sensor's `fault` property only).
ConfigResult readFaultSpec(const YAML::Node& node, const config::Where& where, FaultSpec& out);

}  // namespace sim
}  // namespace tactile
