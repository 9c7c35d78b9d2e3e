#include "tactile_servo_rtt/servo_component.hpp"

#include "tactile_types_rtt/atomic_attribute.hpp"

#include <rtt/Component.hpp>
#include <rtt/Logger.hpp>
#include <rtt/os/TimeService.hpp>

#include "tactile_servo/program_io.hpp"

namespace tactile {

ServoComponent::ServoComponent(const std::string& name)
    : Component(name, PreOperational),
      features_in_("features"),
      flange_in_("flange_pose"),
      wrench_in_("estimated_wrench"),
      robot_in_("robot_state"),
      command_out_("pose_command"),
      phase_out_("phase") {
  addProperty("program_file", program_file_)
      .doc("YAML phase program (controller, safety, phases; see tactile_servo/program_io.hpp). Read by configure().");
  addProperty("controller_mode", controller_mode_)
      .doc("Overrides the program's controller.mode at configure(): '' = the program's, 'proposed' (Eq. 8: the "
           "touch-dependent J^-1 with the DZMP rows), 'baseline' (Li et al., RSS 2013: constant J^-1 with the CoP -> "
           "rotation rows, no DZMP) or 'no_rotation' (ablation: constant diag(1,1,1,0,0,1)), as the headless "
           "runner's scene key `controller`. Set by the deployments' servo_*.cpf.");
  addProperty("period", period_)
      .doc("Servo period (s): dt of the first cycle after start (later cycles use the TimeService). "
           "0 = the activity's period (1 ms without one). In [0, 10].");
  addAtomicAttribute(*provides(), "last_status", last_status_);
  addAttribute("integral", integral_);
  addEventPort(features_in_).doc("Contact features in {s} (from the feature component).");
  addPort(flange_in_).doc("Measured flange pose {g}T{e} (LWR simulator or FRI bridge).");
  addPort(wrench_in_).doc("The arm's estimated external wrench [Fx Fy Fz Tx Ty Tz] ({g} axes; LWR simulator or FRI "
                          "bridge): the force-mismatch watchdog compares its force along z_s with the tactile force. "
                          "Unconnected: that check is off.");
  addPort(robot_in_).doc("The arm side's state (FRI bridge or LWR simulator): while it is not commandable (the KRC "
                         "in monitor mode, low link quality, drives off, a configuration mismatch) the servo holds at "
                         "the measured pose with everything frozen (status waiting_for_robot) and resumes from the "
                         "measured pose; dry_run: the servo runs, the arm is held. Unconnected: always commandable.");
  addPort(command_out_).doc("Desired flange pose {g}T{e} for the Cartesian impedance controller, with the servo status.");
  addPort(phase_out_).doc("Phase program state: index, name, entry time, status.");
  addOperation("switchPhase", &ServoComponent::switchPhase, this, RTT::ClientThread)
      .doc("Switch to the named phase at the next cycle (clears a force-ceiling latch). False for an unknown name.")
      .arg("name", "Phase name as in the program file.");
  addOperation("phaseName", &ServoComponent::phaseName, this, RTT::ClientThread).doc("Name of the current phase.");
  addOperation("phaseIndex", &ServoComponent::phaseIndex, this, RTT::ClientThread)
      .doc("Index of the current phase in the program (-1 before configure()); no string is built, for state "
           "machines that check it every cycle.");
  addOperation("phaseIndexOf", &ServoComponent::phaseIndexOf, this, RTT::ClientThread)
      .doc("Index of the named phase in the configured program, -1 for an unknown name (or before configure()).")
      .arg("name", "Phase name as in the program file.");
  addOperation("controllerMode", &ServoComponent::controllerMode, this, RTT::ClientThread)
      .doc("The controller in use after configure(): 'proposed', 'baseline' or 'no_rotation' ('' before).");
  addOperation("lastError", &ServoComponent::lastError, this, RTT::ClientThread)
      .doc("Message of the last failed configure().");
  addOperation("statusName", &ServoComponent::statusName, this, RTT::ClientThread)
      .doc("The name of last_status (the servo's status of the last cycle), e.g. 'surface_too_curved'. Builds a "
           "string: for a state machine's entry program, not its run program.");
  addOperation("statusText", &ServoComponent::statusText, this, RTT::ClientThread)
      .doc("What last_status means for the operator, in one sentence. Builds a string (as statusName).");
}

ServoComponent::~ServoComponent() {
  stop();
  haltActivity();  // its thread, while the ports exist (component.hpp)
  provides()->removeService("scripting");  // its state machines, while the component is whole
}

bool ServoComponent::configureHook() {
  ServoParams p;
  ConfigResult r = program_file_.empty()
                       ? ConfigResult::failure("program_file is empty: set it to a YAML phase program")
                       : loadServoProgram(program_file_, p);
  if (r) {
    if (!controller_mode_.empty() && !parseControllerMode(controller_mode_, p.mode))
      r = ConfigResult::failure(getName() + ".controller_mode = '" + controller_mode_ +
                                "': must be '' (the program's controller.mode), " + kControllerModeNames);
  }
  // dt of the first cycle: `period`, else the activity period (1 ms without one).
  if (r && !(period_ >= 0.0 && period_ <= 10.0)) r = rangeError("period", period_, "must be in [0, 10] s (0: the activity's)");
  if (r) r = stage_.configure(p, period_ > 0.0 ? period_ : getPeriod() > 0.0 ? getPeriod() : 1e-3);
  if (!verdict(r, last_error_)) return false;
  mode_in_use_ = toString(p.mode);
  features_ = ContactFeatures();
  out_ = ServoOutput();
  command_out_.setDataSample(out_.command);
  phase_out_.setDataSample(out_.phase);
  current_phase_.store(stage_.servo().phaseIndex());
  return true;
}

bool ServoComponent::startHook() {
  stage_.reset();
  features_ = ContactFeatures();
  requested_phase_.store(-1);
  current_phase_.store(stage_.servo().phaseIndex());
  // Only data written after this start counts: no pose, no features yet.
  flange_in_.clear();
  wrench_in_.clear();
  robot_in_.clear();
  features_in_.clear();
  return true;
}

bool ServoComponent::switchPhase(const std::string& name) {
  if (!isConfigured()) return false;
  const int idx = stage_.servo().phaseIndexOf(name.c_str());  // reads the configured program only
  if (idx < 0) return false;
  requested_phase_.store(idx);  // applied by updateHook (the core is not thread-safe)
  return true;
}

int ServoComponent::phaseIndex() const { return isConfigured() ? current_phase_.load() : -1; }

int ServoComponent::phaseIndexOf(const std::string& name) const {
  return isConfigured() ? stage_.servo().phaseIndexOf(name.c_str()) : -1;  // reads the configured program only
}

std::string ServoComponent::statusName() const {
  return toString(static_cast<ServoStatus>(last_status_.load()));
}

std::string ServoComponent::statusText() const {
  return explain(static_cast<ServoStatus>(last_status_.load()));
}

std::string ServoComponent::phaseName() const {
  if (!isConfigured()) return std::string();
  return stage_.servo().phase(current_phase_.load()).name;
}

void ServoComponent::updateHook() {
  const HookScope hook(*this);  // the other hooks' writes before this update (component.hpp)
  const int req = requested_phase_.exchange(-1);
  if (req >= 0) stage_.requestPhase(req);
  features_in_.read(features_, false);  // keeps the last sample when nothing new
  if (flange_in_.read(pose_, false) != RTT::NoData) stage_.setMeasuredPose(pose_);
  if (wrench_in_.read(wrench_, false) != RTT::NoData) stage_.setEstimatedWrench(wrench_);
  if (robot_in_.read(robot_, false) != RTT::NoData) stage_.setRobotState(robot_);
  const double now = RTT::os::TimeService::Instance()->secondsSince(0);
  ServoStatus st = ServoStatus::NotConfigured;
  const bool command = stage_.step(now, features_, out_, st);  // holds (no command) until a valid pose arrived
  record(last_status_, static_cast<int>(st));
  current_phase_.store(stage_.servo().phaseIndex());
  if (command) command_out_.write(out_.command);
  phase_out_.write(out_.phase);
  // The integrator's view (attribute `integral`): copied in place, the core's state is not touched.
  const Vec6& integral = stage_.servo().controlLaw().integral();
  for (std::size_t i = 0; i < 6; ++i) integral_[i] = integral[static_cast<Eigen::Index>(i)];
}

}  // namespace tactile

ORO_CREATE_COMPONENT_LIBRARY()
ORO_LIST_COMPONENT_TYPE(tactile::ServoComponent)
