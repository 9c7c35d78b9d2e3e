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
// watchdog works on it). The same cores run here as in the RTT components:
// tactile::Calibration, tactile::FeatureExtractor, tactile::TactileServo, and
// the simulator's World in place of the robot.
//
// Deterministic for a given scene and seed (the only randomness is the
// sensor noise, seeded). The runner is an application, not a core: it
// allocates its logs up front and measures wall time for the summary.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "tactile_features/calibration.hpp"
#include "tactile_fri/bridge.hpp"
#include "tactile_sim/scene.hpp"

namespace tactile {
namespace sim {

/// One row of timeseries.csv (logged at the servo rate).
struct LogRow {
  double t = 0;
  int phase = 0;
  ServoStatus servo = ServoStatus::NotConfigured;
  ContactType contact = ContactType::None;
  FeatureStatus feature_status = FeatureStatus::NotConfigured;
  std::array<double, 3> cmd{}, act{};      ///< sensor position {g}: commanded, actual (m)
  std::array<double, 3> cmd_rpy{}, act_rpy{};  ///< sensor orientation {g} (rad)
  ContactFeatures f;
  Vec6 s_d = Vec6::Zero();
  double sd_force = 0;                     ///< desired force (N) = s_d(d_z) / c_z
  double force_true = 0;                   ///< N, normal force on the sensor (layer + housing)
  double force_layer = 0, housing_force = 0;
  double moment_x_true = 0, moment_y_true = 0;  ///< N m, about x_s / y_s
  double tray_angle_deg = 0;
  std::array<double, 3> true_contact{};    ///< pressure centre on the surface {g} (m)
  bool true_in_contact = false;
  Vec6 u_s = Vec6::Zero();
  int beta = 0;
  double feature_age = 0;                  ///< t - features.time_s (s)
};

struct PhaseEntry {
  std::string name;
  double t_enter = 0;
};

struct Snapshot {
  double t = 0;
  std::string label;
  TactileFrame frame;
};

struct ContactPoint {
  double t = 0;
  std::array<double, 3> p{};     ///< CoP mapped to {g} (m)
  std::array<double, 3> truth{}; ///< true pressure centre {g} (m)
};

/// summary.json. Metrics a scene does not have are NaN (written as null).
struct Summary {
  std::string scene, controller, status = "ok", fidelity;
  uint64_t seed = 1;
  double sim_time_s = 0, wall_time_s = 0, real_time_factor = 0;
  int contact_lost_count = 0;  ///< contact held >= 5 servo cycles, then absent >= 5, in a contact phase
  double force_true_mean_n = 0, force_true_max_n = 0, force_true_rms_error_n = 0, force_true_in_band_fraction = 0;
  double alignment_time_s = 0, path_length_m = 0, slide_speed_mps = 0;
  double dzmp_final_m = 0, tray_angle_max_deg = 0, dzmp_recovery_time_s = 0, translation_x_m = 0;
  // Through FRI (scene through_fri): bridge replies and the largest step
  // between consecutive commands the simulated KRC applied.
  long fri_replies = 0;
  double fri_max_step_m = 0, fri_max_step_rad = 0;
  int exit_code = 0;  ///< 0 ok, 3 simulator fatal (NaN, joint limit, singularity, force limit), 4 servo force ceiling
};

struct RunResult {
  std::vector<std::string> phase_names;  ///< by phase index
  std::vector<LogRow> rows;
  std::vector<PhaseEntry> phases;
  std::vector<Snapshot> snapshots;
  std::vector<ContactPoint> contacts;
  Summary summary;
};

class Runner {
 public:
  /// Configures world, calibration, extractor and servo from the scene.
  ConfigResult configure(const Scene& scene);

  /// Runs the whole scene. `progress(t, duration)` is called about 100 times.
  void run(RunResult& out, const std::function<void(double, double)>& progress = {});

  const Scene& scene() const { return scene_; }

 private:
  void computeSummary(RunResult& out) const;
  /// The KRC side of one FRI cycle: measurement bytes from the world state,
  /// the bridge's reply decoded into the pose the robot applies.
  bool friCycle(const SimState& st, const PoseCommand& desired, double t, double dt, KDL::Frame& applied, Summary& sum);

  Scene scene_;
  World world_;
  Calibration calibration_;
  FeatureExtractor extractor_;
  TactileServo servo_;
  fri::FriBridge bridge_;
  fri::MsrPacket msr_{};
  fri::CmdPacket cmd_{};
  std::array<uint8_t, 2048> wire_{};
  uint16_t fri_seq_ = 0, fri_refl_ = 0;
  bool fri_have_applied_ = false;
  KDL::Frame fri_applied_;
};

/// Writers for a run directory (timeseries.csv, summary.json, snapshots.csv,
/// contacts.csv). Return false with `error` set on I/O failure.
bool writeRun(const std::string& dir, const Scene& scene, const RunResult& r, std::string& error);
std::string summaryJson(const Scene& scene, const RunResult& r);

}  // namespace sim
}  // namespace tactile
