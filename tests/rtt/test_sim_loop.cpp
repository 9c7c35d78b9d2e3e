// One loop, two hosts: the RTT sim deployment (tactile::SimClock executing
// Robot = tactile::LwrSimComponent, Sensor = tactile::WtsSimComponent,
// Features = tactile::FeatureComponent, Servo = tactile::ServoComponent as its
// slaves, wired as deployments/sim_loop.ops does) against the headless runner
// (tactile_sim run) on every shipped scene, full duration, same seed:
//  * the pose command of every servo cycle (a BUFFER connection on
//    Servo.pose_command) equals the runner's to 1e-12 (position m, quaternion);
//  * the rows rebuilt from the deployment's ports (features, phase, pose
//    command, the arm's ground truth) give the runner's summary
//    (tactile::sim::computeSummary on both), and the clock ends the run with
//    the runner's status.
#include <gtest/gtest.h>

#include <rtt/Activity.hpp>
#include <rtt/Attribute.hpp>
#include <rtt/ConnPolicy.hpp>
#include <rtt/InputPort.hpp>
#include <rtt/TaskContext.hpp>
#include <rtt/extras/SlaveActivity.hpp>
#include <rtt/os/TimeService.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <tuple>
#include <cmath>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "alloc_counter.hpp"
#include "tactile_config/registry.hpp"
#include "tactile_servo/program_io.hpp"
#include "support/rtt_environment.hpp"
#include "tactile_features_rtt/feature_component.hpp"
#include "tactile_servo_rtt/servo_component.hpp"
#include "tactile_sim_runner/loop.hpp"
#include "tactile_sim_runner/runner.hpp"
#include "tactile_sim_faults/sensor_faults.hpp"
#include "tactile_sim_rtt/lwr_sim_component.hpp"
#include "tactile_sim_rtt/sim_clock.hpp"
#include "tactile_sim_rtt/wts_sim_component.hpp"
#include "temp_file.hpp"
#include "tactile_types_rtt/atomic_attribute.hpp"

namespace {

using namespace tactile;

const auto* const env = ::testing::AddGlobalTestEnvironment(new test::RttEnvironment(test::Clock::System));

const std::string kScenes = TACTILE_SCENE_DIR "/";

/// What the deployment produced, captured through buffer connections.
struct Recording {
  std::vector<PoseCommand> commands;
  std::vector<PhaseState> phases;
  std::vector<ContactFeatures> features;
  std::vector<SimTruth> truths;
  std::string status;
  int exit_code = -1;
  int ticks = 0;
};

template <typename T>
void drain(RTT::InputPort<T>& port, std::vector<T>& out) {
  T v;
  while (port.read(v, false) == RTT::NewData) out.push_back(v);
}

/// The sim deployment in-process, as deployments/sim_loop.ops wires it; the
/// scene's controller mode is written into a temporary program file.
Recording runDeployment(const std::string& scene_file, const std::string& program_file, double servo_period) {
  Recording rec;
  SimClock clock("Clock");
  LwrSimComponent robot("Robot");
  WtsSimComponent sensor("Sensor");
  FeatureComponent features("Features");
  ServoComponent servo("Servo");
  clock.setActivity(new RTT::Activity(ORO_SCHED_OTHER, 0, 0.0));
  for (RTT::TaskContext* s : std::initializer_list<RTT::TaskContext*>{&robot, &sensor, &features, &servo}) {
    EXPECT_TRUE(s->setActivity(new RTT::extras::SlaveActivity(clock.getActivity())));
    clock.addPeer(s);
  }
  robot.properties()->getPropertyType<std::string>("scene_file")->set(scene_file);
  robot.properties()->getPropertyType<std::string>("program_file")->set(program_file);
  sensor.properties()->getPropertyType<std::string>("scene_file")->set(scene_file);
  clock.properties()->getPropertyType<std::string>("scene_file")->set(scene_file);
  features.properties()->getPropertyType<std::string>("param_file")->set(TACTILE_SOURCE_DIR
                                                                          "/params/sensors/wts0614.yaml");
  servo.properties()->getPropertyType<std::string>("program_file")->set(program_file);
  servo.properties()->getPropertyType<double>("period")->set(servo_period);

  const RTT::ConnPolicy data = RTT::ConnPolicy::data(RTT::ConnPolicy::LOCK_FREE);
  auto connect = [&](RTT::TaskContext& a, const char* out, RTT::TaskContext& b, const char* in) {
    EXPECT_TRUE(a.ports()->getPort(out)->connectTo(b.ports()->getPort(in), data)) << out << " -> " << in;
  };
  connect(robot, "taxel_forces", sensor, "taxel_forces");
  connect(sensor, "raw_frame", features, "raw_frame");
  connect(features, "features", servo, "features");
  connect(robot, "flange_pose", servo, "flange_pose");
  connect(robot, "estimated_wrench", servo, "estimated_wrench");  // the force-mismatch watchdog, as the runner
  connect(servo, "pose_command", robot, "pose_command");

  // Recorders (buffers large enough for a whole run: nothing is dropped).
  RTT::InputPort<PoseCommand> cmd_in("cmd_in");
  RTT::InputPort<PhaseState> phase_in("phase_in");
  RTT::InputPort<ContactFeatures> feat_in("feat_in");
  RTT::InputPort<SimTruth> truth_in("truth_in");
  RTT::TaskContext io("io");
  io.ports()->addPort(cmd_in);
  io.ports()->addPort(phase_in);
  io.ports()->addPort(feat_in);
  io.ports()->addPort(truth_in);
  EXPECT_TRUE(servo.ports()->getPort("pose_command")->connectTo(&cmd_in, RTT::ConnPolicy::buffer(20000)));
  EXPECT_TRUE(servo.ports()->getPort("phase")->connectTo(&phase_in, RTT::ConnPolicy::buffer(20000)));
  EXPECT_TRUE(features.ports()->getPort("features")->connectTo(&feat_in, RTT::ConnPolicy::buffer(20000)));
  EXPECT_TRUE(robot.ports()->getPort("truth")->connectTo(&truth_in, RTT::ConnPolicy::buffer(70000)));

  EXPECT_TRUE(robot.configure()) << robot.lastError();
  EXPECT_TRUE(sensor.configure()) << sensor.lastError();
  EXPECT_TRUE(features.configure()) << features.lastError();
  EXPECT_TRUE(servo.configure()) << servo.lastError();
  EXPECT_TRUE(clock.configure()) << clock.lastError();
  EXPECT_TRUE(sensor.start() && features.start() && servo.start() && robot.start());
  drain(truth_in, rec.truths);  // the arm's initial state
  EXPECT_TRUE(clock.start());
  auto finished = [&] { return tactile::readAttribute<bool>(*clock.provides(), "finished"); };
  // The truth buffer (one sample per physics tick) is drained while the clock runs.
  const auto t0 = std::chrono::steady_clock::now();
  while (!finished()) {
    drain(truth_in, rec.truths);
    std::this_thread::sleep_for(std::chrono::microseconds(200));
    if (std::chrono::steady_clock::now() - t0 > std::chrono::seconds(300)) {
      ADD_FAILURE() << "the clock did not finish in 300 s";
      break;
    }
  }
  clock.stop();
  drain(truth_in, rec.truths);
  drain(cmd_in, rec.commands);
  drain(phase_in, rec.phases);
  drain(feat_in, rec.features);
  rec.status = tactile::readAttribute<std::string>(*clock.provides(), "status");
  rec.exit_code = tactile::readAttribute<int>(*clock.provides(), "exit_code");
  rec.ticks = tactile::readAttribute<int>(*clock.provides(), "ticks");
  servo.stop();
  features.stop();
  sensor.stop();
  robot.stop();
  RTT::os::TimeService::Instance()->enableSystemClock(true);
  return rec;
}

/// The runner's rows rebuilt from the deployment's recordings: the schedule
/// says on which tick each features sample was written (a features tick after
/// a new raw frame) and which truth sample a servo cycle saw (the state after
/// the previous physics tick: sample i on tick i). The scene's stream faults
/// (stale, disconnect) withhold the frames acquired in their windows.
bool rowsFromRecording(const sim::Scene& sc, const Recording& rec, sim::RunResult& out, std::string& why) {
  sim::Schedule sched;
  if (!sched.configure(sc.rates, sc.duration)) return false;
  sim::SensorFaultSchedule stream;
  if (!stream.configure(sc.faults, sc.calibration.rows, sc.calibration.cols)) return false;
  auto delivered = [&stream](double t) {
    RawTactileFrame probe;
    probe.time_s = t;
    return stream.stream(probe) != sim::FaultAction::Withhold;
  };
  std::size_t fi = 0, ci = 0, pi = 0;
  bool new_raw = false;
  // With a WTS transfer delay a frame reaches the features on the first tick
  // at or after its acquisition + delay (TaxelResponse::deliver).
  const double delay = sc.sensor_effects.wts_transfer_delay_s;
  std::vector<double> in_flight;
  ContactFeatures feats;  // NotConfigured until the first extraction
  Pose cmd;
  bool have_cmd = false;
  for (long i = 0; pi < rec.phases.size(); ++i, sched.advance()) {
    const sim::StageFires f = sched.fires();
    if (delay > 0.0) {
      if (f.wts && delivered(sched.timeOf(i))) in_flight.push_back(sched.timeOf(i));
      while (!in_flight.empty() && in_flight.front() + delay <= sched.timeOf(i) + 1e-9) {
        in_flight.erase(in_flight.begin());
        new_raw = true;
      }
    } else if (f.wts && delivered(sched.timeOf(i))) {
      new_raw = true;
    }
    if (f.features && new_raw) {
      if (fi >= rec.features.size()) {
        why = "fewer features samples than features ticks";
        return false;
      }
      feats = rec.features[fi++];
      new_raw = false;
    }
    if (!f.servo) continue;
    const PhaseState& ph = rec.phases[pi++];
    // One command per servo cycle in the sim (the pose is there from tick 0).
    if (ci < rec.commands.size()) {
      cmd = rec.commands[ci++].pose;
      have_cmd = true;
    }
    if (!have_cmd || static_cast<std::size_t>(i) >= rec.truths.size()) {
      why = "servo cycle " + std::to_string(pi) + " without a command or a truth sample";
      return false;
    }
    out.rows.push_back(sim::makeRow(sc, sched.timeOf(i), ph.index, ph.status, feats, cmd,
                                    rec.truths[static_cast<std::size_t>(i)]));
  }
  out.phases = sim::phaseEntries(sc, out.rows);
  sim::computeSummary(sc, out);
  return true;
}

struct Case {
  const char* scene;
  ControllerMode mode;
  const char* effects = nullptr;  ///< an `effects:` map appended to the scene (YAML flow map)
  const char* name = "";          ///< test name suffix
  const char* faults = nullptr;   ///< a `faults:` list appended to the scene (YAML flow list)
};

/// The scene with an `effects:` map appended, as a temporary file (its
/// relative paths made absolute); the scene itself without.
// With effects: a copy of the scene with the `effects:` map (paths made
// absolute), so that the deployment loads the same file as the runner.
std::string sceneWithEffects(const Case& c) {
  if (!c.effects && !c.faults) return kScenes + c.scene;
  std::ifstream in(kScenes + c.scene);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (std::size_t at = text.find("../"); at != std::string::npos; at = text.find("../", at))
    text.replace(at, 3, TACTILE_SOURCE_DIR "/params/");
  if (c.effects) text += std::string("\neffects: ") + c.effects + "\n";
  if (c.faults) text += std::string("\nfaults: ") + c.faults + "\n";
  return test::writeTempFile(std::string("effects") + c.name + "_" + c.scene, text);
}

class SimLoop : public ::testing::TestWithParam<Case> {};

TEST_P(SimLoop, DeploymentIsTheRunnersLoop) {
  const Case c = GetParam();
  sim::Scene sc;
  const std::string scene_file = sceneWithEffects(c);
  sim::RunFiles files{scene_file, "", ""};  // the program the registry binds to the shipped scene
  const ConfigResult bound =
      config::programForScene(TACTILE_SOURCE_DIR "/experiments.yaml", kScenes + c.scene, files.program);
  ASSERT_TRUE(bound.ok()) << bound.message();
  const ConfigResult loaded = sim::loadRun(files, sc);
  ASSERT_TRUE(loaded.ok()) << loaded.message();
  sc.controller = c.mode;
  // The servo component reads the mode from its program file: the scene's
  // program (its base merged) with the controller overridden (as --controller does).
  std::string program_file = sc.program_file;
  if (c.mode != ControllerMode::Proposed) {
    YAML::Node doc;
    const ConfigResult merged = loadProgramDocument(sc.program_file, doc);
    ASSERT_TRUE(merged.ok()) << merged.message();
    doc["controller"]["mode"] = toString(c.mode);
    program_file = test::writeTempFile(std::string(toString(c.mode)) + "_" + c.scene, YAML::Dump(doc) + "\n");
  }
  sim::Runner runner;
  ASSERT_TRUE(runner.configure(sc).ok());
  sim::RunResult want;
  runner.run(want);

  Recording rec = runDeployment(scene_file, program_file, 1.0 / sc.rates.servo);

  // A latched stop (a watchdog, the force ceiling; tactile_sim's exit codes
  // 4-11): the clock runs the servo one cycle more, which the runner does not
  // record, so that the experiment's state machine sees the latched status
  // (sim_clock.cpp). After a watchdog that cycle holds the last command.
  const bool latched_stop = want.summary.exit_code >= 4 && want.summary.exit_code <= 11;
  if (latched_stop) {
    ASSERT_EQ(rec.commands.size(), want.rows.size() + 1) << "pose commands: one per servo cycle and the latched one";
    ASSERT_EQ(rec.phases.size(), want.rows.size() + 1) << "servo cycles: the runner's and the latched one";
    const PoseCommand &extra = rec.commands.back(), &last = rec.commands[want.rows.size() - 1];
    EXPECT_EQ(extra.status, last.status) << "the latched status again";
    if (watchdogStatus(last.status)) {
      for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(extra.pose.p[i], last.pose.p[i]) << "a watchdog holds";
      for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(extra.pose.q[i], last.pose.q[i]) << "a watchdog holds";
    }
    rec.commands.pop_back();
    rec.phases.pop_back();
  }

  // Every servo cycle's pose command, to 1e-12.
  ASSERT_EQ(rec.phases.size(), want.rows.size()) << "servo cycles";
  ASSERT_EQ(rec.commands.size(), want.rows.size()) << "pose commands (one per servo cycle)";
  double worst = 0.0;
  for (std::size_t k = 0; k < want.rows.size(); ++k) {
    const KDL::Frame T = toFrame(rec.commands[k].pose) * sc.servo.sensor_mount;
    const sim::LogRow& w = want.rows[k];
    const double d[] = {T.p.x() - w.cmd[0], T.p.y() - w.cmd[1], T.p.z() - w.cmd[2]};
    for (double e : d) worst = std::max(worst, std::fabs(e));
    double r, p, y;
    T.M.GetRPY(r, p, y);
    for (double e : {r - w.cmd_rpy[0], p - w.cmd_rpy[1], y - w.cmd_rpy[2]}) worst = std::max(worst, std::fabs(e));
    ASSERT_LE(worst, 1e-12) << "servo cycle " << k << " t = " << w.t;
    ASSERT_EQ(rec.commands[k].status, w.servo) << "servo cycle " << k;
    ASSERT_EQ(rec.phases[k].index, w.phase) << "servo cycle " << k;
  }
  std::printf("%s (%s): %zu servo cycles, largest pose command difference %.3g (m, rad), %d ticks\n", c.scene,
              toString(c.mode), want.rows.size(), worst, rec.ticks);

  // The same summary from the deployment's rows, and the same end.
  sim::RunResult got;
  std::string why;
  ASSERT_TRUE(rowsFromRecording(sc, rec, got, why)) << why;
  ASSERT_EQ(got.rows.size(), want.rows.size());
  EXPECT_EQ(rec.status, want.summary.status);
  EXPECT_EQ(rec.exit_code, want.summary.exit_code);
  const sim::Summary &g = got.summary, &w = want.summary;
  auto same = [](double a, double b) { return (std::isnan(a) && std::isnan(b)) || a == b; };
  EXPECT_EQ(g.contact_lost_count, w.contact_lost_count);
  for (auto [name, a, b] : {std::tuple<const char*, double, double>{"force_true_mean_n", g.force_true_mean_n, w.force_true_mean_n},
                            {"force_true_max_n", g.force_true_max_n, w.force_true_max_n},
                            {"force_true_rms_error_n", g.force_true_rms_error_n, w.force_true_rms_error_n},
                            {"force_true_in_band_fraction", g.force_true_in_band_fraction, w.force_true_in_band_fraction},
                            {"force_scored_s", g.force_scored_s, w.force_scored_s},
                            {"force_true_in_band_s", g.force_true_in_band_s, w.force_true_in_band_s},
                            {"alignment_time_s", g.alignment_time_s, w.alignment_time_s},
                            {"path_length_m", g.path_length_m, w.path_length_m},
                            {"slide_speed_mps", g.slide_speed_mps, w.slide_speed_mps},
                            {"dzmp_final_m", g.dzmp_final_m, w.dzmp_final_m},
                            {"tray_angle_max_deg", g.tray_angle_max_deg, w.tray_angle_max_deg},
                            {"dzmp_recovery_time_s", g.dzmp_recovery_time_s, w.dzmp_recovery_time_s},
                            {"translation_x_m", g.translation_x_m, w.translation_x_m}})
    EXPECT_TRUE(same(a, b)) << name << ": deployment " << a << ", runner " << b;
  ASSERT_EQ(got.phases.size(), want.phases.size());
  for (std::size_t k = 0; k < got.phases.size(); ++k) {
    EXPECT_EQ(got.phases[k].name, want.phases[k].name);
    EXPECT_EQ(got.phases[k].t_enter, want.phases[k].t_enter);
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, SimLoop,
                         ::testing::Values(Case{"edge_exploration.yaml", ControllerMode::Proposed},
                                           Case{"bent_bar.yaml", ControllerMode::Proposed},
                                           Case{"bent_bar.yaml", ControllerMode::Baseline},
                                           Case{"bent_bar.yaml", ControllerMode::NoRotation},
                                           Case{"co_manipulation.yaml", ControllerMode::Proposed},
                                           Case{"sphere_table.yaml", ControllerMode::Proposed},
                                           Case{"partial_edge.yaml", ControllerMode::Baseline},
                                           // The force estimate at its bound on an estimated wrench with
                                           // its error (bias, noise: the same numbers at the same times).
                                           Case{"off_centre_load.yaml", ControllerMode::Proposed},
                                           // The speed law and the slope feed-forward (the bent bar at
                                           // 60 mm/s), and a wave tighter than the pad (the careful law
                                           // stopped by the surface-too-curved watchdog).
                                           Case{"bent_bar_speed_law.yaml", ControllerMode::Proposed},
                                           Case{"tight_wave.yaml", ControllerMode::Proposed},
                                           // The physics and timing effects (friction, FRI delay, KRC cycle).
                                           Case{"edge_exploration.yaml", ControllerMode::Proposed,
                                                "{friction_mu: 0.5, fri_delay_s: 0.002, krc_cycle_s: 0.002}",
                                                "_physics_effects"},
                                           Case{"co_manipulation.yaml", ControllerMode::Proposed,
                                                "{friction_mu: 0.5, fri_delay_s: 0.002, krc_cycle_s: 0.002}",
                                                "_physics_effects"},
                                           // The sensor's effects, all on (the transfer delay makes the
                                           // clock update the sensor every tick).
                                           Case{"edge_exploration.yaml", ControllerMode::Proposed,
                                                "{wts_transfer_delay_s: 0.0157, gain_spread: 0.1, dead_taxels: 2, "
                                                "calibration_error: 0.05, crosstalk: 0.05, "
                                                "creep: {fraction: 0.1, tau_s: 2.0}, hysteresis: 0.05, "
                                                "device_noise: true}",
                                                "_sensor_effects"},
                                           Case{"co_manipulation.yaml", ControllerMode::Proposed,
                                                "{wts_transfer_delay_s: 0.0157, gain_spread: 0.1, dead_taxels: 2, "
                                                "calibration_error: 0.05, crosstalk: 0.05, "
                                                "creep: {fraction: 0.1, tau_s: 2.0}, hysteresis: 0.05}",
                                                "_sensor_effects"},
                                           // Scheduled faults of the pad and of the estimated wrench
                                           // (sensor_faults.hpp): the same frames and wrenches at the same times.
                                           Case{"edge_exploration.yaml", ControllerMode::Proposed, nullptr, "_faults",
                                                "[{kind: tare_creep, start_s: 5, counts_per_min: 300}, "
                                                "{kind: pad_mass, start_s: 6, mass_kg: 0.3}, "
                                                "{kind: repeat, start_s: 8, duration_s: 1}, "
                                                "{kind: stale, start_s: 10, duration_s: 0.5}, "
                                                "{kind: stuck, start_s: 12, rows: [1, 4], cols: [5, 8], force_n: 8}, "
                                                "{kind: wrench_sign, start_s: 14}]"}),
                         [](const ::testing::TestParamInfo<Case>& i) {
                           std::string n = i.param.scene;
                           n = n.substr(0, n.find('.'));
                           return n + "_" + toString(i.param.mode) + i.param.name;
                         });

/// The edge exploration's loop in this thread: the clock on a SlaveActivity
/// without a master (its updates run in the caller), the four stages its
/// slaves and wired as deployments/sim_loop.ops does, plus `extra` slaves.
class ClockedEdgeExploration : public ::testing::Test {
 protected:
  /// threaded: the clock on a thread of its own (RTT::Activity), as deployed.
  void build(std::initializer_list<RTT::TaskContext*> extra = {}, bool threaded = false) {
    const std::string scene = kScenes + "edge_exploration.yaml";
    if (threaded) {
      clock.setActivity(new RTT::Activity(ORO_SCHED_OTHER, 0, 0.0));
    } else {
      clock.setActivity(new RTT::extras::SlaveActivity(0.0));
    }
    std::vector<RTT::TaskContext*> slaves{&robot, &sensor, &features, &servo};
    slaves.insert(slaves.end(), extra);
    for (RTT::TaskContext* s : slaves) {
      ASSERT_TRUE(s->setActivity(new RTT::extras::SlaveActivity(clock.getActivity())));
      clock.addPeer(s);
    }
    robot.properties()->getPropertyType<std::string>("scene_file")->set(scene);
    robot.properties()->getPropertyType<std::string>("program_file")->set(
        TACTILE_SOURCE_DIR "/params/programs/edge_exploration.yaml");
    sensor.properties()->getPropertyType<std::string>("scene_file")->set(scene);
    clock.properties()->getPropertyType<std::string>("scene_file")->set(scene);
    features.properties()->getPropertyType<std::string>("param_file")->set(
        TACTILE_SOURCE_DIR "/params/sensors/wts0614.yaml");
    servo.properties()->getPropertyType<std::string>("program_file")->set(
        TACTILE_SOURCE_DIR "/params/programs/edge_exploration.yaml");
    servo.properties()->getPropertyType<double>("period")->set(0.01);
    connect(robot, "taxel_forces", sensor, "taxel_forces");
    connect(sensor, "raw_frame", features, "raw_frame");
    connect(features, "features", servo, "features");
    connect(robot, "flange_pose", servo, "flange_pose");
    connect(robot, "estimated_wrench", servo, "estimated_wrench");
    connect(servo, "pose_command", robot, "pose_command");
  }
  void start() {
    ASSERT_TRUE(robot.configure() && sensor.configure() && features.configure() && servo.configure());
    ASSERT_TRUE(clock.configure()) << clock.lastError();
    ASSERT_TRUE(sensor.start() && features.start() && servo.start() && robot.start());
    ASSERT_TRUE(clock.start());
  }
  static void connect(RTT::TaskContext& a, const char* out, RTT::TaskContext& b, const char* in) {
    const RTT::ConnPolicy data = RTT::ConnPolicy::data(RTT::ConnPolicy::LOCK_FREE);
    ASSERT_TRUE(a.ports()->getPort(out)->connectTo(b.ports()->getPort(in), data)) << out << " -> " << in;
  }
  void TearDown() override {
    clock.stop();
    clock.update();  // runs what is still queued on the clock's engine before the slaves go away
    RTT::os::TimeService::Instance()->enableSystemClock(true);
  }
  int ticks() { return tactile::readAttribute<int>(*clock.provides(), "ticks", -1); }

  // Declared first, destroyed last: the slaves go away before their master.
  SimClock clock{"Clock"};
  LwrSimComponent robot{"Robot"};
  WtsSimComponent sensor{"Sensor"};
  FeatureComponent features{"Features"};
  ServoComponent servo{"Servo"};
};

// The whole deployed loop per tick allocates nothing: the clock executing the
// four stages through an edge exploration into contact.
TEST_F(ClockedEdgeExploration, TicksDoNotAllocate) {
  build();
  start();
  const int per_update = SimClock::kTicksPerUpdate;
  for (int k = 0; k < 2000 / per_update; ++k) ASSERT_TRUE(clock.update());  // warm-up: 2000 ticks, every port used
  {
    tactile::test::AllocationScope scope;
    for (int k = 0; k < 5000 / per_update; ++k) clock.update();  // 5000 ticks: free motion into contact and alignment
    EXPECT_EQ(scope.count(), 0u);
  }
  EXPECT_EQ(ticks(), 7000);
  EXPECT_NE(servo.phaseName(), "free_motion") << "the loop reached the bar";
}

// cleanup() leaves the clock's engine without its thread, so that nothing a
// slave does while the deployer unloads it reaches the clock (the slaves are
// unloaded before it); configure() gives the thread back and the clock runs.
TEST_F(ClockedEdgeExploration, CleanupDetachesTheClocksThreadAndConfigureAttachesIt) {
  build({}, true);
  start();
  for (int i = 0; i < 200000 && ticks() < 100; ++i) std::this_thread::yield();  // a count, not a time
  ASSERT_GE(ticks(), 100) << "the clock's thread runs the loop";
  ASSERT_TRUE(clock.stop());
  ASSERT_TRUE(servo.stop() && features.stop() && sensor.stop() && robot.stop());
  ASSERT_TRUE(clock.cleanup());
  EXPECT_EQ(clock.getActivity(), nullptr) << "the engine without the clock's thread";
  ASSERT_TRUE(clock.configure()) << clock.lastError();
  ASSERT_NE(clock.getActivity(), nullptr);
  EXPECT_TRUE(clock.getActivity()->isActive());
  ASSERT_TRUE(sensor.start() && features.start() && servo.start() && robot.start());
  ASSERT_TRUE(clock.start());
  for (int i = 0; i < 200000 && ticks() < 100; ++i) std::this_thread::yield();
  EXPECT_GE(ticks(), 100) << "the clock runs again after configure()";
}

/// A slave with event ports, as the deployment's reporter (OCL::FileReporting):
/// counts the samples that trigger it, each a message queued on the clock's
/// engine (RTT's SlaveActivity::trigger).
class TriggerCounter : public RTT::TaskContext {
 public:
  TriggerCounter() : RTT::TaskContext("Reporter") {
    ports()->addEventPort(truth_);
    ports()->addEventPort(pose_);
    ports()->addEventPort(features_);
    ports()->addEventPort(command_);
  }
  bool dataOnPortHook(RTT::base::PortInterface* port) override {
    const bool trigger = RTT::TaskContext::dataOnPortHook(port);
    if (trigger) ++triggers;
    return trigger;
  }
  RTT::InputPort<SimTruth> truth_{"truth"};
  RTT::InputPort<Pose> pose_{"flange_pose"};
  RTT::InputPort<ContactFeatures> features_{"features"};
  RTT::InputPort<PoseCommand> command_{"pose_command"};
  int triggers = 0;
};

// Between two of the clock's updates, what its slaves queue on its engine
// stays well within the queue (RTT 2.10's ORONUM_EE_MQUEUE_SIZE, 100): an
// update that overfilled it left messages the engine never ran again, and
// the deployer crashed unloading the slaves (rtt_deployer_sim_run_fails_cleanly
// under load). The stages of the loop (tactile::Component) queue none; a
// reporter on four ports queues one per sample.
TEST_F(ClockedEdgeExploration, AnUpdateQueuesFarFewerTriggersThanTheEngineHolds) {
  constexpr int kEngineQueue = 100;
  TriggerCounter reporter;  // destroyed before the fixture's clock
  build({&reporter});
  connect(robot, "truth", reporter, "truth");
  connect(robot, "flange_pose", reporter, "flange_pose");
  connect(features, "features", reporter, "features");
  connect(servo, "pose_command", reporter, "pose_command");
  start();
  ASSERT_TRUE(reporter.start());
  int most = 0;
  for (int k = 0; k < 3000 / SimClock::kTicksPerUpdate; ++k) {  // 3 s: free motion into contact
    const int before = reporter.triggers;
    ASSERT_TRUE(clock.update());
    most = std::max(most, reporter.triggers - before);
  }
  EXPECT_GT(most, 0) << "the reporter's ports were written";
  // Two samples per tick (truth, flange pose) and a few per servo cycle: a
  // quarter of the queue at most.
  EXPECT_LE(most, kEngineQueue / 4);
  clock.stop();
  clock.update();  // the reporter goes before TearDown: nothing of it may stay queued
}

}  // namespace
