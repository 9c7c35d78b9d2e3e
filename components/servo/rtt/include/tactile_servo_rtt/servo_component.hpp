// tactile::ServoComponent: thin RTT wrapper around tactile::TactileServo
// (Sec. 4, Algorithm 1, Eq. 7-15). The hooks move data between ports and the
// core; the control law, the phase program and the safety logic are in the core.
//
// Interface (documented with .doc() in the constructor):
//   property program_file (string)  YAML phase program (components/servo/programs/*.yaml)
//   in   features     (/tactile/ContactFeatures)  from tactile::FeatureComponent
//   in   flange_pose  (/tactile/Pose)             measured {g}T{e} (LWR simulator / FRI bridge)
//   out  pose_command (/tactile/PoseCommand)      desired {g}T{e} (LWR simulator / FRI bridge)
//   out  phase        (/tactile/PhaseState)       where the phase program is
//   op   bool switchPhase(string name)  switch phase at the next cycle (false: unknown name)
//   op   string phaseName()             name of the current phase
//   op   int phaseIndex(string name)    index of a phase (as in phase.index), -1 if unknown
//   op   string lastError()             message of the last failed configure()
//   attr last_status (int)              ServoStatus of the last cycle
//
// Time: the cycle time is RTT's TimeService (seconds), the clock the sensor
// chain must also stamp its frames with (the stale-features watchdog compares
// them). dt is the time since the previous cycle (the activity period on the
// first one). pose_command is written only once the core has a valid measured
// flange pose (written after this start); the first one written is that pose.
#pragma once

#include <rtt/InputPort.hpp>
#include <rtt/OutputPort.hpp>
#include <rtt/TaskContext.hpp>

#include <atomic>
#include <string>

#include "tactile_servo/servo.hpp"
#include "tactile_types/types.hpp"

namespace tactile {

class ServoComponent : public RTT::TaskContext {
 public:
  explicit ServoComponent(const std::string& name);

  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;

  bool switchPhase(const std::string& name);
  std::string phaseName() const;
  int phaseIndex(const std::string& name) const;
  std::string lastError() const { return last_error_; }

 private:
  std::string program_file_;
  std::string last_error_;
  int last_status_ = static_cast<int>(ServoStatus::NotConfigured);

  RTT::InputPort<ContactFeatures> features_in_;
  RTT::InputPort<Pose> flange_in_;
  RTT::OutputPort<PoseCommand> command_out_;
  RTT::OutputPort<PhaseState> phase_out_;

  TactileServo servo_;
  ServoInput in_;
  ServoOutput out_;
  std::atomic<int> requested_phase_{-1};
  std::atomic<int> current_phase_{0};
  bool first_cycle_ = true;
  double last_time_ = 0.0;
};

}  // namespace tactile
