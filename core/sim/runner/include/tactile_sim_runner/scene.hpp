// Scene files: the world a run simulates, the sensor and the effects.
//
// A scene names neither the servo's program nor its controller: a run binds
// the three (RunFiles), as an entry of the experiment registry
// (experiments.yaml) or `tactile_sim run SCENE --program FILE` does.
//
// A scene is a YAML file (params/scenes/*.yaml). Paths inside it are relative
// to the scene file. Every key is optional unless marked; unknown keys are
// errors. The keys, their units, ranges, defaults and meanings are declared
// once, in scene_schema.hpp (the top level, initial_flange,
// effects.wrench_error) and sim_schema.hpp (objects, sensor, arm, effects), and shown
// in docs/formats.md, "Scenes" (generated:
// `tactile_sim schema scene`; the faults: fault_schema.hpp). Checked across
// keys here:
//
//   rates.sim must give a physics step 1 / rates.sim <= 0.01 s (>= 100 Hz): a
//   coarser step would be refused by the world on every cycle.
//   metrics.criteria: {KEY: {min: .., max: ..}}: the experiment passes when every
//   summary.json metric named is within its bounds (either optional): criteria_passed.
#pragma once

#include <array>
#include <limits>
#include <string>
#include <vector>

#include "tactile_features/extractor.hpp"
#include "tactile_servo/servo.hpp"
#include "tactile_sim_lwr/taxel_response.hpp"
#include "tactile_sim_lwr/world.hpp"
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

/// A scene as read, and what the run binds to it (loadRun): its program and
/// controller. loadScene() leaves program_file empty and servo default.
struct Scene {
  std::string file;         ///< the scene file
  std::string name, description, figure;
  std::string program_file;  ///< the run's phase program (RunFiles::program)
  ControllerMode controller = ControllerMode::Proposed;  ///< the run's (RunFiles::controller)
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

/// What one run binds: a scene, the servo's phase program and the controller.
/// An entry of the experiment registry (experiments.yaml, DeployGuard) or the
/// command line (`tactile_sim run SCENE --program FILE [--controller C]`) names them.
struct RunFiles {
  std::string scene;    ///< params/scenes/*.yaml
  std::string program;  ///< params/programs/*.yaml (the file the RTT servo loads)
  /// '' : the program's controller.mode; else a ControllerMode's name.
  std::string controller;
};

/// Load and validate a scene file: the world, the sensor, the effects (and
/// the feature file it names). The run's program is not read: program_file
/// stays empty and the pad is not mounted ({e}T{s} the identity; loadRun()
/// mounts it as the program's controller.sensor_mount says). Errors name the
/// file and the field.
ConfigResult loadScene(const std::string& file, Scene& out);

/// The same, with overrides applied to the scene's YAML before it is read:
/// each "a.b.c=VALUE" sets key c of map b of map a (created if absent) to
/// VALUE parsed as YAML ("sensor.noise_counts=30", "rates={sim: 500}"); the
/// result is checked like the file itself (`tactile_sim run --set`). In a
/// list, a number picks an element by index and a name the element of that
/// `name` ("objects.0.radius=0.02"). A `program.` key is refused: loadRun().
ConfigResult loadScene(const std::string& file, Scene& out, const std::vector<std::string>& overrides);

/// A run: the scene (as loadScene), its program with its `base:` merged and
/// the overrides under `program.` applied to it
/// ("program.speed_law.force_budget_n=0.4",
/// "program.phases.explore.kp_per_s.x=4.8"), and the controller; then the
/// checks between them (the scene's metrics name the program's phases).
ConfigResult loadRun(const RunFiles& files, Scene& out, const std::vector<std::string>& overrides = {});

/// The run as read: the scene's document with its overrides applied, and the
/// program's with its `base:` merged and the `program.` overrides applied,
/// after loadRun() checked them in full (`tactile_sim scene`, `program`).
ConfigResult runDocuments(const RunFiles& files, const std::vector<std::string>& overrides, YAML::Node& scene,
                          YAML::Node& program);

/// Cross-checks after command-line overrides (rates, sub-samples...); with a
/// program (loadRun), also that the metrics name its phases.
ConfigResult validateScene(const Scene& s);

/// The world's parameters for a scene: scene.world with the scene's seed and
/// physics step (1 / rates.sim), as the runner and the RTT arm configure it.
WorldParams worldParams(const Scene& s);

}  // namespace sim
}  // namespace tactile
