// Phase programs (YAML) -> ServoParams. Every error names the file, the phase
// and the field, e.g.
//   "programs/x.yaml: phases.align.kp.wy = -1: must be >= 0 (per cycle)".
//
// Format (all keys optional unless marked; see programs/*.yaml for examples):
//
//   controller:
//     mode: proposed | baseline | no_rotation   # Eq. 8 | Li et al. (RSS 2013, liJinv) | ablation (noRotationJinv)
//     pose_update: integrated | measured # Eq. 15 | Eq. 12
//     c_z: 0.000555556                   # m/N (Eq. 2), converts `force` targets to d_z
//     motion_sign: {x: -1, y: -1, z: 1, wx: 1, wy: -1, wz: -1}   # or a list of 6
//     sensor_mount: {xyz: [0, 0, 0.03], rpy_deg: [0, 0, 0]}      # {e}T{s}
//     initial_phase: NAME                # default: the first phase
//   safety:
//     max_trans_step: 0.0005             # m per cycle
//     max_rot_step_deg: 0.5              # deg per cycle
//     workspace: {min: [x, y, z], max: [x, y, z]}   # flange position in {g} (m)
//     force_ceiling: 40                  # N
//     ceiling_retreat: 0.01              # m
//     stale_timeout: 0.05                # s
//     contact_loss: {mode: hold | backoff | search, backoff_distance: 0.005,
//                    search_speed: 0.005, search_max_distance: 0.01}
//   phase_defaults: {kp: .., ki: .., integral_limit: .., u_max: ..}   # per-axis maps
//   phases:                              # required, a list
//     - name: NAME                       # required
//       s_d: {cop_x: 0, cop_y: 0, d_z: 0.0033, dzmp_x: 0, dzmp_y: 0, alpha_z: 0}
//            # rows of Δs; `force: 6` (N) sets the d_z row to c_z * 6; or a list of 6
//       jacobian: touch                  # or {beta: 0|1} or {point: 6x6, edge: 6x6} or {matrix: 6x6}
//       P: {x: 0, y: 1, z: 1, wx: 0, wy: 1, wz: 1, com: 0}   # gammas of Eq. 10, or a 6x6 list
//       kp: {x: .., y: .., z: .., wx: .., wy: .., wz: ..}    # per cycle (or a list of 6)
//       ki: {...}                        # 1/s
//       integral_limit: {...}            # |K_I ∫Δ| per axis (m or rad per cycle)
//       u_max: {...}                     # PI output limit per axis (m or rad per cycle)
//       feedforward: {vx: 0, vy: 0, vz: 0.01, wx: 0, wy: 0, wz: 0}   # {s}, m/s and rad/s
//       requires_contact: true
//       reset_integrator: true
//       terminal: false
//       transitions:
//         - {on: contact | edge | point | contact_lost, to: NAME, cycles: 1}
//         - {on: aligned, to: NAME, cycles: 20, tolerance: {alpha_z: 0.02, dzmp_y: 0.0005, ...}}
//         - {on: force_above, to: NAME, force_n: 20}
//         - {on: timeout, to: NAME, timeout_s: 30}
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

/// Same from an already parsed YAML document; `file` is used in messages.
ConfigResult loadServoProgram(const YAML::Node& root, const std::string& file, ServoParams& out);

}  // namespace tactile
