#include "tactile_servo_rtt/servo_component.hpp"

#include <rtt/Component.hpp>
#include <rtt/Logger.hpp>
#include <rtt/os/TimeService.hpp>

#include "tactile_servo/program_io.hpp"

namespace tactile {

ServoComponent::ServoComponent(const std::string& name)
    : RTT::TaskContext(name, PreOperational),
      features_in_("features"),
      flange_in_("flange_pose"),
      command_out_("pose_command"),
      phase_out_("phase") {
  addProperty("program_file", program_file_)
      .doc("YAML phase program (controller, safety, phases; see tactile_servo/program_io.hpp). Read by configure().");
  addAttribute("last_status", last_status_);
  addEventPort(features_in_).doc("Contact features in {s} (from the feature component).");
  addPort(flange_in_).doc("Measured flange pose {g}T{e} (LWR simulator or FRI bridge).");
  addPort(command_out_).doc("Desired flange pose {g}T{e} for the Cartesian impedance controller, with the servo status.");
  addPort(phase_out_).doc("Phase program state: index, name, entry time, status.");
  addOperation("switchPhase", &ServoComponent::switchPhase, this, RTT::ClientThread)
      .doc("Switch to the named phase at the next cycle (clears a force-ceiling latch). False for an unknown name.")
      .arg("name", "Phase name as in the program file.");
  addOperation("phaseName", &ServoComponent::phaseName, this, RTT::ClientThread).doc("Name of the current phase.");
  addOperation("phaseIndex", &ServoComponent::phaseIndex, this, RTT::ClientThread)
      .doc("Index of the named phase in the program (as in the phase port's `index`), -1 if unknown. "
           "Look it up once (e.g. in a state's entry) and compare indices per cycle: no strings in the servo's thread.")
      .arg("name", "Phase name as in the program file.");
  addOperation("lastError", &ServoComponent::lastError, this, RTT::ClientThread)
      .doc("Message of the last failed configure().");
}

bool ServoComponent::configureHook() {
  ServoParams p;
  ConfigResult r = program_file_.empty()
                       ? ConfigResult::failure("program_file is empty: set it to a YAML phase program")
                       : loadServoProgram(program_file_, p);
  if (r) r = servo_.configure(p);
  if (!r) {
    last_error_ = r.message();
    RTT::log(RTT::Error) << getName() << ": " << last_error_ << RTT::endlog();
    return false;
  }
  last_error_.clear();
  in_ = ServoInput();
  out_ = ServoOutput();
  command_out_.setDataSample(out_.command);
  phase_out_.setDataSample(out_.phase);
  current_phase_.store(servo_.phaseIndex());
  return true;
}

bool ServoComponent::startHook() {
  servo_.reset();
  requested_phase_.store(-1);
  current_phase_.store(servo_.phaseIndex());
  // Only data written after this start counts: no pose, no features yet.
  flange_in_.clear();
  features_in_.clear();
  in_.flange_measured = kNoPose;
  in_.features = ContactFeatures();
  first_cycle_ = true;
  return true;
}

bool ServoComponent::switchPhase(const std::string& name) {
  if (!isConfigured()) return false;
  const int idx = servo_.phaseIndexOf(name.c_str());  // reads the configured program only
  if (idx < 0) return false;
  requested_phase_.store(idx);  // applied by updateHook (the core is not thread-safe)
  return true;
}

int ServoComponent::phaseIndex(const std::string& name) const {
  if (!isConfigured()) return -1;
  return servo_.phaseIndexOf(name.c_str());  // reads the configured program only
}

std::string ServoComponent::phaseName() const {
  if (!isConfigured()) return std::string();
  return servo_.phase(current_phase_.load()).name;
}

void ServoComponent::updateHook() {
  const int req = requested_phase_.exchange(-1);
  if (req >= 0) servo_.requestPhase(req);
  features_in_.read(in_.features, false);        // keeps the last sample when nothing new
  flange_in_.read(in_.flange_measured, false);    // kNoPose until the first sample (the core waits)
  const double now = RTT::os::TimeService::Instance()->secondsSince(0);
  double dt = now - last_time_;
  if (first_cycle_) dt = getPeriod() > 0.0 ? getPeriod() : 1e-3;
  first_cycle_ = false;
  last_time_ = now;
  in_.time_s = now;
  const ServoStatus st = servo_.step(in_, dt, out_);
  last_status_ = static_cast<int>(st);
  current_phase_.store(servo_.phaseIndex());
  if (out_.valid) command_out_.write(out_.command);  // nothing before a valid measured pose
  phase_out_.write(out_.phase);
}

}  // namespace tactile

ORO_CREATE_COMPONENT_LIBRARY()
ORO_LIST_COMPONENT_TYPE(tactile::ServoComponent)
