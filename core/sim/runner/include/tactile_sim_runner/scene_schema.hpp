// The declared top level of a scene file (tactile_types/schema.hpp): each
// key with its member, unit, range and meaning. Keys that name a file or
// hold a block of their own (features_file, sensor, arm, objects,
// effects, faults, metrics.criteria) are declared for their place and their
// table row and read by scene.cpp; `sensor`, `arm` and `effects` are
// declared in sim_schema.hpp, `initial_flange` below. The reader's unknown-key errors, validateScene's range
// checks and docs/formats.md's table (`tactile_sim schema scene`) come from
// this declaration.
#pragma once

#include <array>
#include <string>

#include "tactile_sim_runner/scene.hpp"
#include "tactile_types/schema.hpp"

namespace tactile {
namespace sim {

const schema::Block<Scene>& sceneSchema();

/// `initial_flange`, as the file gives it; the reader turns it into the
/// world's initial flange pose ({g}T{e}, reached by IK at the start).
struct InitialFlange {
  std::array<double, 3> xyz{0.0, 0.0, 0.0};      ///< m in {g}
  std::array<double, 3> rpy_deg{0.0, 0.0, 0.0};  ///< deg: roll, pitch, yaw (KDL::Rotation::RPY)
};
const schema::Block<InitialFlange>& initialFlangeSchema();

/// `effects.wrench_error`: the arm's estimated wrench's error (EstimatedWrench).
const schema::Block<WrenchErrorParams>& wrenchErrorSchema();

/// The key tables of a scene (Markdown): its top level, `initial_flange`,
/// then `objects[]`, `sensor`, `arm` and `effects` (sim_schema.hpp), `effects.wrench_error`.
std::string sceneFileSchemaMarkdown();

}  // namespace sim
}  // namespace tactile
