// What one run of the loop logs (timeseries.csv rows, phases, snapshots,
// contacts) and its summary.json: the headless runner fills it, and the RTT
// sim deployment's recordings give the same rows (tactile_sim_runner/loop.hpp).
#pragma once

#include <array>
#include <limits>
#include <cstdint>
#include <string>
#include <vector>

#include "tactile_servo/servo.hpp"
#include "tactile_types/types.hpp"

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
  /// The speed law's cap on the slide (m/s, ServoOutput::slide_speed; 0 in a
  /// phase without it) and the input that decided it (SpeedLimiter); NaN / -1
  /// where the log does not carry them (a deployed run's reporter table).
  double slide_speed = std::numeric_limits<double>::quiet_NaN();
  int speed_limiter = -1;
  SpeedLawInput speed_inputs;              ///< what the law saw (zeros where not recorded)
  /// rad: the measured joint closest to its limit, its distance from it, as
  /// the phase program saw it (ProgramSignals::joint_margin); NaN where not recorded.
  double joint_margin = std::numeric_limits<double>::quiet_NaN();
  /// N: the wrench's press along z_s, the fused estimate's correction and its
  /// demand (ServoOutput::force_wrench, force_correction, force_demand); NaN
  /// where not recorded.
  double force_wrench = std::numeric_limits<double>::quiet_NaN();
  double force_correction = std::numeric_limits<double>::quiet_NaN();
  double force_demand = std::numeric_limits<double>::quiet_NaN();
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

/// A point of the contact line: where the edge crosses a taxel column
/// (tactile_features/edge_line.hpp), through the measured flange pose and the
/// sensor mount into {g}.
struct EdgePoint {
  double t = 0;
  std::array<double, 3> p{};  ///< {g} (m)
  int phase = 0;
};

struct ContactPoint {
  double t = 0;
  std::array<double, 3> p{};     ///< CoP mapped to {g} (m)
  std::array<double, 3> truth{}; ///< true pressure centre {g} (m)
  /// lambda1 (m^2): the contact's second moment along the edge (Eq. 4). On a
  /// curved edge of radius R the CoP lies lambda1 / (2 R) inside the curve
  /// (scripts/tools/contour_check.py corrects the cloud with it).
  double lambda1 = 0;
  int phase = 0;  ///< the servo's phase index
};

/// summary.json. Metrics a scene does not have are NaN (written as null).
///
/// Two windows of the run (computeSummary; docs/formats.md, "summary.json"):
///  * the slide: every servo cycle scored as a scored phase (the scene's
///    metrics.force_phases; without it, every phase that requires contact and
///    is not terminal), from the phase's first cycle: transients included. A
///    detour, the run leaving such a phase and back in it within
///    metrics.transient_s, belongs to the phase it left;
///  * the scored window: the cycles of the slide at least metrics.transient_s
///    after the start of their phase (a detour's return starts no new transient).
/// Per window: the true force per cycle (mean, max, RMS error about f_d, the
/// fraction within force_band_n of it); the path of the true contact point
/// between consecutive cycles of the window both in true contact; the duration,
/// the time between consecutive cycles of the window; the mean speed, the path
/// over the part of the duration in true contact (path / duration while the
/// contact held throughout).
struct Summary {
  std::string scene, controller, status = "ok", fidelity;
  uint64_t seed = 1;
  double sim_time_s = 0, wall_time_s = 0, real_time_factor = 0;
  /// s: when the fault that ended the run happened (the first cycle with the
  /// fatal servo status; the end for the simulator's); NaN when status is ok.
  double fault_time_s = std::numeric_limits<double>::quiet_NaN();
  int contact_lost_count = 0;  ///< contact held >= 5 servo cycles, then absent >= 5, in a contact phase
  double alignment_time_s = 0;
  // The scored window: the force_true_* keys; path_length_m and slide_speed_mps,
  // which summary.json also writes as scored_path_m and scored_mean_speed_mps.
  double force_true_mean_n = 0, force_true_max_n = 0, force_true_rms_error_n = 0, force_true_in_band_fraction = 0;
  double force_scored_s = 0, force_true_in_band_s = 0;  ///< scored time (each cycle counts the time since the
                                                        ///< log's previous one), of which |f_true - f_d| <= band (s)
  double path_length_m = 0, slide_speed_mps = 0, scored_duration_s = 0;
  // The slide, transients included.
  double slide_path_m = 0, slide_duration_s = 0, slide_mean_speed_mps = 0;
  double slide_force_true_mean_n = 0, slide_force_true_max_n = 0, slide_force_true_rms_error_n = 0,
         slide_force_true_in_band_fraction = 0;
  double dzmp_final_m = 0, tray_angle_max_deg = 0, dzmp_recovery_time_s = 0, translation_x_m = 0;
  // Through FRI (scene through_fri): bridge replies and the largest step
  // between consecutive commands the simulated KRC applied.
  long fri_replies = 0;
  double fri_max_step_m = 0, fri_max_step_rad = 0;
  int sim_unconverged_steps = 0;  ///< physics steps whose quasi-static solve did not converge
  double sim_unconverged_max_residual = 0.0;  ///< N, N m: the largest residual such a step stopped at (0: none)
  std::vector<std::string> criteria_failed;  ///< scene criteria not met, "metric = v > max"; empty = passed
  int exit_code = 0;  ///< 0 ok, 3 simulator (fatal: NaN, joint limit, singularity, force limit; or its steps or
                      ///< commands refused: sim_step_rejected, sim_invalid_command), 4 servo force ceiling,
                      ///< 5/6/7 a servo watchdog (phase_timeout, arm_stalled, force_mismatch), 8 surface_too_curved
};

/// The summary metric called `name` in summary.json (the numeric ones), false
/// if there is none of that name.
bool summaryMetric(const Summary& s, const std::string& name, double& value);

struct RunResult {
  std::vector<std::string> phase_names;  ///< by phase index
  std::vector<LogRow> rows;
  std::vector<PhaseEntry> phases;
  std::vector<Snapshot> snapshots;
  std::vector<ContactPoint> contacts;
  std::vector<EdgePoint> edge_points;  ///< edge_points.csv
  Summary summary;
};

}  // namespace sim
}  // namespace tactile
