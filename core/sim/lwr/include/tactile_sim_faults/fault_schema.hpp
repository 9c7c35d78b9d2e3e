// The declared entry of a scene's `faults:` (tactile_types/schema.hpp): the
// reader (readFaultSpec, sensor_faults_io.hpp) with its unknown-key and
// other-kind errors, SensorFaultSchedule's range checks and docs/formats.md's
// table (`tactile_sim schema faults`) come from it.
#pragma once

#include "tactile_sim_faults/sensor_faults.hpp"
#include "tactile_types/schema.hpp"

namespace tactile {
namespace sim {

/// One scheduled fault (FaultSpec); its keys depend on `kind`. rows, cols,
/// counts and force_n are read by readFaultSpec and checked by
/// SensorFaultSchedule (within the pad, within its full scale, one of
/// counts and force_n).
const schema::Block<FaultSpec>& faultSchema();

}  // namespace sim
}  // namespace tactile
