// tactile::LwrSimComponent: the simulated ARM (KUKA LWR 4+ under Cartesian
// impedance, Eq. 11, with the WTS0614 pad's elastic layer on its flange):
// thin RTT wrapper around tactile::sim::World, loaded from the headless
// runner's scene files (params/scenes/*.yaml) with the servo's program
// (the pad's mount), as tactile::sim::loadRun reads them.
//
// It stands in for the robot: the controller-facing ports are those of the
// FRI bridge (tactile::FriBridgeComponent), so a deployment swaps the two by
// one loadComponent line. The tactile SENSOR is a separate component,
// tactile::WtsSimComponent (raw counts on `raw_frame`, as tactile::WtsComponent),
// fed by this component's sim-only `taxel_forces` port.
//
// Interface (documented with .doc() in the constructor):
//   property scene_file (string)   scene YAML (objects, arm, pad, initial pose, rates)
//   property program_file (string) the servo's program (its controller.sensor_mount mounts the pad)
//   in   pose_command (/tactile/PoseCommand)  desired {g}T{e} (last valid held; the start pose before any)
//   out  flange_pose  (/tactile/Pose)         measured {g}T{e}, after every physics step (and at start)
//   out  estimated_wrench (/tactile/Wrench)   the contact wrench on the flange, {g} axes at the flange
//                                             origin (what the KRC's estExtTcpFT estimates), every step
//   out  robot_state  (/tactile/RobotState)   the KRC's state by the FRI bridge's rule, from the scene's
//                                             `krc` script (default: command mode throughout); not
//                                             commandable: the arm holds where it is
//   out  taxel_forces (/tactile/TactileFrame) SIM ONLY: the true taxel force image (N) for the
//                                             sensor, before each WTS acquisition of the scene's schedule
//   out  truth        (/tactile/SimTruth)     SIM ONLY: ground truth for logs (never read by the controller)
//   attr sim_period (double)  physics step 1 / rates.sim (run the component periodically at it)
//   attr sim_time (double)    simulated time (s)
//   attr sim_status (int)     SimStatus of the last step (>= 10: fatal, see lwr_arm.hpp)
//   attr frames (int)         images written since start
//   op   string statusName(), string lastError()
//
// Each update: read pose_command -> World::step(cmd, 1 / rates.sim) ->
// flange_pose, estimated_wrench, truth; when the scene's schedule
// (tactile::sim::Schedule) fires a WTS acquisition on the next physics tick,
// World::acquireForces -> taxel_forces. start() resets the world to the
// scene's initial state and writes the initial outputs (the image of the
// tick-0 acquisition included). No heap allocation per cycle.
#pragma once

#include <rtt/InputPort.hpp>
#include <rtt/OutputPort.hpp>
#include <rtt/TaskContext.hpp>

#include "tactile_types_rtt/component.hpp"

#include <atomic>
#include <string>

#include "tactile_sim_runner/loop.hpp"
#include "tactile_sim_lwr/world.hpp"
#include "tactile_fri/krc_model.hpp"
#include "tactile_types/types.hpp"

namespace tactile {

class LwrSimComponent : public Component {
 public:
  explicit LwrSimComponent(const std::string& name);
  ~LwrSimComponent() override { haltActivity(); }  // stops its thread while its ports exist (component.hpp)

  bool configureHook() override;
  bool startHook() override;
  void updateHook() override;

  std::string lastError() const { return last_error_; }
  std::string statusName() const;
  /// The simulated world (tests; not thread-safe while running).
  const sim::World& world() const { return world_; }

 private:
  void publish();

  // properties / attributes
  std::string scene_file_;
  std::string program_file_;
  // The component's record, read by any thread (atomic_attribute.hpp).
  std::atomic<double> sim_period_{0.001};
  std::atomic<double> sim_time_{0.0};
  std::atomic<int> sim_status_{static_cast<int>(sim::SimStatus::NotConfigured)};
  std::atomic<int> frames_{0};
  std::string last_error_;

  // ports
  RTT::InputPort<PoseCommand> command_in_;
  RTT::OutputPort<Pose> pose_out_;
  RTT::OutputPort<Wrench> wrench_out_;
  RTT::OutputPort<TactileFrame> forces_out_;
  RTT::OutputPort<SimTruth> truth_out_;
  RTT::OutputPort<RobotState> robot_out_;
  fri::KrcScript krc_script_;  // the scene's `krc`
  RobotState robot_;

  // cores and preallocated samples
  sim::World world_;
  sim::WorldParams world_params_;
  sim::Schedule schedule_;  // the loop's schedule: when the sensor acquires
  sim::SimState state_;
  sim::SensorTruth acq_;
  PoseCommand cmd_in_;
  Pose cmd_;
  TactileFrame forces_;
  SimTruth truth_;
  Wrench wrench_;
  sim::EstimatedWrench est_wrench_;  // the arm's estimated wrench with the scene's error (loop.hpp)
};

}  // namespace tactile
