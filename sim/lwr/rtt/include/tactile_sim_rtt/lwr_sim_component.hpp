// tactile::LwrSimComponent: thin RTT wrapper around the headless simulator
// (tactile::sim::World: LWR 4+ under Cartesian impedance, Eq. 11, with the
// WTS0614 pad on its flange) loaded from the same scene files as the headless
// runner (sim/scenes/*.yaml, tactile::sim::loadScene).
//
// It stands in for the real robot + sensor: the ports have the names and
// types of the FRI bridge (pose_command in, flange_pose out) and of the WTS
// reader (raw_frame out), so a deployment swaps one loadComponent line.
//
// Interface (documented with .doc() in the constructor):
//   property scene_file (string)   scene YAML (objects, arm, sensor, initial pose)
//   property wts_period (double)   s between WTS acquisitions (default 1/140)
//   in   pose_command (/tactile/PoseCommand)  desired {g}T{e}
//   out  flange_pose  (/tactile/Pose)         measured {g}T{e}, every update
//   out  raw_frame    (/tactile/RawTactileFrame)  WTS acquisition (counts)
//   out  frame        (/tactile/TactileFrame) the same acquisition calibrated with
//        the table that inverts the simulated response (World::calibration()),
//        for a FeatureComponent on its `frame` input
//   attr sim_period (double)  physics step of the scene (1 / rates.sim): run the
//        component periodically at this period
//   attr sim_time (double)    simulated time (s)
//   attr sim_status (int)     SimStatus of the last step (>= 10: fatal, see lwr_arm.hpp)
//   op   string statusName()  sim_status as text ("ok", "joint_limit", ...)
//   attr frames (int)         acquisitions written since start
//   op   string lastError()   message of the last failed configure()
//
// updateHook: read pose_command (the last valid command is held; before any,
// the start pose) -> World::step(cmd, sim_period) -> write flange_pose; when
// the simulated time reached the next acquisition -> World::acquire ->
// calibration -> write raw_frame and frame. Frames are stamped with RTT's
// TimeService (seconds), the clock of the ServoComponent's stale-features
// watchdog. No heap allocation per cycle (outputs preallocated).
#pragma once

#include <rtt/InputPort.hpp>
#include <rtt/OutputPort.hpp>
#include <rtt/TaskContext.hpp>

#include <atomic>
#include <string>

#include "tactile_features/calibration.hpp"
#include "tactile_sim/world.hpp"
#include "tactile_types/types.hpp"

namespace tactile {

class LwrSimComponent : public RTT::TaskContext {
 public:
  explicit LwrSimComponent(const std::string& name);

  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;

  std::string lastError() const { return last_error_; }
  std::string statusName() const;
  /// The simulated world (tests; not thread-safe while running).
  const sim::World& world() const { return world_; }

 private:
  // properties / attributes
  std::string scene_file_;
  double wts_period_ = 1.0 / 140.0;
  double sim_period_ = 0.001;
  double sim_time_ = 0.0;
  int sim_status_ = static_cast<int>(sim::SimStatus::NotConfigured);
  std::atomic<int> status_shadow_{static_cast<int>(sim::SimStatus::NotConfigured)};  // for statusName()
  int frames_ = 0;
  std::string last_error_;

  // ports
  RTT::InputPort<PoseCommand> command_in_;
  RTT::OutputPort<Pose> pose_out_;
  RTT::OutputPort<RawTactileFrame> raw_out_;
  RTT::OutputPort<TactileFrame> frame_out_;

  // cores and preallocated samples
  sim::World world_;
  sim::WorldParams world_params_;
  Calibration calibration_;
  sim::SimState state_;
  sim::SensorTruth truth_;
  PoseCommand cmd_in_;
  Pose cmd_;
  RawTactileFrame raw_;
  TactileFrame frame_;
  double next_acquisition_ = 0.0;
};

}  // namespace tactile
