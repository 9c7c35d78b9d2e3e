#include "tactile_sim_rtt/wts_sim_component.hpp"

#include "tactile_types_rtt/atomic_attribute.hpp"

#include <rtt/Logger.hpp>
#include <rtt/os/TimeService.hpp>

#include <cmath>

#include "tactile_sim_runner/scene.hpp"

namespace tactile {

WtsSimComponent::WtsSimComponent(const std::string& name)
    : Component(name, PreOperational),
      forces_in_("taxel_forces"),
      raw_out_("raw_frame"),
      fault_frame_out_("fault_frame") {
  addProperty("scene_file", scene_file_)
      .doc("Scene YAML (params/scenes/*.yaml): its features_file's `calibration:` block (the real reader's "
           "calibration, inverted), sensor.noise_counts, sensor.threshold, seed and the sensor's `effects:` "
           "(transfer delay, gains, dead taxels, calibration error, crosstalk, creep, hysteresis, device noise) "
           "and the pad's scheduled `faults:` (tactile_sim_faults/sensor_faults.hpp). Read by configure().");
  addAtomicAttribute(*provides(), "frames", frames_);
  addProperty("fault", fault_)
      .doc("TESTS ONLY, fault injection (tactile_sim_faults/sensor_faults.hpp): '' = none (default), stale (no frame in "
           "[fault_start, fault_start + fault_duration)), disconnect (the same, link_status Disconnected, then "
           "Reconnected), nan (the first acquisition at or after fault_start goes out on fault_frame with a NaN "
           "taxel instead of raw_frame), saturated (that acquisition at full scale on every taxel). Read by configure().");
  addProperty("fault_start", fault_start_).doc("TESTS ONLY: simulated time of the fault (s), >= 0.");
  addProperty("fault_duration", fault_duration_).doc("TESTS ONLY: window of stale and disconnect (s), in (0, 60].");
  addAtomicAttribute(*provides(), "link_status", link_status_);
  addAtomicAttribute(*provides(), "fault_seq", fault_seq_);
  addEventPort(forces_in_).doc("SIM ONLY: true taxel forces (N, {s} layout) from the simulated arm (LwrSimComponent).");
  addPort(raw_out_).doc("Raw WTS frame (12-bit counts, {s} layout), stamped with RTT's TimeService (s): the port "
                        "of tactile::WtsComponent.");
  addPort(fault_frame_out_).doc("TESTS ONLY (fault nan): the calibrated frame (N, {s} layout) with a NaN taxel, for "
                                "FeatureComponent's `frame` input; nothing is written without that fault.");
  addOperation("lastError", &WtsSimComponent::lastError, this, RTT::ClientThread)
      .doc("Message of the last failed configure().");
  addOperation("statusName", &WtsSimComponent::statusName, this, RTT::ClientThread)
      .doc("link_status as text, with the names of tactile::WtsComponent's read_status (NewFrame, Disconnected, "
           "Reconnected).");
}

bool WtsSimComponent::configureHook() {
  sim::Scene scene;
  ConfigResult r = scene_file_.empty() ? ConfigResult::failure("scene_file is empty: set it to a scene YAML (params/scenes/*.yaml)")
                                       : sim::loadScene(scene_file_, scene);
  sim::TaxelResponseParams rp;
  if (r) {  // the scene's faults, and the property's one after them
    rp = sim::responseParams(scene);
    sim::SensorFaultSchedule property;
    r = property.configure(fault_, fault_start_, fault_duration_);
    if (!r) r = ConfigResult::failure(getName() + ": " + r.message());
    else if (property.any()) rp.faults.push_back(property.spec(0));
  }
  if (r) {
    r = response_.configure(rp);
    if (!r) r = ConfigResult::failure(scene_file_ + ": sensor: " + r.message());
  }
  if (!verdict(r, last_error_)) return false;
  raw_ = RawTactileFrame();
  raw_.rows = static_cast<uint16_t>(scene.calibration.rows);
  raw_.cols = static_cast<uint16_t>(scene.calibration.cols);
  raw_out_.setDataSample(raw_);
  nan_frame_ = TactileFrame();
  nan_frame_.rows = raw_.rows;
  nan_frame_.cols = raw_.cols;
  fault_frame_out_.setDataSample(nan_frame_);
  return true;
}

bool WtsSimComponent::startHook() {
  response_.reseed(response_.params().seed);
  seq_ = 0;
  record(frames_, 0);
  record(fault_seq_, -1);
  withheld_ = false;
  shots_ = 0;
  record(link_status_, static_cast<int>(response_.faults().link()));
  return true;
}

void WtsSimComponent::noteFault(bool delivered) {
  const sim::SensorFaultSchedule& f = response_.faults();
  record(link_status_, static_cast<int>(f.link()));
  if (!delivered) {
    if (f.lastAction() == sim::FaultAction::Withhold) withheld_ = true;
    return;
  }
  // The first frame after a withheld window, or the frame a one-shot fault hit (nan, saturated).
  if (withheld_ || f.shots() != shots_) {
    withheld_ = false;
    shots_ = f.shots();
    record(fault_seq_, static_cast<int>(seq_));
  }
}

void WtsSimComponent::updateHook() {
  const HookScope hook(*this);  // the other hooks' writes before this update (component.hpp)
  const double now = RTT::os::TimeService::Instance()->secondsSince(0);  // the servo's clock
  // Acquisition on new forces; with a transfer delay the frame is written
  // when it has arrived (TaxelResponse::deliver), the clock updates us every tick.
  // The schedule's stream faults withhold or repeat frames inside acquire() and deliver().
  const bool acquired = forces_in_.read(forces_, false) == RTT::NewData;
  bool out = acquired && response_.acquire(forces_, now, raw_);
  if (response_.delayed() && response_.deliver(now, raw_)) out = true;
  if (response_.faults().any() && (acquired || out)) noteFault(out);
  if (!out) return;
  raw_.seq = seq_++;
  raw_.device_time_ms = static_cast<uint32_t>(std::llround(raw_.time_s * 1000.0));
  bump(frames_);
  if (response_.faults().lastAction() == sim::FaultAction::NanFrame) {
    sim::nanFrame(forces_, raw_.time_s, raw_.seq, nan_frame_);  // instead of the counts
    fault_frame_out_.write(nan_frame_);
    return;
  }
  raw_out_.write(raw_);
}

}  // namespace tactile
