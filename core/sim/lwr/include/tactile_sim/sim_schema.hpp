// The declared blocks of a scene (tactile_types/schema.hpp): `sensor` (the
// simulated pad, PadParams) and the world's physics and timing effects under
// `effects` (WorldParams). The scene reader (core/sim/runner/src/scene.cpp), the
// range checks of PadSensor::configure and World::configure and the key tables
// of docs/formats.md (`tactile_sim schema scene`) come from these.
#pragma once

#include <string>

#include "tactile_sim/pad_sensor.hpp"
#include "tactile_sim/world.hpp"
#include "tactile_types/schema.hpp"

namespace tactile {
namespace sim {

const schema::Block<PadParams>& sensorSchema();
/// `effects`' physics and timing keys; the sensor's effects and the wrench
/// error share the block (sensor_faults_io.hpp, scene.hpp).
const schema::Block<WorldParams>& worldEffectsSchema();

/// The key tables of the declared scene blocks (Markdown).
std::string sceneSchemaMarkdown();

}  // namespace sim
}  // namespace tactile
