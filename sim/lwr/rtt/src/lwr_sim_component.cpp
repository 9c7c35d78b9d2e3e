#include "tactile_sim_rtt/lwr_sim_component.hpp"

#include <rtt/Component.hpp>
#include <rtt/Logger.hpp>
#include <rtt/os/TimeService.hpp>

#include <cmath>

#include "tactile_sim/scene.hpp"

namespace tactile {

LwrSimComponent::LwrSimComponent(const std::string& name)
    : RTT::TaskContext(name, PreOperational),
      command_in_("pose_command"),
      pose_out_("flange_pose"),
      raw_out_("raw_frame"),
      frame_out_("frame") {
  addProperty("scene_file", scene_file_)
      .doc("Scene YAML (sim/scenes/*.yaml, the headless runner's files): arm, sensor, objects, initial flange "
           "pose, physics rate. Read by configure().");
  addProperty("wts_period", wts_period_)
      .doc("Simulated time between two WTS acquisitions (s), in (0, 1]; default 1/140 (Table 2).");
  addAttribute("sim_period", sim_period_);
  addAttribute("sim_time", sim_time_);
  addAttribute("sim_status", sim_status_);
  addAttribute("frames", frames_);
  addEventPort(command_in_).doc("Desired flange pose {g}T{e} (from the servo); the last valid one is held.");
  addPort(pose_out_).doc("Measured flange pose {g}T{e}, written every physics step.");
  addPort(raw_out_).doc("Simulated WTS0614 acquisition (12-bit counts, {s} layout), every wts_period.");
  addPort(frame_out_).doc("The same acquisition calibrated with the table that inverts the simulated response (N).");
  addOperation("lastError", &LwrSimComponent::lastError, this, RTT::ClientThread)
      .doc("Message of the last failed configure().");
  addOperation("statusName", &LwrSimComponent::statusName, this, RTT::ClientThread)
      .doc("SimStatus of the last physics step as text.");
}

bool LwrSimComponent::configureHook() {
  sim::Scene scene;
  ConfigResult r = scene_file_.empty() ? ConfigResult::failure("scene_file is empty: set it to a scene YAML (sim/scenes/*.yaml)")
                                       : sim::loadScene(scene_file_, scene);
  if (r && !(wts_period_ > 0.0 && wts_period_ <= 1.0))
    r = rangeError("wts_period", wts_period_, "(0, 1] s");
  if (r) {
    world_params_ = scene.world;
    world_params_.seed = scene.seed;
    sim_period_ = 1.0 / scene.rates.sim;
    r = world_.configure(world_params_);
    if (!r) r = ConfigResult::failure(scene_file_ + ": " + r.message());
  }
  if (r) {
    r = calibration_.configure(world_.calibration());  // inverts the simulated taxel response
    if (!r) r = ConfigResult::failure(scene_file_ + ": calibration: " + r.message());
  }
  if (!r) {
    last_error_ = r.message();
    RTT::log(RTT::Error) << getName() << ": " << last_error_ << RTT::endlog();
    return false;
  }
  if (getPeriod() > 0.0 && std::fabs(getPeriod() - sim_period_) > 1e-9)
    RTT::log(RTT::Warning) << getName() << ": activity period " << getPeriod() << " s differs from the scene's physics step "
                           << sim_period_ << " s: simulated time runs at " << sim_period_ / getPeriod()
                           << " x wall time" << RTT::endlog();
  last_error_.clear();
  // Preallocate the output samples (fixed-size types).
  raw_ = RawTactileFrame();
  frame_ = TactileFrame();
  world_.acquire(raw_, truth_);  // sizes rows/cols as the simulated sensor
  calibration_.step(raw_, frame_);
  pose_out_.setDataSample(world_.state().flange_g);
  raw_out_.setDataSample(raw_);
  frame_out_.setDataSample(frame_);
  return true;
}

bool LwrSimComponent::startHook() {
  // A (re)start begins from the scene's initial state.
  const ConfigResult r = world_.configure(world_params_);
  if (!r) {
    last_error_ = r.message();
    return false;
  }
  state_ = world_.state();
  cmd_ = state_.flange_g;  // hold the start pose until a command arrives
  sim_time_ = state_.time_s;
  next_acquisition_ = state_.time_s;
  frames_ = 0;
  sim_status_ = static_cast<int>(sim::SimStatus::Ok);
  status_shadow_.store(sim_status_);
  return true;
}

std::string LwrSimComponent::statusName() const {
  return sim::toString(static_cast<sim::SimStatus>(status_shadow_.load()));
}

void LwrSimComponent::updateHook() {
  if (command_in_.read(cmd_in_, false) == RTT::NewData) cmd_ = cmd_in_.pose;  // World rejects NaN / non-unit
  const sim::SimStatus st = world_.step(cmd_, sim_period_, state_);
  sim_status_ = static_cast<int>(st);
  status_shadow_.store(sim_status_);
  sim_time_ = state_.time_s;
  pose_out_.write(state_.flange_g);
  if (state_.time_s + 0.25 * sim_period_ >= next_acquisition_) {
    next_acquisition_ += wts_period_;
    world_.acquire(raw_, truth_);
    raw_.time_s = RTT::os::TimeService::Instance()->secondsSince(0);  // the servo's clock
    calibration_.step(raw_, frame_);  // copies time_s and seq
    raw_out_.write(raw_);
    frame_out_.write(frame_);
    ++frames_;
  }
}

}  // namespace tactile

ORO_CREATE_COMPONENT_LIBRARY()
ORO_LIST_COMPONENT_TYPE(tactile::LwrSimComponent)
