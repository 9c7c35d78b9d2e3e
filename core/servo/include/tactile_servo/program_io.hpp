// Phase programs (YAML) -> ServoParams. Every error names the file, the phase
// and the field, e.g.
//   "programs/x.yaml: phases.align.kp_per_s.wy = -1: must be >= 0 (1/s)".
// Every gain, limit and delay is per second / in seconds (independent of the
// servo rate). The per-cycle keys of earlier programs (kp, ki, integral_limit,
// u_max, max_trans_step, max_rot_step_deg, transitions' cycles) are rejected
// with an error naming the key and its replacement.
//
// Format (all keys optional unless marked; see programs/*.yaml for examples):
//
//   base: other.yaml                     # optional: this file is an overlay of that program
//                                        # (path relative to this file; see "Overlays" below)
//   controller, safety, watchdogs, force_estimate, speed_law, slope_feedforward:
//                                        # blocks declared once, each key with its unit, range,
//                                        # default and meaning (servo_schema.hpp; the tables of
//                                        # docs/formats.md, "Keys of the program's blocks")
//   phase_defaults: {kp_per_s: .., ki_per_s2: .., integral_limit_per_s: .., u_max_per_s: ..,   # per-axis maps
//                    max_duration_s: 0}  # default of every non-terminal phase (0 = no limit)
//   phases:                              # required, a list
//     - name: NAME                       # required
//       s_d: {cop_x: 0, cop_y: 0, d_z: 0.0033, dzmp_x: 0, dzmp_y: 0, alpha_z: 0}
//            # rows of Δs; `force: 6` (N) sets the d_z row to c_z * 6; or a list of 6
//       jacobian: touch                  # or {beta: 0|1} or {point: 6x6, edge: 6x6} or {matrix: 6x6}
//       P: {x: 0, y: 1, z: 1, wx: 0, wy: 1, wz: 1, com: 0}   # gammas of Eq. 10, or a 6x6 list
//       kp_per_s: {x: .., y: .., z: .., wx: .., wy: .., wz: ..}   # 1/s (or a list of 6)
//       ki_per_s2: {...}                 # 1/s^2
//       integral_limit_per_s: {...}      # |K_I ∫Δ| per axis (m/s or rad/s)
//       u_max_per_s: {...}               # PI rate limit per axis (m/s or rad/s)
//       feedforward: {vx: 0, vy: 0, vz: 0.01, wx: 0, wy: 0, wz: 0}   # {s}, m/s and rad/s
//       requires_contact: true
//       reset_integrator: true
//       terminal: false
//       max_duration_s: 30               # longer in this phase -> status phase_timeout (fatal)
//       transitions:
//         - {on: contact | edge | point | multiple | contact_lost, to: NAME, for_s: 0}   # s the condition holds
//         - {on: aligned, to: NAME, for_s: 0.2, tolerance: {alpha_z: 0.02, dzmp_y: 0.0005, ...}}
//         - {on: force_above, to: NAME, force_n: 20}
//         - {on: timeout, to: NAME, timeout_s: 30}
//         - {on: wrist_wound | wrist_unwound, to: NAME, angle_deg: 150}   # the yaw about z_s (phase_program.hpp)
//         - {on: loop_closed, to: NAME, radius_m: 0.002, leave_m: 0.03}
//         - {on: joint_margin, to: NAME, angle_deg: 3}   # a measured joint within 3 deg of its limit
//
// Overlays: a file with `base: B` is B with the file's own keys merged over it,
// then read as above (errors name the overlay file):
//   * a mapping merges key by key, recursively;
//   * a list whose elements are all mappings with a `name` (phases) merges
//     element by element by name, in the base's order;
//   * a scalar, any other list (transitions, matrices, 6-lists) or a value of
//     another kind replaces the base's;
//   * `~` (null) removes the base's key (one the base lacks is an error);
//   * a key the base does not have is added: the shared defaults
//     (programs/common/lwr_wts0614.yaml) leave out what each program sets,
//     and a typo is still an error, the reader's (every block, phase and
//     vector rejects a key it does not know);
//   * a phase name that the base does not have is an error: an overlay
//     changes its base's phases;
//   * except `add_phases`: a list of whole phases appended after the base's,
//     each with a name the base's phases do not have (a phase no transition
//     reaches is an error of the merged program).
// B may itself have a base (a chain); a cycle, a missing base file and a key
// the base lacks are errors naming the file and the key. Configuration time only.
#pragma once

#include <string>

#include "tactile_servo/servo.hpp"

namespace YAML {
class Node;
}

namespace tactile {

/// Load a phase program from a file; validates it fully (a scratch
/// TactileServo is configured with it), so a success here configures.
ConfigResult loadServoProgram(const std::string& file, ServoParams& out);

/// Same from an already parsed YAML document; `file` is used in messages and
/// a `base:` in it is relative to the directory of `file`.
ConfigResult loadServoProgram(const YAML::Node& root, const std::string& file, ServoParams& out);

/// A program file as one document, its `base:` chain merged (see "Overlays"),
/// without the `base` key: what loadServoProgram reads, for tools that read
/// program keys themselves.
ConfigResult loadProgramDocument(const std::string& file, YAML::Node& out);

/// Same for a document already read from `file` (`root` is not changed; `out`
/// is `root` itself when it has no `base`).
ConfigResult resolveProgramBase(const YAML::Node& root, const std::string& file, YAML::Node& out);

}  // namespace tactile
