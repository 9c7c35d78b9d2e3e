// tactile::DeployGuard: checked steps for the deployer scripts (deployments/*.ops).
//
// OCL's deployer (2.10) runs an .ops file statement by statement while parsing
// it; an operation that returns false, or throws, does not stop the script, and
// `deployer -s` fails (exit 255) only when the parser fails. So a deployment
// script records every step here,
//     Guard.step(Robot.configure(), "configure Robot (FRI bridge, fri_bridge.cpf)")
// skips the steps after a failure with
//     if Guard.ok then Guard.step(...)
// and ends at a checkpoint
//     var int checkpoint_name(Guard.verdict())
// whose size hint RTT evaluates while parsing: -1 after a failed step is a
// parse error ("... with an expression leading to a negative number"), which
// stops the script there and makes runScript() false: the deployer exits 255
// (after its normal shutdown: components stopped, cleaned up and unloaded,
// orocos.log closed; at a terminal it first opens its prompt for inspection).
// The failed step is named in the log: "[Guard] deployment step failed: <what>".
//
// The experiment scripts also keep their per-experiment file names here
// (properties), so the shared include scripts (deployments/robot_loop.ops,
// sim_loop.ops) read them: RTT script variables do not cross runScript().
//
// Not on any real-time path: the deployer's own thread calls it while it
// sets the deployment up (ClientThread operations).
#include <rtt/Component.hpp>
#include <rtt/Logger.hpp>
#include <rtt/TaskContext.hpp>
#include <rtt/os/fosi.h>

#include <string>

namespace tactile {

class DeployGuard : public RTT::TaskContext {
 public:
  explicit DeployGuard(const std::string& name) : RTT::TaskContext(name) {
    addProperty("experiment", experiment_).doc("Experiment name (e.g. bent_bar): the report's and the log's name.");
    addProperty("servo_cpf", servo_cpf_).doc("Property file of the Servo (its program_file, controller_mode).");
    addProperty("sim_cpf", sim_cpf_).doc("Property file of the simulated robot (its scene_file, wts_period).");
    addProperty("state_machine_file", osd_file_).doc("The experiment's state machine (.osd), loaded into the Servo.");
    addProperty("state_machine", sm_name_).doc("Its instance name (the RootMachine line of the .osd).");
    addProperty("timeout", timeout_).doc("Longest wall-clock wait (s) for the state machine in the run scripts.");
    addProperty("dry_run", dry_run_)
        .doc("Robot deployments: a bring-up dry run (robot_loop.ops sets the FRI bridge's dry_run before it "
             "starts: the bridge holds the arm, the servo computes and records as if it followed).");
    addProperty("report_file", report_file_).doc("File of the OCL::FileReporting time series (empty: no report).");
    addAttribute("ok", ok_);
    addAttribute("steps", steps_);
    addAttribute("failed_step", failed_step_);
    addOperation("step", &DeployGuard::step, this, RTT::ClientThread)
        .doc("Record one deployment step: logs it (Info) when done is true; when false, logs "
             "'deployment step failed: what' (Error) and clears ok. After a failure, further steps are "
             "not recorded. Returns done.")
        .arg("done", "The step's result (e.g. Robot.configure()).")
        .arg("what", "What the step does, as the operator should read it.");
    addOperation("fail", &DeployGuard::fail, this, RTT::ClientThread)
        .doc("Record a failed step (same as step(false, what)).")
        .arg("what", "What failed.");
    addOperation("verdict", &DeployGuard::verdict, this, RTT::ClientThread)
        .doc("1 while every step succeeded, -1 after a failed one: the size hint of a checkpoint "
             "`var int name(Guard.verdict())`, which ends the script (parse error) after a failure.");
    addOperation("sleep", &DeployGuard::sleep, this, RTT::ClientThread)
        .doc("Sleep (wall clock): waiting loops of the experiment scripts.")
        .arg("s", "Seconds, [0, 10].");
  }

  bool step(bool done, const std::string& what) {
    if (!ok_) return false;  // the script is already failing: only the first failure is reported
    ++steps_;
    if (done) {
      RTT::log(RTT::Info) << "[" << getName() << "] step " << steps_ << " ok: " << what << RTT::endlog();
      return true;
    }
    ok_ = false;
    failed_step_ = what;
    RTT::log(RTT::Error) << "[" << getName() << "] deployment step failed: " << what << RTT::endlog();
    return false;
  }
  bool fail(const std::string& what) { return step(false, what); }
  int verdict() const { return ok_ ? 1 : -1; }
  void sleep(double s) const {
    if (!(s > 0.0 && s <= 10.0)) return;
    TIME_SPEC ts = ticks2timespec(nano2ticks(static_cast<long long>(s * 1e9)));  // RTT's OS layer
    rtos_nanosleep(&ts, nullptr);
  }

 private:
  std::string experiment_, servo_cpf_, sim_cpf_, osd_file_, sm_name_, report_file_;
  double timeout_ = 60.0;
  bool dry_run_ = false;
  bool ok_ = true;
  int steps_ = 0;
  std::string failed_step_;
};

}  // namespace tactile

ORO_CREATE_COMPONENT_LIBRARY()
ORO_LIST_COMPONENT_TYPE(tactile::DeployGuard)
