// The declared top level of a scene file (tactile_types/schema.hpp): each
// key with its member, unit, range and meaning. Keys that name a file or
// hold a block of their own (program, features_file, sensor, arm, objects,
// effects, faults, metrics.criteria) are declared for their place and their
// table row and read by scene.cpp; `sensor` and `effects` are declared in
// sim_schema.hpp. The reader's unknown-key errors, validateScene's range
// checks and docs/formats.md's table (`tactile_sim schema scene`) come from
// this declaration.
#pragma once

#include <string>

#include "tactile_sim/scene.hpp"
#include "tactile_types/schema.hpp"

namespace tactile {
namespace sim {

const schema::Block<Scene>& sceneSchema();

/// The key tables of a scene (Markdown): its top level, then `sensor` and
/// `effects` (sim_schema.hpp).
std::string sceneFileSchemaMarkdown();

}  // namespace sim
}  // namespace tactile
