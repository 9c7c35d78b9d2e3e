// The declared blocks of a scene (tactile_types/schema.hpp): `sensor` (the
// simulated pad, PadParams), `arm` (ArmParams) and, under `effects`, the
// world's physics and timing effects (WorldParams) and the sensor's
// (SensorEffects). The scene reader (core/sim/runner/src/scene.cpp), the
// range checks of PadSensor::configure, LwrArm::configure, World::configure
// and TaxelResponse::configure and the key tables
// of docs/formats.md (`tactile_sim schema scene`) come from these.
#pragma once

#include <string>

#include "tactile_sim_lwr/lwr_arm.hpp"
#include "tactile_sim_lwr/pad_sensor.hpp"
#include "tactile_sim_lwr/world.hpp"
#include "tactile_types/schema.hpp"

namespace tactile {
namespace sim {

const schema::Block<PadParams>& sensorSchema();
/// The arm's start and impedance; q_init_deg (degrees, stored in radians in
/// q_init) is read by the scene reader.
const schema::Block<ArmParams>& armSchema();
/// `effects`' physics and timing keys; the sensor's effects and the wrench
/// error share the block (sensor_faults_io.hpp, scene.hpp).
const schema::Block<WorldParams>& worldEffectsSchema();

/// `effects`' sensor keys (TaxelResponse); dead_taxels (a count or a list)
/// is read by the scene reader.
const schema::Block<SensorEffects>& sensorEffectsSchema();

/// One entry of a scene's `objects:` (ObjectParams); its keys depend on
/// `type` ("table" is read as "plane"). vertices (bar, bent_bar) and a
/// tray's fidelity are read by the scene reader; the vertices' count and
/// spacing, a plane's normal and one tray per scene are ObjectSet's checks.
const schema::Block<ObjectParams>& objectSchema();

/// The key tables of the declared scene blocks (Markdown).
std::string sceneSchemaMarkdown();

}  // namespace sim
}  // namespace tactile
