// tactile::ServoComponent: thin RTT wrapper around tactile::ServoStage
// (tactile::TactileServo, Sec. 4, Algorithm 1, Eq. 7-15), the same stage the
// headless runner steps. The hooks move data between ports and the stage; the
// control law, the phase program and the safety logic are in the core.
//
// Interface (documented with .doc() in the constructor):
//   property program_file (string)  YAML phase program (params/programs/*.yaml)
//   property controller_mode (string) '' = the program's controller.mode, or
//            proposed | baseline (Li et al., RSS 2013) | no_rotation (ablation): the deployment picks
//            the controller by its .cpf, as the runner's scene key `controller`
//   property period (double)        servo period (s), dt of the first cycle; 0 = the activity's
//   in   features     (/tactile/ContactFeatures)  from tactile::FeatureComponent
//   in   flange_pose  (/tactile/Pose)             measured {g}T{e} (LWR simulator / FRI bridge)
//   in   estimated_wrench (/tactile/Wrench)       the arm's estimated external wrench ({g} axes; LWR
//                                                 simulator / FRI bridge): the force-mismatch watchdog
//                                                 (unconnected: that check is off)
//   in   robot_state (/tactile/RobotState)        the arm side's state (LWR simulator / FRI bridge): not
//                                                 commandable -> hold, frozen (waiting_for_robot), resume
//                                                 from the measured pose (unconnected: commandable)
//   out  pose_command (/tactile/PoseCommand)      desired {g}T{e} (LWR simulator / FRI bridge)
//   out  phase        (/tactile/PhaseState)       where the phase program is
//   op   bool switchPhase(string name)  switch phase at the next cycle (false: unknown name)
//   op   string phaseName()             name of the current phase
//   op   int phaseIndex()               index of the current phase (no string built)
//   op   int phaseIndexOf(string name)  index of a phase of the program (-1: unknown)
//   op   string controllerMode()        controller in use (proposed | baseline | no_rotation)
//   op   string lastError()             message of the last failed configure()
//   attr last_status (int)              ServoStatus of the last cycle
//   attr integral (array, 6 doubles)    view of the PI integrator ∫Δs_task dt (Eq. 13) per task
//                                       axis x y z wx wy wz after the last cycle (for soaks and logs,
//                                       read in the servo's thread, e.g. by a slave reporter;
//                                       the controller never reads it back)
//
// Time: the cycle time is RTT's TimeService (seconds), the clock the sensor
// chain must also stamp its frames with (the stale-features watchdog compares
// them). dt is the time since the previous cycle (the activity period on the
// first one). Until a valid flange pose arrived the stage holds: the core is
// not stepped and pose_command is not written (last_status WaitingForPose).
#pragma once

#include <rtt/InputPort.hpp>
#include <rtt/OutputPort.hpp>
#include <rtt/TaskContext.hpp>

#include "tactile_types_rtt/component.hpp"

#include <atomic>
#include <string>
#include <vector>

#include "tactile_servo/servo.hpp"
#include "tactile_servo/servo_stage.hpp"
#include "tactile_types/types.hpp"

namespace tactile {

class ServoComponent : public Component {
 public:
  explicit ServoComponent(const std::string& name);
  /// Removes the scripting service first: the experiment's state machine
  /// (.osd) runs in this component and calls its operations; RTT would
  /// otherwise tear it down in ~TaskContext, after this part of the object
  /// is gone (UBSan: a member call on a destroyed ServoComponent).
  ~ServoComponent() override;

  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;

  bool switchPhase(const std::string& name);
  std::string phaseName() const;
  int phaseIndex() const;
  int phaseIndexOf(const std::string& name) const;
  std::string controllerMode() const { return mode_in_use_; }
  std::string lastError() const { return last_error_; }
  std::string statusName() const;
  std::string statusText() const;

 private:
  std::string program_file_;
  std::string controller_mode_;
  std::string mode_in_use_;
  double period_ = 0.0;
  std::string last_error_;
  std::atomic<int> last_status_{static_cast<int>(ServoStatus::NotConfigured)};  // read by any thread
  std::vector<double> integral_ = std::vector<double>(6, 0.0);  // sized once: updated in place, no allocation

  RTT::InputPort<ContactFeatures> features_in_;
  RTT::InputPort<Pose> flange_in_;
  RTT::InputPort<Wrench> wrench_in_;
  RTT::InputPort<RobotState> robot_in_;
  RTT::OutputPort<PoseCommand> command_out_;
  RTT::OutputPort<PhaseState> phase_out_;

  ServoStage stage_;  // the loop's servo stage (the headless runner steps the same)
  ContactFeatures features_;
  Pose pose_;
  Wrench wrench_;
  RobotState robot_;
  ServoOutput out_;
  std::atomic<int> requested_phase_{-1};
  std::atomic<int> current_phase_{0};
};

}  // namespace tactile
