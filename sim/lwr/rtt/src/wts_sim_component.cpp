#include "tactile_sim_rtt/wts_sim_component.hpp"

#include <rtt/Logger.hpp>
#include <rtt/os/TimeService.hpp>

#include <cmath>

#include "tactile_sim/scene.hpp"

namespace tactile {

WtsSimComponent::WtsSimComponent(const std::string& name)
    : RTT::TaskContext(name, PreOperational), forces_in_("taxel_forces"), raw_out_("raw_frame") {
  addProperty("scene_file", scene_file_)
      .doc("Scene YAML (sim/scenes/*.yaml): its features_file's `calibration:` block (the real reader's "
           "calibration, inverted), sensor.noise_counts, sensor.threshold, seed and the sensor's `effects:` "
           "(transfer delay, gains, dead taxels, calibration error, crosstalk, creep, hysteresis, device noise). "
           "Read by configure().");
  addAttribute("frames", frames_);
  addEventPort(forces_in_).doc("SIM ONLY: true taxel forces (N, {s} layout) from the simulated arm (LwrSimComponent).");
  addPort(raw_out_).doc("Raw WTS frame (12-bit counts, {s} layout), stamped with RTT's TimeService (s): the port "
                        "of tactile::WtsComponent.");
  addOperation("lastError", &WtsSimComponent::lastError, this, RTT::ClientThread)
      .doc("Message of the last failed configure().");
}

bool WtsSimComponent::configureHook() {
  sim::Scene scene;
  ConfigResult r = scene_file_.empty() ? ConfigResult::failure("scene_file is empty: set it to a scene YAML (sim/scenes/*.yaml)")
                                       : sim::loadScene(scene_file_, scene);
  if (r) {
    r = response_.configure(sim::responseParams(scene));
    if (!r) r = ConfigResult::failure(scene_file_ + ": sensor: " + r.message());
  }
  if (!r) {
    last_error_ = r.message();
    RTT::log(RTT::Error) << getName() << ": " << last_error_ << RTT::endlog();
    return false;
  }
  last_error_.clear();
  raw_ = RawTactileFrame();
  raw_.rows = static_cast<uint16_t>(scene.calibration.rows);
  raw_.cols = static_cast<uint16_t>(scene.calibration.cols);
  raw_out_.setDataSample(raw_);
  return true;
}

bool WtsSimComponent::startHook() {
  response_.reseed(response_.params().seed);
  seq_ = 0;
  frames_ = 0;
  return true;
}

void WtsSimComponent::updateHook() {
  const double now = RTT::os::TimeService::Instance()->secondsSince(0);  // the servo's clock
  // Acquisition on new forces; with a transfer delay the frame is written
  // when it has arrived (TaxelResponse::deliver), the clock updates us every tick.
  bool out = forces_in_.read(forces_, false) == RTT::NewData && response_.acquire(forces_, now, raw_);
  if (response_.delayed() && response_.deliver(now, raw_)) out = true;
  if (!out) return;
  raw_.seq = seq_++;
  raw_.device_time_ms = static_cast<uint32_t>(std::llround(raw_.time_s * 1000.0));
  raw_out_.write(raw_);
  ++frames_;
}

}  // namespace tactile
