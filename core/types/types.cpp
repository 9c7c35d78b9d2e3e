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
    case ServoStatus::PhantomContact: return "phantom_contact";
    case ServoStatus::UnseenLoad: return "unseen_load";
    case ServoStatus::CorrectionSaturated: return "correction_saturated";
    case ServoStatus::CorrectionDrift: return "correction_drift";
  }
  return "unknown";
}

const char* explain(ServoStatus s) {
  switch (s) {
    case ServoStatus::Ok: return "servoing";
    case ServoStatus::FreeMotion: return "moving without contact";
    case ServoStatus::Holding: return "holding: the features are stale";
    case ServoStatus::ContactLost: return "the contact was lost: searching along z_s";
    case ServoStatus::Limited: return "servoing at the speed limits";
    case ServoStatus::Done: return "the program's terminal phase: holding";
    case ServoStatus::WaitingForPose: return "waiting for the arm's first measured pose";
    case ServoStatus::Starting: return "starting";
    case ServoStatus::WaitingForRobot: return "the arm cannot be commanded (KRC in monitor mode, link quality, drives off): holding";
    case ServoStatus::ForceCeiling:
      return "the tactile force passed the program's ceiling (safety.force_ceiling): retreating along -z_s, then "
             "holding until a phase switch";
    case ServoStatus::InvalidInput: return "a non-finite pose, feature or time step: holding";
    case ServoStatus::NotConfigured: return "not configured";
    case ServoStatus::PhaseTimeout:
      return "longer in a phase than its max_duration_s: the phase never ended; holding";
    case ServoStatus::ArmStalled:
      return "the arm did not follow the commanded motion (a joint limit, a collision, a controller that does not "
             "move): holding";
    case ServoStatus::ForceMismatch:
      return "the arm's estimated wrench along z_s carries more than the taxels' force and the force estimate's "
             "bound (load on the housing, a pad softer than calibrated): stopped as the program says";
    case ServoStatus::SurfaceTooCurved:
      return "the surface curves more tightly than the rigid pad can follow (or lies where no taxel sees it): the "
             "arm's wrench carries more than the force set point while the image shrank to part of the pad or "
             "vanished; holding";
    case ServoStatus::PhantomContact:
      return "the taxels read a load the arm's estimated wrench does not carry (a stuck or pressed region, the "
             "cable or the cover, a calibration too high): the contact is not real; stopped as the program says";
    case ServoStatus::UnseenLoad:
      return "the arm's estimated wrench carries a load no taxel sees (the housing, the cable, a wrong load "
             "model): stopped as the program says";
    case ServoStatus::CorrectionSaturated:
      return "the force estimate's correction stayed at its limit (force_estimate.max_correction_n): the taxels "
             "and the wrench disagree by more than the estimate may bridge (a calibration off, a wrench bias); "
             "stopped as the program says";
    case ServoStatus::CorrectionDrift:
      return "the force estimate's correction kept moving where the load the taxels miss should stay the same "
             "(watchdogs.correction_drift): the two sensors drift apart (the arm's wrench drifts or jumps, or "
             "the pad's tare creeps) and the estimate would carry the true force with them; stopped as the "
             "program says";
  }
  return "unknown status";
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
