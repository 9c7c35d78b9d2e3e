// Headless experiment runner: sensor -> features -> servo -> arm, at the
// rates of the paper's Table 2, each a parameter:
//
//   physics (the KRC's 1 kHz impedance loop)   rates.sim
//   WTS acquisition                           rates.wts      (140 Hz)
//   feature extraction on the latest frame    rates.features (200 Hz)
//   tactile servo on the latest features      rates.servo    (100 Hz)
//
// Each stage reads the latest output of the stage before it, so the servo
// sees features that are up to 1/wts + 1/features old, as on the robot (the
// feature's time_s is its frame's acquisition time: the servo's stale-data
// watchdog works on it); features are extracted when a new raw frame arrived.
// It is the loop of the RTT sim deployment (deployments/sim_loop.ops), stage
// for stage: the arm (World::step, World::acquireForces), the sensor
// (tactile::sim::TaxelResponse on the sensor's calibration file),
// tactile::SensorStage, tactile::ServoStage and, with through_fri,
// tactile::fri::FriBridge against tactile::fri::KrcModel, fired by
// tactile::sim::Schedule and ended by tactile::sim::EndRule (loop.hpp);
// tests/rtt/test_sim_loop.cpp checks equal pose commands on every servo cycle.
//
// Deterministic for a given scene and seed (the only randomness is the
// sensor noise, seeded). The runner is an application, not a core: it
// allocates its logs up front and measures wall time for the summary.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "tactile_features/sensor_stage.hpp"
#include "tactile_fri/bridge.hpp"
#include "tactile_fri/krc_model.hpp"
#include "tactile_servo/servo_stage.hpp"
#include "tactile_sim_runner/loop.hpp"
#include "tactile_sim_runner/run_log.hpp"
#include "tactile_sim_runner/scene.hpp"
#include "tactile_sim_lwr/taxel_response.hpp"

namespace tactile {
namespace sim {

class Runner {
 public:
  /// Configures world, calibration, extractor and servo from the scene.
  ConfigResult configure(const Scene& scene);

  /// Runs the whole scene. `progress(t, duration)` is called about 100 times.
  void run(RunResult& out, const std::function<void(double, double)>& progress = {});

  const Scene& scene() const { return scene_; }

 private:
  // The steps of run(), in order.
  struct RunState;
  /// Resets the stages to the scene's start and fills the signals with the arm's initial state.
  void startRun(RunResult& out, RunState& rs);
  /// The WTS acquisition (or a delayed frame's arrival), then calibration and features on the latest frame.
  void sensorCycle(double t, const StageFires& fi, RunState& rs);
  /// One servo cycle on the latest features, logged; the end rule's verdict on its status.
  EndReason servoCycle(double t, RunState& rs, RunResult& out);
  /// The servo cycle's records: phase and first-contact snapshots, the row, contacts and edge points.
  void logServoCycle(double t, RunState& rs, RunResult& out) const;
  /// One physics step toward the latest command (through the FRI link when the scene says so).
  void physicsCycle(double t, const fri::KrcScript::At& krc_now, RunState& rs, Summary& sum);
  /// The last snapshots, the end status and the simulated time into the summary.
  void finishRun(EndReason end, const RunState& rs, RunResult& out);

  /// The KRC side of one FRI cycle (tactile::fri::KrcModel): measurement
  /// bytes from the world state, the bridge's reply applied to the KRC's set point.
  bool friCycle(const SimState& st, const fri::KrcScript::At& krc_now, const PoseCommand& desired, double t,
                KDL::Frame& applied, RobotState& robot, Summary& sum);

  Scene scene_;
  World world_;             // the arm (physics) and the pad's contact image
  TaxelResponse response_;  // the sensor's electronics: forces -> counts
  SensorStage sensor_;      // counts -> calibrated frame -> features
  ServoStage servo_;        // features + measured pose -> pose command
  Schedule schedule_;
  EndRule end_;
  fri::FriBridge bridge_;
  fri::KrcModel krc_;
  fri::KrcScript krc_script_;  // the scene's `krc` (the KRC's script)
  std::array<uint8_t, 2048> wire_{};
};

/// Writers for a run directory (timeseries.csv, summary.json, snapshots.csv,
/// contacts.csv). Return false with `error` set on I/O failure.
bool writeRun(const std::string& dir, const Scene& scene, const RunResult& r, std::string& error);
std::string summaryJson(const Scene& scene, const RunResult& r);

}  // namespace sim
}  // namespace tactile
