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
// The end of a run is not such a checkpoint: a run that ends FAILED (its state
// machine, a fault) is an outcome, reported as cleanly as a passing one. The
// finish scripts (deployments/experiment_finish.ops, sim_finish.ops) record it
//     Guard.outcome(state == "FINISHED", "the state machine ... ended in ...")
// which logs "[Guard] run FINISHED: <what>" or "[Guard] run FAILED: <what>"
// and leaves ok alone (the reporter is still stopped and its file closed),
// and the entry scripts end with the verdict
//     var int experiment_finished = Guard.finish()
// an ordinary assignment: finish() logs "[Guard] verdict: FINISHED: <what>"
// or "[Guard] verdict: FAILED: <what>" (a failed run's outcome, or
// "deployment step failed: <step>") and returns 0 or 255. After a failure it
// also makes 255 the deployer's exit status: the deployer (OCL 2.10) returns 0
// for any script that parsed, so finish() registers an exit handler that ends
// the process with 255 once main() has returned, i.e. after the deployer's
// normal shutdown (components stopped, cleaned up and unloaded, orocos.log
// closed); the libraries of components are never unloaded before that.
//
// The experiment's files come from the experiment registry (experiments.yaml
// at the repository root, `registry_file`): select(name) reads its entry and
// fills the properties the shared include scripts read (deployments/sim_loop.ops,
// robot_loop.ops, experiment_start.ops, ...): RTT script variables do not
// cross runScript(). The name reaches an unattended run through the
// environment (TACTILE_EXPERIMENT, read once when the Guard is constructed)
// and an operator at the prompt through Guard.select("bent_bar"). In the
// deployer's XML form (robot.xml, sim.xml) configure() selects it and hands
// the entry to its peers.
//
// Not on any real-time path: the deployer's own thread calls it while it
// sets the deployment up (ClientThread operations); select() reads files.
#include <rtt/Component.hpp>
#include <rtt/Logger.hpp>
#include <rtt/Service.hpp>
#include <rtt/TaskContext.hpp>
#include <rtt/internal/DataSource.hpp>
#include <rtt/scripting/Scripting.hpp>
#include <rtt/os/fosi.h>
#include <yaml-cpp/yaml.h>

#include "tactile_config/registry.hpp"

#include <climits>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace tactile {

namespace {

// The keys of an experiment entry (experiments.yaml's header documents them).
std::string joined(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : ", ") + (s.empty() ? std::string("''") : s);
  return out;
}

bool fileExists(const std::string& path) { return std::ifstream(path).good(); }

// The deployer's exit status after a failed run or step (finish()).
constexpr int kFailedExit = 255;

// Registered with std::atexit by finish(): runs when the deployer's main() has
// returned, after its shutdown, and ends the process with kFailedExit instead
// of the deployer's own 0 (the remaining exit handlers are static destructors).
void exitFailed() {
  std::fflush(nullptr);
  std::_Exit(kFailedExit);
}

// A state-machine parameter as declared in an .osd: `param double explore_time`.
struct OsdParam {
  std::string type, name;
};

// The instance `instance` of an .osd file: its RootMachine line names the
// StateMachine type, whose `param` lines are the parameters. Empty type: no such instance.
bool osdParams(const std::string& file, const std::string& instance, std::string& type,
               std::vector<OsdParam>& params, std::vector<std::string>& instances) {
  std::ifstream in(file);
  if (!in) return false;
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  static const std::regex root(R"(^\s*RootMachine\s+(\w+)\s+(\w+))", std::regex::multiline);
  type.clear();
  for (std::sregex_iterator it(text.begin(), text.end(), root), e; it != e; ++it) {
    instances.push_back((*it)[2]);
    if ((*it)[2] == instance) type = (*it)[1];
  }
  if (type.empty()) return true;
  const std::regex machine("^\\s*StateMachine\\s+" + type + "\\b", std::regex::multiline);
  std::smatch m;
  if (!std::regex_search(text, m, machine)) return true;
  // Its body up to the next StateMachine / RootMachine line.
  const std::string rest = m.suffix().str();
  static const std::regex next(R"(^\s*(StateMachine|RootMachine)\s)", std::regex::multiline);
  std::smatch n;
  const std::string body = std::regex_search(rest, n, next) ? rest.substr(0, n.position(0)) : rest;
  static const std::regex param(R"(^\s*param\s+(\w+)\s+(\w+))", std::regex::multiline);
  for (std::sregex_iterator it(body.begin(), body.end(), param), e; it != e; ++it)
    params.push_back({(*it)[1], (*it)[2]});
  return true;
}

}  // namespace

class DeployGuard : public RTT::TaskContext {
 public:
  explicit DeployGuard(const std::string& name) : RTT::TaskContext(name) {
    if (const char* env = std::getenv("TACTILE_EXPERIMENT")) experiment_ = env;
    addProperty("registry_file", registry_file_)
        .doc("The experiment registry (YAML, experiments: <name>: {scene, program, controller, state_machine, "
             "timeout_s, robot, metrics}); relative to the deployer's working directory (deployments/). Its "
             "paths are relative to its own directory; select() makes them relative to the working directory.");
    addProperty("experiment", experiment_)
        .doc("Experiment name, a key of registry_file's experiments (e.g. bent_bar). Unattended runs: from "
             "the environment variable TACTILE_EXPERIMENT, read when the Guard is constructed; the entry "
             "scripts then call select(experiment). At the prompt: Guard.select(\"bent_bar\") sets it.");
    addProperty("program_file", program_file_)
        .doc("The Servo's phase program (YAML), from the registry's `program` (select()).");
    addProperty("controller_mode", controller_mode_)
        .doc("The Servo's controller_mode from the registry's `controller`: '' (the program's), proposed, "
             "baseline, no_rotation (select()).");
    addProperty("scene_file", scene_file_)
        .doc("The simulated world (params/scenes/*.yaml) from the registry's `scene` (select()); the simulated "
             "arm, sensor and clock read it (sim_loop.ops; sim.xml: configure() gives it to its peers).");
    addProperty("servo_cpf", servo_cpf_)
        .doc("Optional: a Servo property file read after the registry's program and controller, replacing "
             "them (tests' own programs). Empty: none.");
    addProperty("sim_cpf", sim_cpf_)
        .doc("Optional: a property file of the simulated robot read after scene_file, replacing it (tests' "
             "own scenes). Empty: none.");
    addProperty("state_machine_file", osd_file_)
        .doc("The experiment's state machine (.osd), loaded into the Servo (registry: state_machine.file).");
    addProperty("state_machine", sm_name_)
        .doc("Its instance name (the RootMachine line of the .osd; registry: state_machine.name).");
    addProperty("timeout", timeout_)
        .doc("Longest wall-clock wait (s) for the end of the run in the run scripts (registry: timeout_s).");
    addProperty("robot", robot_).doc("The registry's `robot`: true when the experiment also runs on the real arm.");
    addProperty("dry_run", dry_run_)
        .doc("Robot deployments: a bring-up dry run (robot_loop.ops sets the FRI bridge's dry_run before it "
             "starts: the bridge holds the arm, the servo computes and records as if it followed).");
    addProperty("report_suffix", report_suffix_)
        .doc("select() sets report_file to <experiment> + report_suffix (default _sim.dat; the robot XML: "
             "_robot.dat).");
    addProperty("report_file", report_file_)
        .doc("File of the OCL::FileReporting time series (empty: no report); select() sets <experiment> + "
             "report_suffix, the robot and ROS entry scripts their own name after it.");
    addAttribute("ok", ok_);
    addAttribute("steps", steps_);
    addAttribute("failed_step", failed_step_);
    addAttribute("select_error", select_error_);
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
             "`var int name(Guard.verdict())`, which ends the script (parse error) after a failure. "
             "Set-up scripts only: a run's end is outcome() and finish().");
    addOperation("outcome", &DeployGuard::outcome, this, RTT::ClientThread)
        .doc("Record the run's outcome (the finish scripts, once the experiment's state machine ended): logs "
             "'run FINISHED: what' (Info) or 'run FAILED: what' (Error). Not a deployment step: ok stays as it "
             "is, so the steps after it (stopping the reporter) run and are logged. Returns finished.")
        .arg("finished", "True when the run ended as the experiment expects (its state machine in FINISHED).")
        .arg("what", "How it ended, as the operator should read it (the machine's state, the servo's status).");
    addOperation("finish", &DeployGuard::finish, this, RTT::ClientThread)
        .doc("The verdict at the end of an entry script, `var int name = Guard.finish()` (no parse error "
             "either way): logs 'verdict: FINISHED: ...' or 'verdict: FAILED: ...' (the run's outcome or the "
             "failed step) and returns 0, or 255 after a failed run or step, which then becomes the deployer's "
             "exit status (after its normal shutdown).");
    addOperation("sleep", &DeployGuard::sleep, this, RTT::ClientThread)
        .doc("Sleep (wall clock): waiting loops of the experiment scripts.")
        .arg("s", "Seconds, [0, 10].");
    addOperation("select", &DeployGuard::select, this, RTT::ClientThread)
        .doc("Read the experiment `name` from registry_file and fill experiment, program_file, "
             "controller_mode, scene_file, state_machine_file, state_machine, timeout, robot and "
             "report_file (<name> + report_suffix); checks that its files exist, its controller and that every "
             "state-machine param is a `param` of the named RootMachine in its .osd. False (nothing "
             "changed) with an error naming the file, the key and the valid values (logged, and in the "
             "attribute select_error). Unattended: TACTILE_EXPERIMENT=<name>; at the prompt: "
             "Guard.select(\"bent_bar\") before runScript(\"robot.ops\").")
        .arg("name", "Experiment name (a key of the registry's experiments).");
    addOperation("experiments", &DeployGuard::experiments, this, RTT::ClientThread)
        .doc("The experiment names of registry_file, space separated (empty when it cannot be read).");
    addOperation("setStateMachineParams", &DeployGuard::setStateMachineParams, this, RTT::ClientThread)
        .doc("Set the selected experiment's state-machine params (registry: state_machine.params) on the "
             "state machine `state_machine` loaded into the peer `component` (addPeer(\"Guard\", component) "
             "first). Call after activate() (which sets the RootMachine line's values) and before start(). "
             "True when nothing is selected (no params). False, naming the param, when one is not an "
             "attribute of the loaded machine or its value does not fit its type.")
        .arg("component", "The peer that runs the state machine (Servo).");
  }

  // The deployer's XML form (deployments/robot.xml, sim.xml: no script):
  // configure() selects `experiment` (TACTILE_EXPERIMENT) and hands the entry
  // to its peers (the XML's Peers list): a peer with
  // program_file and controller_mode (the Servo) gets both and, when it has
  // the scripting service, the state machine loaded (not activated); a peer
  // with scene_file gets the scene (and, with program_file alone, the
  // simulated arm, the program: its pad's mount); one with ReportFile (OCL::FileReporting)
  // the report file. The peers must come after the Guard in the XML (they are
  // configured in order). False, logged, on an unknown entry or a failed load.
  bool configureHook() override {
    if (!select(experiment_)) return false;
    for (const std::string& name : getPeerList()) {
      RTT::TaskContext* peer = getPeer(name);
      RTT::PropertyBag* props = peer->properties();
      auto* program = props->getPropertyType<std::string>("program_file");
      auto* mode = props->getPropertyType<std::string>("controller_mode");
      if (program && mode) {
        program->set(program_file_);
        mode->set(controller_mode_);
        log(name + ".program_file = " + program_file_ + ", controller_mode '" + controller_mode_ + "'");
        if (peer->provides()->hasService("scripting")) {
          auto scripting = peer->getProvider<RTT::Scripting>("scripting");
          // The deployer attaches the peer's activity in the peer's own step,
          // after this one: silence the scripting service's zero-period
          // warning for this load only.
          auto* warn = peer->provides("scripting")->properties()->getPropertyType<bool>("ZeroPeriodWarning");
          const bool warn_was = warn ? warn->get() : true;
          if (warn) warn->set(false);
          const bool loaded = scripting && scripting->loadStateMachines(osd_file_);
          if (warn) warn->set(warn_was);
          if (!loaded) {
            RTT::log(RTT::Error) << "[" << getName() << "] " << name << ": cannot load the state machine file "
                                 << osd_file_ << " (registry: state_machine.file)" << RTT::endlog();
            return false;
          }
          log(name + ": state machine " + sm_name_ + " loaded from " + osd_file_ + " (not activated)");
        }
      }
      if (auto* scene = props->getPropertyType<std::string>("scene_file")) {
        scene->set(scene_file_);
        log(name + ".scene_file = " + scene_file_);
        if (program && !mode) {  // the simulated arm: its pad mounted as the program says
          program->set(program_file_);
          log(name + ".program_file = " + program_file_);
        }
      }
      if (auto* report = props->getPropertyType<std::string>("ReportFile")) {
        report->set(report_file_);
        log(name + ".ReportFile = " + report_file_);
      }
    }
    return true;
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

  bool outcome(bool finished, const std::string& what) {
    run_finished_ = finished;
    run_what_ = what;
    RTT::log(finished ? RTT::Info : RTT::Error)
        << "[" << getName() << "] run " << (finished ? "FINISHED: " : "FAILED: ") << what << RTT::endlog();
    return finished;
  }

  int finish() {
    const bool passed = ok_ && run_finished_;
    const std::string what = !ok_ ? "deployment step failed: " + failed_step_
                             : !run_what_.empty() ? run_what_
                                                  : "every deployment step succeeded (" + std::to_string(steps_) + ")";
    const std::string line = std::string(passed ? "FINISHED: " : "FAILED: ") + what;
    if (line != verdict_logged_) {  // an entry script and the finish script it runs may both end with finish()
      verdict_logged_ = line;
      RTT::log(passed ? RTT::Info : RTT::Error) << "[" << getName() << "] verdict: " << line << " (deployer exit "
                                                << (passed ? 0 : kFailedExit) << ")" << RTT::endlog();
    }
    if (!passed && !exit_registered_) exit_registered_ = std::atexit(&exitFailed) == 0;
    return passed ? 0 : kFailedExit;
  }
  void sleep(double s) const {
    if (!(s > 0.0 && s <= 10.0)) return;
    TIME_SPEC ts = ticks2timespec(nano2ticks(static_cast<long long>(s * 1e9)));  // RTT's OS layer
    rtos_nanosleep(&ts, nullptr);
  }

  std::string experiments() const {
    std::string out;
    try {
      const YAML::Node all = YAML::LoadFile(registry_file_)["experiments"];
      if (!all.IsMap()) return "";
      for (const auto& kv : all) out += (out.empty() ? "" : " ") + kv.first.as<std::string>();
    } catch (const YAML::Exception&) {
      return "";
    }
    return out;
  }

  bool select(const std::string& name) {
    select_error_.clear();
    const std::string err = readEntry(name);
    if (!err.empty()) {
      select_error_ = err;
      RTT::log(RTT::Error) << "[" << getName() << "] select(\"" << name << "\"): " << err << RTT::endlog();
      return false;
    }
    RTT::log(RTT::Info) << "[" << getName() << "] experiment " << experiment_ << " (" << registry_file_
                        << "): program " << program_file_ << ", controller '" << controller_mode_ << "', scene "
                        << scene_file_ << ", state machine " << sm_name_ << " in " << osd_file_ << ", timeout "
                        << timeout_ << " s" << RTT::endlog();
    return true;
  }

  bool setStateMachineParams(const std::string& component) {
    if (params_.empty()) return true;
    RTT::TaskContext* peer = getPeer(component);
    if (!peer) return paramError("no peer " + component + " (addPeer(\"" + getName() + "\", \"" + component + "\") first)");
    RTT::Service::shared_ptr sm = peer->provides()->getService(sm_name_);
    if (!sm) return paramError(component + " has no state machine " + sm_name_ + " (loaded from " + osd_file_ + "?)");
    const std::string where = registry_file_ + ": experiments." + experiment_ + ".state_machine.params.";
    for (const auto& p : params_) {
      RTT::base::AttributeBase* a = sm->getAttribute(p.name);
      if (!a) return paramError(where + p.name + ": " + sm_name_ + " has no such param");
      RTT::base::DataSourceBase::shared_ptr ds = a->getDataSource();
      if (p.type == "double") {
        auto* d = RTT::internal::AssignableDataSource<double>::narrow(ds.get());
        if (!d) return paramError(where + p.name + ": not a double in " + sm_name_);
        d->set(p.number);
      } else if (p.type == "string") {
        auto* d = RTT::internal::AssignableDataSource<std::string>::narrow(ds.get());
        if (!d) return paramError(where + p.name + ": not a string in " + sm_name_);
        d->set(p.value);
      } else if (p.type == "int") {
        auto* d = RTT::internal::AssignableDataSource<int>::narrow(ds.get());
        if (!d) return paramError(where + p.name + ": not an int in " + sm_name_);
        d->set(static_cast<int>(p.number));
      } else if (p.type == "bool") {
        auto* d = RTT::internal::AssignableDataSource<bool>::narrow(ds.get());
        if (!d) return paramError(where + p.name + ": not a bool in " + sm_name_);
        d->set(p.number != 0.0);
      } else {
        return paramError(where + p.name + ": param type " + p.type + " not supported (double, int, bool, string)");
      }
      RTT::log(RTT::Info) << "[" << getName() << "] " << component << "." << sm_name_ << "." << p.name << " = "
                          << p.value << " (" << registry_file_ << ")" << RTT::endlog();
    }
    return true;
  }

 private:
  struct Param {
    std::string type, name, value;  // value as written in the registry (strings, the log)
    double number = 0.0;            // double, int and bool params, checked by select()
  };

  void log(const std::string& what) const {
    RTT::log(RTT::Info) << "[" << getName() << "] " << what << RTT::endlog();
  }

  bool paramError(const std::string& what) {
    RTT::log(RTT::Error) << "[" << getName() << "] setStateMachineParams: " << what << RTT::endlog();
    return false;
  }

  // A machine that declares `param double run_time` (the run's length, as
  // the headless run's: timed_phase_experiment.osd) gets the scene's
  // `duration` unless the entry's params give it. "" or the error.
  static std::string sceneDurationParam(const std::string& key, const std::string& scene_file,
                                        const std::vector<OsdParam>& declared, std::vector<Param>& params) {
    bool wants = false;
    for (const auto& d : declared) wants = wants || (d.name == "run_time" && d.type == "double");
    for (const auto& p : params) wants = wants && p.name != "run_time";
    if (!wants) return "";
    double duration = 0.0;
    try {
      const YAML::Node d = YAML::LoadFile(scene_file)["duration"];
      if (!d) return key + "scene: " + scene_file + " has no `duration` (s, > 0) for the state machine's run_time";
      duration = d.as<double>();
    } catch (const YAML::Exception& ex) {
      return key + "scene: " + scene_file + ": duration: " + ex.what() + " (valid: s, > 0)";
    }
    if (!(duration > 0.0))
      return key + "scene: " + scene_file + ": duration: " + std::to_string(duration) + " (valid: s, > 0)";
    std::ostringstream v;
    v << duration;
    Param p{"double", "run_time", v.str()};
    p.number = duration;
    params.push_back(p);
    return "";
  }

  static std::string canonical(const std::string& path) {
    char buf[PATH_MAX];
    return ::realpath(path.c_str(), buf) ? std::string(buf) : path;
  }

  // Registry paths are relative to the registry's directory; the deployer's
  // working directory is deployments/: prefix the registry's directory.
  std::string resolved(const std::string& path) const {
    if (path.empty() || path[0] == '/') return path;
    const auto slash = registry_file_.find_last_of('/');
    return slash == std::string::npos ? path : registry_file_.substr(0, slash + 1) + path;
  }

  // The entry's state_machine.params, each a declared param of the machine
  // (`type` in `osd`) and of its declared type, into `params`. "" or the error.
  static std::string entryParams(const YAML::Node& sm, const std::string& key, const std::string& type,
                                 const std::string& osd, const std::vector<OsdParam>& declared,
                                 std::vector<Param>& params) {
    std::vector<std::string> declared_names;
    for (const auto& d : declared) declared_names.push_back(d.name);
    const YAML::Node ps = sm["params"];
    if (!ps) return "";
    if (!ps.IsMap()) return key + "state_machine.params: not a map (params: " + joined(declared_names) + ")";
    for (const auto& kv : ps) {
      const std::string p = kv.first.as<std::string>();
      const OsdParam* d = nullptr;
      for (const auto& x : declared) d = (x.name == p) ? &x : d;
      if (!d)
        return key + "state_machine.params." + p + ": not a param of " + type + " in " + osd +
               " (params: " + joined(declared_names) + ")";
      Param param{d->type, p, kv.second.as<std::string>()};
      try {
        if (d->type == "double") param.number = kv.second.as<double>();
        if (d->type == "int") param.number = kv.second.as<int>();
        if (d->type == "bool") param.number = kv.second.as<bool>() ? 1.0 : 0.0;
      } catch (const YAML::Exception&) {
        return key + "state_machine.params." + p + ": '" + param.value + "' is not a " + d->type + " (param " +
               d->type + " " + p + " of " + type + ")";
      }
      params.push_back(param);
    }
    return "";
  }

  // The registry's entry `name` (the registry's own errors: unreadable, no
  // experiments map, no such entry, not a map) into `err`, else "".
  YAML::Node registryEntry(const std::string& name, std::string& err) const {
    const std::string& f = registry_file_;
    YAML::Node root;
    try {
      root = YAML::LoadFile(f);
    } catch (const YAML::Exception& ex) {
      err = f + ": cannot read the experiment registry (registry_file): " + ex.what();
      return {};
    }
    const YAML::Node all = root["experiments"];
    if (!all || !all.IsMap()) {
      err = f + ": experiments: missing or not a map of experiment entries";
      return {};
    }
    std::vector<std::string> names;
    for (const auto& kv : all) names.push_back(kv.first.as<std::string>());
    const YAML::Node e = all[name];
    if (name.empty())
      err = f + ": no experiment selected (TACTILE_EXPERIMENT unset or Guard.select(\"\")); experiments: " +
            joined(names);
    else if (!e)
      err = f + ": experiments." + name + ": no such experiment (experiments: " + joined(names) + ")";
    else if (!e.IsMap())
      err = f + ": experiments." + name + ": not a map";
    return e;
  }

  // Reads and checks entry `name`; on success sets the properties and returns
  // "", else the error (file: key: what, valid values) and changes nothing.
  std::string readEntry(const std::string& name) {
    std::string entry_err;
    const YAML::Node e = registryEntry(name, entry_err);
    if (!entry_err.empty()) return entry_err;
    const std::string key = registry_file_ + ": experiments." + name + ".";
    try {
      config::ExperimentEntry entry;
      const ConfigResult read = config::readExperimentEntry(e, config::Where{registry_file_, "experiments." + name}, entry);
      if (!read) return read.message();
      const std::string& scene = entry.scene;
      const std::string& program = entry.program;
      const std::string& controller = entry.controller;
      const double timeout = entry.timeout_s;
      const bool robot = entry.robot;
      const YAML::Node sm = e["state_machine"];
      const std::string osd = resolved(entry.sm_file);
      const std::string instance = entry.sm_name;
      const std::vector<std::pair<std::string, std::string>> files = {
          {"scene", resolved(scene)}, {"program", resolved(program)}, {"state_machine.file", osd}};
      for (const auto& [k, path] : files)
        if (!fileExists(path)) return key + k + ": no such file " + path;
      std::string type;
      std::vector<OsdParam> declared;
      std::vector<std::string> instances;
      osdParams(osd, instance, type, declared, instances);
      if (type.empty())
        return key + "state_machine.name: " + instance + " is not a RootMachine of " + osd +
               " (RootMachines: " + joined(instances) + ")";
      std::vector<Param> params;
      if (std::string err = entryParams(sm, key, type, osd, declared, params); !err.empty()) return err;
      const std::string derived = sceneDurationParam(key, resolved(scene), declared, params);
      if (!derived.empty()) return derived;
      // Checked: take it.
      experiment_ = name;
      scene_file_ = resolved(scene);
      program_file_ = resolved(program);
      controller_mode_ = controller;
      osd_file_ = osd;
      sm_name_ = instance;
      timeout_ = timeout;
      robot_ = robot;
      report_file_ = name + report_suffix_;
      params_ = params;
    } catch (const YAML::Exception& ex) {
      return key.substr(0, key.size() - 1) + ": " + ex.what();
    }
    return "";
  }

  std::string registry_file_ = "../experiments.yaml";
  std::string experiment_, program_file_, controller_mode_, scene_file_;
  std::string servo_cpf_, sim_cpf_, osd_file_, sm_name_, report_file_, report_suffix_ = "_sim.dat";
  double timeout_ = 60.0;
  bool robot_ = false;
  bool dry_run_ = false;
  bool ok_ = true;
  int steps_ = 0;
  std::string failed_step_, select_error_;
  bool run_finished_ = true;  // outcome(): the run ended as expected (true until a run reports otherwise)
  std::string run_what_, verdict_logged_;
  bool exit_registered_ = false;
  std::vector<Param> params_;
};

}  // namespace tactile

ORO_CREATE_COMPONENT_LIBRARY()
ORO_LIST_COMPONENT_TYPE(tactile::DeployGuard)
