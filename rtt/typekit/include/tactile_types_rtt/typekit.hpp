// RTT typekit for the shared plain types of tactile_types/types.hpp (core/types).
//
// Registered RTT type names (the ones to use in deployment scripts):
//   /tactile/RawTactileFrame   /tactile/TactileFrame   /tactile/ContactFeatures
//   /tactile/Pose              /tactile/PoseCommand    /tactile/PhaseState
//   /tactile/Wrench            /tactile/SimTruth
//   /tactile/ContactType       /tactile/FeatureStatus  /tactile/ServoStatus  (enums:
//        decompose to their name, e.g. "edge"; convert automatically to/from int)
//   /uint16_t                  (member type of frames and features; converts to/from int)
//   /tactile/double[]  /tactile/uint16_t[]  /tactile/char[]   (fixed-size array members)
//
// The library is an RTT typekit plugin (ORO_TYPEKIT_PLUGIN): the deployer loads
// it with import("tactile") from <RTT_COMPONENT_PATH>/<target>/tactile/types.
#pragma once

#include <rtt/types/TypekitPlugin.hpp>

#include <string>

namespace tactile {
namespace rtt_types {

constexpr const char* kRawTactileFrame = "/tactile/RawTactileFrame";
constexpr const char* kTactileFrame = "/tactile/TactileFrame";
constexpr const char* kContactFeatures = "/tactile/ContactFeatures";
constexpr const char* kPose = "/tactile/Pose";
constexpr const char* kPoseCommand = "/tactile/PoseCommand";
constexpr const char* kPhaseState = "/tactile/PhaseState";
constexpr const char* kWrench = "/tactile/Wrench";
constexpr const char* kSimTruth = "/tactile/SimTruth";
constexpr const char* kRobotState = "/tactile/RobotState";
constexpr const char* kRobotMode = "/tactile/RobotMode";
constexpr const char* kContactType = "/tactile/ContactType";
constexpr const char* kFeatureStatus = "/tactile/FeatureStatus";
constexpr const char* kServoStatus = "/tactile/ServoStatus";
constexpr const char* kUint16 = "/uint16_t";

class TactileTypekit : public RTT::types::TypekitPlugin {
 public:
  bool loadTypes() override;
  bool loadOperators() override;
  bool loadConstructors() override;
  std::string getName() override { return "tactile"; }
};

}  // namespace rtt_types
}  // namespace tactile
