// Scene files: what the headless runner simulates and how.
//
// A scene is a YAML file (params/scenes/*.yaml). Paths inside it are relative to
// the scene file. Every key is optional unless marked; unknown keys are errors.
//
//   name: edge_exploration            # required
//   description: "..."
//   figure: fig10                     # which paper figure the plots mirror (fig10 | fig12 | fig14 | none)
//   program: ../programs/edge_exploration.yaml   # required: the phase program
//   controller: proposed              # proposed | baseline (Li et al.) | no_rotation (ablation); --controller overrides
//   features_file: ../sensors/wts0614.yaml   # `features:` and `calibration:` maps (same
//                                     # file as on the robot): the features, the reader's calibration and,
//                                     # inverted, the simulated sensor's response (no response keys here)
//   duration: 60                      # s of simulated time
//   seed: 1
//   fidelity: quasi_static            # quasi_static | dynamics
//   start_in_equilibrium: true        # dynamics: start at the static balance of the initial
//                                     # command (an object resting on the sensor does not drop)
//   rates: {sim: 1000, servo: 100, wts: 140, features: 200}   # Hz (Table 2)
//   sensor: {subsamples: 4, physics_subsamples: 1, noise_counts: 6, threshold: 0.2, modulus: 5e7, ...}
//   arm: {q_init_deg: [7 values], k_trans: 1000, k_rot: 100, damping_ratio: 0.7,
//         dyn_refresh_q: 1e-4, dyn_refresh_qd: 1e-2}   # dynamics: mass/Coriolis refresh thresholds (0 = every step)
//   initial_flange: {xyz: [x, y, z], rpy_deg: [r, p, y]}       # {g}T{e} at start (IK)
//   objects:                          # only what the scene needs
//     - {name: table, type: plane, point: [0,0,0], normal: [0,0,1]}
//     - {name: ball, type: sphere, center: [..], radius: 0.02}
//     - {name: bar, type: bar, radius: 0.003, vertices: [[..], [..]]}
//     - {name: bent, type: bent_bar, radius: 0.003, vertices: [[..], [..], ...]}
//     - {name: tray, type: tray, bearing: [..], bar_from: [..], bar_to: [..], bar_radius: .., tray_mass: ..,
//        tray_com: [..], mass: 0.2, mass_from: [..], mass_to: [..], move_start_s: .., move_duration_s: ..,
//        pitch_stiffness: .., roll_stiffness: .., bearing_damping: .., initial_pitch: .., initial_roll: ..,
//        fidelity: dynamics}          # per-body fidelity: a dynamic tray (its inertia, springs, bearing
//                                     # damping integrated in time) on a quasi-static arm; default: the scene's
//   effects:                          # physics and timing effects, each off by default (no cost when off)
//     friction_mu: 0                  # Coulomb friction at the pad, [0, 2] (rubber on metal ~0.5-1):
//                                     # spring-slider, drag mu N while sliding, stuck below; acts at the
//                                     # pressure centre, its moment about the flange tilts the sensor
//     friction_stiffness: 5000        # N/m, (0, 1e7]: shear stiffness of the layer before it slides
//     fri_delay_s: 0                  # FRI transport delay of the flange command, [0, 1] s, whole physics steps
//     krc_cycle_s: 0                  # KRC set-point sample-and-hold, [0, 1] s, whole physics steps (0 = every step)
//   rates.sim must give a physics step 1 / rates.sim <= 0.01 s (>= 100 Hz): a
//   coarser step would be refused by the world on every cycle.
//   through_fri: false                # route every physics-rate command through the FRI
//                                     # protocol and tactile::fri::FriBridge (bytes on the wire)
//   fri_file: ../sensors/fri.yaml                # bridge parameters (rate limiter...)
//   krc: "0:friOpen,1:friStart"       # the KRC's script (tactile::fri::KrcScript: friOpen, friStart,
//                                     # friStop, friClose, quality=.., power=.. at times in s); while the
//                                     # arm is not commandable it holds still and the servo waits.
//                                     # Default "": command mode from the start
//   effects:                          # each off by default; off costs nothing per frame
//     wts_transfer_delay_s: 0         # s, [0, 1]: the frame sampled at t reaches the reader at t + d
//                                     # (serial transfer; WTS0614 plain periodic frame 181 B at 115200
//                                     # baud 8N1 = 15.7 ms, core/sim/lwr/README.md "Sensor effects")
//     gain_spread: 0                  # [0, 0.5]: 1-sigma relative per-taxel sensitivity spread (seeded)
//     dead_taxels: 0                  # [0, rows*cols] dead taxels at seeded positions, or a list [[row, col], ...]
//     calibration_error: 0            # [0, 0.5]: 1-sigma relative error of the reader's calibration per
//                                     # taxel (seeded): the sensor's true response is (1 + e) x the file's
//     crosstalk: 0                    # [0, 0.25]: fraction of a taxel's load spread to each 4-neighbour
//     creep: {fraction: 0, tau_s: 1.0}   # [0, 1], (0, 1000] s: under a constant load the signal tends to
//                                     # (1 + fraction) x its instantaneous value with time constant tau_s
//     hysteresis: 0                   # [0, 0.5]: loading reads (1 - h) x load, unloading (1 + h) x load
//     device_noise: false             # true: sensor noise at the WTS's level (TaxelResponse::deviceNoiseCounts)
//     wrench_error:                   # the arm's estimated wrench (estExtTcpFT, from the joint torques) is not
//                                     # the contact wrench: (1 + scale) F + bias + drift |p - p_0| + noise
//       bias_n: [0, 0, 0]             # N, {g}, each in [-20, 20]: constant force offset
//       drift_n_per_m: [0, 0, 0]      # N/m, {g}, each in [-100, 100]: offset growing with the flange's distance
//                                     # from its start position (a model error that depends on the posture)
//       scale: 0                      # [-0.5, 0.5]: relative gain error of the force
//       noise_n: 0                    # N, [0, 10]: 1-sigma noise per axis, a function of (seed, time) only
//   faults:                           # scheduled faults of the pad and of the arm's estimated wrench
//                                     # (tactile_sim/sensor_faults.hpp; at most 8; none by default).
//                                     # Each: kind (required), start_s (s, >= 0, default 0), duration_s
//                                     # (s, default 0 = to the end; stale, repeat, disconnect: (0, 60]);
//                                     # rows / cols: [first, last] taxels from 0, inclusive (default all)
//     - {kind: stuck, start_s: 8, rows: [1, 4], cols: [5, 8], force_n: 8}   # or counts: [0, 4095] per taxel;
//                                     # force_n: [0, 1000] N over the region, no noise
//     - {kind: dead, start_s: 8, cols: [0, 4]}          # the region reads 0
//     - {kind: tare_creep, start_s: 8, counts_per_min: 300}   # [-4095, 4095]: every taxel's zero drifts
//     - {kind: calibration, scale: 0.5}  # [0.1, 10]: the reader's force = scale x the true force
//     - {kind: saturated, start_s: 8}    # one frame at full scale
//     - {kind: stale, start_s: 8, duration_s: 0.5}        # no frame in the window
//     - {kind: repeat, start_s: 8, duration_s: 2}         # the last frame's counts re-sent, new seq and time
//     - {kind: disconnect, start_s: 8, duration_s: 1}     # stale with the link down (lab_sim unplugs the PTY)
//     - {kind: wrench_bias, start_s: 8, bias_n: [0, 0, 5]}             # N, {g}, each [-100, 100]
//     - {kind: wrench_drift, start_s: 8, drift_n_per_min: [0, 0, 10]}  # N/min, {g}, each [-100, 100]
//     - {kind: wrench_frame, start_s: 8, axes: flange}  # flange | sensor: those axes' components given as {g}'s
//     - {kind: wrench_sign, start_s: 8}  # the wrench negated
//     - {kind: pad_mass, mass_kg: 0.5}   # [-5, 5] kg: the load model's pad mass off (true - modelled)
//   `tactile_sim run --set 'faults=[{kind: stuck, start_s: 8, force_n: 8}]'` sets the list.
//   metrics:
//     transient_s: 2.0                # the start of each scored phase left out of the scored window
//     force_phases: [explore]         # the scored phases, the slide (default: all contact phases
//                                     # that are not terminal); Summary (run_log.hpp): the two windows
//     alignment: {from: align, to: explore}   # alignment_time_s = t(to) - t(from)
//     force_band_n: 1.0               # |f_true - f_desired| band for force_true_in_band_fraction
//     criteria:                       # the experiment passes when every summary.json metric named
//       alignment_time_s: {max: 10}   # here is within [min, max] (either bound optional); the result
//       slide_path_m: {min: 0.15}     # is summary.json's criteria_passed / criteria_failed. The whole
//                                     # slide (slide_*) or the scored window (force_true_*, scored_*)
#pragma once

#include <array>
#include <limits>
#include <string>
#include <vector>

#include "tactile_features/extractor.hpp"
#include "tactile_servo/servo.hpp"
#include "tactile_sim/taxel_response.hpp"
#include "tactile_sim/world.hpp"
#include "tactile_types/config_result.hpp"

namespace YAML {
class Node;
}

namespace tactile {
namespace sim {

struct Rates {
  double sim = 1000.0;      ///< Hz: arm physics (the KRC's impedance loop)
  double servo = 100.0;     ///< Hz: tactile servo (Table 2)
  double wts = 140.0;       ///< Hz: WTS acquisition
  double features = 200.0;  ///< Hz: feature extraction
};

/// One pass criterion of an experiment: min <= summary.json[metric] <= max
/// (a NaN value fails: e.g. an alignment that never happened).
struct Criterion {
  std::string metric;  ///< a summary.json key (summaryMetric())
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
};

struct SceneMetrics {
  std::vector<Criterion> criteria;  ///< what "the experiment passes" means (metrics.criteria)
  double transient_s = 2.0;
  std::vector<std::string> force_phases;
  std::string align_from, align_to;
  double force_band_n = 1.0;
};

/// effects.wrench_error: the error of the arm's estimated wrench (force part;
/// the moments are exact). All zero: the estimate is the contact wrench.
struct WrenchErrorParams {
  std::array<double, 3> bias_n{0.0, 0.0, 0.0};         ///< N, {g}
  std::array<double, 3> drift_n_per_m{0.0, 0.0, 0.0};  ///< N/m, {g}, times |p_flange - p_flange(0)|
  double scale = 0.0;                                  ///< relative gain error
  double noise_n = 0.0;                                ///< N, 1 sigma per axis
  bool any() const {
    for (int i = 0; i < 3; ++i)
      if (bias_n[i] != 0.0 || drift_n_per_m[i] != 0.0) return true;
    return scale != 0.0 || noise_n != 0.0;
  }
};

struct Scene {
  std::string file;         ///< the scene file
  std::string name, description, figure;
  std::string program_file;
  ControllerMode controller = ControllerMode::Proposed;
  double duration = 30.0;
  uint64_t seed = 1;
  Rates rates;
  FeatureParams features;
  CalibrationParams calibration;  ///< features_file's `calibration:` (rows/cols from features)
  ServoParams servo;        ///< loaded from program_file
  WorldParams world;
  SceneMetrics metrics;
  bool through_fri = false;  ///< commands go through FRI packets and the bridge
  std::string fri_file;      ///< bridge parameters (empty: defaults)
  std::string krc;           ///< the KRC's script (fri::KrcScript; empty: command mode from the start)
  SensorEffects sensor_effects;  ///< `effects:` keys of the sensor (TaxelResponse)
  WrenchErrorParams wrench_error;  ///< effects.wrench_error (the arm's estimated wrench)
  std::vector<FaultSpec> faults;   ///< `faults:` (the pad's and the estimated wrench's, sensor_faults.hpp)
};

/// The simulated sensor's parameters (TaxelResponse) of a scene: its
/// calibration file, sensor.noise_counts / threshold, seed and sensor effects.
/// The runner and tactile::WtsSimComponent both use it.
TaxelResponseParams responseParams(const Scene& s);

/// Load and validate a scene (and the program and feature files it names).
/// Errors name the file and the field.
ConfigResult loadScene(const std::string& file, Scene& out);

/// The same, with overrides applied to the scene's YAML before it is read:
/// each "a.b.c=VALUE" sets key c of map b of map a (created if absent) to
/// VALUE parsed as YAML ("sensor.noise_counts=30", "rates={sim: 500}"); the
/// result is checked like the file itself (`tactile_sim run --set`). A key
/// under `program.` is one of the scene's program, set in the program with its
/// `base:` merged ("program.speed_law.force_budget_n=0.4"). In a list, a
/// number picks an element by index and a name the element of that `name`
/// ("program.phases.explore.kp_per_s.x=4.8").
ConfigResult loadScene(const std::string& file, Scene& out, const std::vector<std::string>& overrides);

/// The scene as read: its document with the overrides applied, and its
/// program's with its `base:` merged and the `program.` overrides applied,
/// after loadScene() checked them in full (`tactile_sim scene`).
ConfigResult sceneDocuments(const std::string& file, const std::vector<std::string>& overrides, YAML::Node& scene,
                            YAML::Node& program);

/// Cross-checks after command-line overrides (rates, sub-samples...).
ConfigResult validateScene(const Scene& s);

/// The world's parameters for a scene: scene.world with the scene's seed and
/// physics step (1 / rates.sim), as the runner and the RTT arm configure it.
WorldParams worldParams(const Scene& s);

}  // namespace sim
}  // namespace tactile
