// YAML -> BridgeParams / UdpParams. Keys mirror the struct fields (SI units).
//
//   fri:
//     max_lin_speed: 0.05        # m/s, (0, 2]
//     max_rot_speed: 0.25        # rad/s, (0, 3]
//     cycle_time_s: 0.001        # s, (0, 0.1]: the KRC's cycle (friOpen)
//     max_desired_age_s: 0.1     # s, (0, 10]
//     engage_max_trans: 0.0005   # m, (0, 0.1]: start gate (see bridge.hpp)
//     engage_max_rot: 0.00872665 # rad, (0, 0.5]: start gate
//     resync_after: 8            # packets, [1, 1000]
//     rewind_on_refl: true
//     command_impedance: false
//     cart_stiffness: [2000, 2000, 2000, 200, 200, 200]  # N/m x3, N m/rad x3
//     cart_damping: [0.7, 0.7, 0.7, 0.7, 0.7, 0.7]
//     cart_offset: composed      # none | composed | elementwise (protocol.hpp CartOffset)
//     setpoint_max_dev: 0.01     # m, (0, 1]: the set point read vs the measured pose
//     setpoint_max_dev_rot: 0.05 # rad, (0, 3.2]
//     stop_krc_on_servo_fault: true  # a servo watchdog status asks the KRL program to end
//     udp:
//       bind_address: 0.0.0.0
//       port: 49938              # [0, 65535], 0 = ephemeral
//       krc_port: 0              # [0, 65535], the KRC's source port, 0 = any
#pragma once

#include <string>

#include <yaml-cpp/yaml.h>

#include "tactile_config/yaml_params.hpp"
#include "tactile_fri/bridge.hpp"
#include "tactile_fri/udp.hpp"

namespace tactile {
namespace fri {

/// Reads a `fri:` mapping into `bp` and its `udp:` child into `up` (absent keys
/// keep their value), rejects unknown keys, and validates by configuring a
/// scratch bridge. Failures name the file, the key path and the valid range.
ConfigResult loadBridgeParams(const YAML::Node& node, const config::Where& where, BridgeParams& bp, UdpParams& up);

/// Loads `file` and reads its top-level `fri:` mapping.
ConfigResult loadBridgeParamsFile(const std::string& file, BridgeParams& bp, UdpParams& up);

}  // namespace fri
}  // namespace tactile
