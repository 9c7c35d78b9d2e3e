#include "tactile_types/types.hpp"

namespace tactile {

const char* toString(ContactType t) {
  switch (t) {
    case ContactType::None: return "none";
    case ContactType::Point: return "point";
    case ContactType::Edge: return "edge";
    case ContactType::Multiple: return "multiple";
  }
  return "unknown";
}

const char* toString(FeatureStatus s) {
  switch (s) {
    case FeatureStatus::Ok: return "ok";
    case FeatureStatus::NoContact: return "no_contact";
    case FeatureStatus::Saturated: return "saturated";
    case FeatureStatus::TareRejected: return "tare_rejected";
    case FeatureStatus::InvalidInput: return "invalid_input";
    case FeatureStatus::BadDimensions: return "bad_dimensions";
    case FeatureStatus::NotConfigured: return "not_configured";
    case FeatureStatus::OutOfRange: return "out_of_range";
  }
  return "unknown";
}

const char* toString(ServoStatus s) {
  switch (s) {
    case ServoStatus::Ok: return "ok";
    case ServoStatus::FreeMotion: return "free_motion";
    case ServoStatus::Holding: return "holding";
    case ServoStatus::ContactLost: return "contact_lost";
    case ServoStatus::Limited: return "limited";
    case ServoStatus::Done: return "done";
    case ServoStatus::WaitingForPose: return "waiting_for_pose";
    case ServoStatus::Starting: return "starting";
    case ServoStatus::WaitingForRobot: return "waiting_for_robot";
    case ServoStatus::ForceCeiling: return "force_ceiling";
    case ServoStatus::InvalidInput: return "invalid_input";
    case ServoStatus::NotConfigured: return "not_configured";
    case ServoStatus::PhaseTimeout: return "phase_timeout";
    case ServoStatus::ArmStalled: return "arm_stalled";
    case ServoStatus::ForceMismatch: return "force_mismatch";
    case ServoStatus::SurfaceTooCurved: return "surface_too_curved";
  }
  return "unknown";
}

const char* toString(RobotMode m) {
  switch (m) {
    case RobotMode::Off: return "off";
    case RobotMode::Monitor: return "monitor";
    case RobotMode::Command: return "command";
  }
  return "unknown";
}

}  // namespace tactile
