#include "tactile_sim_rtt/lwr_sim_component.hpp"

#include "tactile_types_rtt/atomic_attribute.hpp"

#include <rtt/Component.hpp>
#include <rtt/Logger.hpp>
#include <rtt/os/TimeService.hpp>

#include <cmath>

#include "tactile_sim_runner/scene.hpp"

namespace tactile {

LwrSimComponent::LwrSimComponent(const std::string& name)
    : Component(name, PreOperational),
      command_in_("pose_command"),
      pose_out_("flange_pose"),
      wrench_out_("estimated_wrench"),
      forces_out_("taxel_forces"),
      truth_out_("truth"),
      robot_out_("robot_state") {
  addProperty("scene_file", scene_file_)
      .doc("Scene YAML (params/scenes/*.yaml, the headless runner's files): arm, pad, objects, initial flange "
           "pose, rates (physics step, WTS schedule). Read by configure().");
  addProperty("program_file", program_file_)
      .doc("The servo's phase program (params/programs/*.yaml; the deployment sets the Servo's): the simulated pad "
           "is mounted on the flange as its controller.sensor_mount says, as on the robot. Read by configure().");
  addAtomicAttribute(*provides(), "sim_period", sim_period_);
  addAtomicAttribute(*provides(), "sim_time", sim_time_);
  addAtomicAttribute(*provides(), "sim_status", sim_status_);
  addAtomicAttribute(*provides(), "frames", frames_);
  addPort(command_in_).doc("Desired flange pose {g}T{e} (from the servo); the last valid one is held.");
  addPort(pose_out_).doc("Measured flange pose {g}T{e}, after every physics step (and at start).");
  addPort(wrench_out_).doc("Contact wrench on the flange [Fx Fy Fz Tx Ty Tz] (N, N m), {g} axes, flange origin: "
                           "what the KRC's estExtTcpFT estimates. Every physics step.");
  addPort(robot_out_).doc("The KRC's state as the FRI bridge reports it, after every physics step: the scene's "
                          "`krc` script (friOpen, friStart, friStop, quality, drives; default: command mode "
                          "throughout); while not commandable the arm holds where it is. Joints: the arm's.");
  addPort(forces_out_).doc("SIM ONLY, for tactile::WtsSimComponent: true taxel forces (N, {s} layout) before each "
                           "WTS acquisition of the scene's schedule.");
  addPort(truth_out_).doc("SIM ONLY, for logs: ground truth after every physics step (contact wrench, layer and "
                          "housing force, tray angles, true contact point, sensor pose). Never read by the controller.");
  addOperation("lastError", &LwrSimComponent::lastError, this, RTT::ClientThread)
      .doc("Message of the last failed configure().");
  addOperation("statusName", &LwrSimComponent::statusName, this, RTT::ClientThread)
      .doc("SimStatus of the last physics step as text.");
}

bool LwrSimComponent::configureHook() {
  sim::Scene scene;
  ConfigResult r =
      scene_file_.empty()     ? ConfigResult::failure("scene_file is empty: set it to a scene YAML (params/scenes/*.yaml)")
      : program_file_.empty() ? ConfigResult::failure("program_file is empty: set it to the Servo's program (the pad's "
                                                      "mount, controller.sensor_mount)")
                              : sim::loadRun(sim::RunFiles{scene_file_, program_file_, ""}, scene);
  if (r) {
    world_params_ = sim::worldParams(scene);  // seed and physics step (the KRC cycle's and FRI delay's unit)
    record(sim_period_, 1.0 / scene.rates.sim);
    est_wrench_.configure(scene.wrench_error, scene.seed, scene.faults);  // validated by loadScene
    r = krc_script_.parse(scene.krc, scene_file_ + ": krc");
    if (r) r = world_.configure(world_params_);
    if (r) r = schedule_.configure(scene.rates, scene.duration);
    if (!r) r = ConfigResult::failure(scene_file_ + ": " + r.message());
  }
  if (!verdict(r, last_error_)) return false;
  const double sim_period = sim_period_.load();
  if (getPeriod() > 0.0 && std::fabs(getPeriod() - sim_period) > 1e-9)
    RTT::log(RTT::Warning) << getName() << ": activity period " << getPeriod() << " s differs from the scene's physics step "
                           << sim_period << " s: simulated time runs at " << sim_period / getPeriod()
                           << " x wall time" << RTT::endlog();
  // Preallocate the output samples (fixed-size types).
  forces_ = world_.pad().trueTaxelForces();
  pose_out_.setDataSample(world_.state().flange_g);
  wrench_out_.setDataSample(wrench_);
  forces_out_.setDataSample(forces_);
  truth_out_.setDataSample(truth_);
  robot_out_.setDataSample(robot_);
  return true;
}

void LwrSimComponent::publish() {
  // The image of the next tick's WTS acquisition (the loop's schedule), then
  // the ground truth (with that acquisition's contact point), as the runner.
  if (schedule_.fires().wts) {
    world_.acquireForces(forces_, acq_);
    forces_.time_s = state_.time_s;
    forces_out_.write(forces_);
    bump(frames_);
  }
  sim::fillTruth(state_, acq_, truth_);
  truth_out_.write(truth_);
  // The KRC's state at the arm's time (before the pose: a servo that sees the pose sees the state too).
  fri::robotStateOf(krc_script_.at(state_.time_s), state_.time_s, robot_);
  for (int j = 0; j < kArmJoints; ++j) robot_.q[static_cast<std::size_t>(j)] = state_.q(j);
  robot_.setpoint = state_.command_g;  // the KRC's set point: the last command the arm took
  robot_out_.write(robot_);
  pose_out_.write(state_.flange_g);
  // Contact wrench on the sensor moved to the flange, {g} axes (the loop's rule, as the runner).
  est_wrench_.fill(state_, wrench_);
  wrench_out_.write(wrench_);
}

bool LwrSimComponent::startHook() {
  // A (re)start begins from the scene's initial state.
  const ConfigResult r = world_.configure(world_params_);
  if (!r) {
    last_error_ = r.message();
    return false;
  }
  schedule_.reset();
  state_ = world_.state();
  est_wrench_.start(state_);
  cmd_ = state_.command_g;  // hold the start command until a command arrives
  acq_ = sim::SensorTruth();
  record(sim_time_, state_.time_s);
  record(frames_, 0);
  record(sim_status_, static_cast<int>(sim::SimStatus::Ok));
  publish();  // the initial pose, wrench, truth and the tick-0 image
  return true;
}

std::string LwrSimComponent::statusName() const {
  return sim::toString(static_cast<sim::SimStatus>(sim_status_.load(std::memory_order_acquire)));
}

void LwrSimComponent::updateHook() {
  const HookScope hook(*this);  // the other hooks' writes before this update (component.hpp)
  if (command_in_.read(cmd_in_, false) == RTT::NewData) cmd_ = cmd_in_.pose;  // World rejects NaN / non-unit
  // Not commandable (robot_ of this time, published last): the KRC keeps the set point it has.
  const sim::SimStatus st = world_.step(robot_.commandable ? cmd_ : state_.command_g, sim_period_.load(std::memory_order_relaxed), state_);
  record(sim_status_, static_cast<int>(st));
  record(sim_time_, state_.time_s);
  schedule_.advance();
  publish();
}

}  // namespace tactile
