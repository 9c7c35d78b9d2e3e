// The declared blocks of a servo phase program (tactile_types/schema.hpp):
// each key of `controller` (but its matrices), `safety`, `watchdogs`,
// `force_estimate`, `speed_law`, `slope_feedforward`, `phase_defaults`, a
// phase and a transition, with its member, unit, range and meaning. The reader
// (program_io.cpp), the range checks of the cores' configure() and the key
// tables of docs/formats.md (`tactile_sim schema`) all come from these.
#pragma once

#include "tactile_servo/servo_params.hpp"
#include "tactile_types/schema.hpp"

namespace tactile {

/// controller: the scalar keys; motion_sign and sensor_mount (a 6-vector and
/// a frame) are read by program_io.cpp beside them.
const schema::Block<ServoParams>& controllerSchema();
const schema::Block<SafetyParams>& safetySchema();
const schema::Block<WatchdogParams>& watchdogSchema();
const schema::Block<ForceEstimateParams>& forceEstimateSchema();
/// speed_law: the law's own keys (SpeedLawParams, speed_law.hpp) ...
const schema::Block<SpeedLawParams>& speedLawSchema();
/// ... and the servo's (where it acts, its filters: SpeedLawConfig), one block in the file.
const schema::Block<SpeedLawConfig>& speedLawServoSchema();
const schema::Block<SlopeFeedforwardConfig>& slopeFeedforwardSchema();
/// phase_defaults: the gains and time limit of phaseSchema(), for every phase.
const schema::Block<PhaseParams>& phaseDefaultsSchema();
/// A phase: its scalars, gains and flags; s_d, jacobian, P and transitions
/// (Custom fields) are read by program_io.cpp.
const schema::Block<PhaseParams>& phaseSchema();
/// A transition: its keys depend on its event (`on`, the block's selector);
/// tolerance (Custom) is read by program_io.cpp.
const schema::Block<TransitionParams>& transitionSchema();
/// The events' names in a file, in TransitionEvent's order ("contact|edge|..."):
/// toString(TransitionEvent)'s, joined once.
const char* transitionEventNames();

}  // namespace tactile

#include <string>

namespace tactile {

/// The key tables of the declared program blocks (Markdown, one section per
/// block, the defaults of a default-constructed ServoParams): what
/// `tactile_sim schema` prints and docs/formats.md shows.
std::string programSchemaMarkdown();

}  // namespace tactile
