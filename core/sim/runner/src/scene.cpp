#include "tactile_sim_runner/scene.hpp"

#include "tactile_fri/krc_model.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>

#include "tactile_config/yaml_params.hpp"
#include "tactile_features/params_io.hpp"
#include "tactile_config/schema_yaml.hpp"
#include "tactile_servo/program_io.hpp"
#include "tactile_sim_runner/scene_schema.hpp"
#include "tactile_sim_lwr/sim_schema.hpp"
#include "tactile_sim_runner/run_log.hpp"
#include "tactile_sim_faults/sensor_faults_io.hpp"

namespace tactile {
namespace sim {

using config::checkKeys;
using config::read;
using config::readVec3;
using config::Where;

namespace {

constexpr double kDeg = kPi / 180.0;

ConfigResult fail(const Where& w, const std::string& msg) { return ConfigResult::failure(w.str() + ": " + msg); }

std::string dirOf(const std::string& file) {
  const auto p = file.find_last_of('/');
  return p == std::string::npos ? std::string(".") : file.substr(0, p);
}

std::string resolve(const std::string& base_dir, const std::string& path) {
  if (path.empty() || path[0] == '/') return path;
  return base_dir + "/" + path;
}

// One of `objects` (declared: objectSchema); its vertices read here.
ConfigResult readObject(const YAML::Node& n, const Where& w, ObjectParams& o) {
  if (!n.IsMap()) return fail(w, "must be a mapping");
  YAML::Node m = n;
  if (n["type"] && n["type"].IsScalar() && n["type"].Scalar() == "table") {  // another name of a plane
    m = YAML::Clone(n);
    m["type"] = "plane";
  }
  ConfigResult r = config::readBlock(m, w, objectSchema(), o);
  if (!r || (o.type != ObjectType::Bar && o.type != ObjectType::BentBar)) return r;
  std::vector<std::vector<double>> v;
  if (!(r = read(n, "vertices", v, w))) return r;
  o.vertices.clear();
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (v[i].size() != 3) return fail(w.child("vertices[" + std::to_string(i) + "]"), "must have 3 entries (m)");
    o.vertices.push_back({v[i][0], v[i][1], v[i][2]});
  }
  return ConfigResult::success();
}

// effects.wrench_error (declared: wrenchErrorSchema).
ConfigResult readWrenchError(const YAML::Node& n, const Where& w, WrenchErrorParams& e) {
  if (!n) return ConfigResult::success();
  ConfigResult r = config::readBlock(n, w, wrenchErrorSchema(), e);
  if (r) r = schema::checkRanges(wrenchErrorSchema(), e, w.str());
  return r;
}

// The sensor's keys of `effects` (declared: sensorEffectsSchema) beside the
// world's and the wrench error; dead_taxels read here.
ConfigResult readSensorEffects(const YAML::Node& n, const Where& w, SensorEffects& e) {
  std::vector<std::string> others = config::keysOf(worldEffectsSchema());
  others.push_back("wrench_error");
  ConfigResult r = config::readBlock(n, w, sensorEffectsSchema(), e, others);
  if (!r) return r;
  if (const YAML::Node d = n["dead_taxels"]) {
    if (d.IsSequence()) {
      std::vector<std::vector<int>> list;
      if (!(r = read(n, "dead_taxels", list, w))) return r;
      for (std::size_t i = 0; i < list.size(); ++i) {
        if (list[i].size() != 2) return fail(w.child("dead_taxels[" + std::to_string(i) + "]"), "must be [row, col]");
        e.dead_list.push_back({list[i][0], list[i][1]});
      }
    } else if (!(r = read(n, "dead_taxels", e.dead_taxels, w))) {
      return fail(w.child("dead_taxels"), "must be a count or a list of [row, col]");
    }
  }
  return schema::checkRanges(sensorEffectsSchema(), e, w.str());
}

ConfigResult readFaults(const YAML::Node& root, const Where& w, Scene& s) {
  const YAML::Node n = root["faults"];
  if (!n || n.IsNull()) return ConfigResult::success();
  if (!n.IsSequence()) return fail(w.child("faults"), "must be a list of {kind: .., start_s: .., ...}");
  for (std::size_t i = 0; i < n.size(); ++i) {
    FaultSpec f;
    ConfigResult r = readFaultSpec(n[i], w.child("faults[" + std::to_string(i) + "]"), f);
    if (!r) return r;
    s.faults.push_back(f);
  }
  return ConfigResult::success();
}

// "a.b.c=VALUE": walk (creating) maps a and b, set c to VALUE parsed as YAML.
ConfigResult applyOverride(YAML::Node& root, const std::string& o, const std::string& file) {
  const std::size_t eq = o.find('=');
  if (eq == std::string::npos || eq == 0 || o[0] == '.' || o[eq - 1] == '.')
    return ConfigResult::failure(file + ": override '" + o + "' must be key.path=value");
  std::vector<std::string> keys;
  std::size_t a = 0;
  while (a < eq) {
    const std::size_t b = std::min(o.find('.', a), eq);
    if (b == a) return ConfigResult::failure(file + ": override '" + o + "' has an empty key");
    keys.push_back(o.substr(a, b - a));
    a = b + 1;
  }
  YAML::Node value;
  try {
    value = YAML::Load(o.substr(eq + 1));
  } catch (const YAML::Exception& e) {
    return ConfigResult::failure(file + ": override '" + o + "': value is not YAML: " + e.what());
  }
  // yaml-cpp nodes are handles: reassigning one rebinds it, so descend by copies
  // of the child handles (operator[] on a non-const map creates the key).
  // A numeric key indexes a list ("objects.0.fidelity=dynamics"); another key
  // picks the list's element of that `name` ("phases.explore.kp_per_s.x=4").
  auto child = [&](YAML::Node parent, const std::string& key, YAML::Node& out) -> ConfigResult {
    if (!parent.IsSequence()) {
      out = parent[key];
      return ConfigResult::success();
    }
    char* end = nullptr;
    const unsigned long i = std::strtoul(key.c_str(), &end, 10);
    if (end != key.c_str() && *end == '\0' && i < parent.size()) {
      out = parent[i];
      return ConfigResult::success();
    }
    for (std::size_t j = 0; j < parent.size(); ++j)
      if (parent[j].IsMap() && parent[j]["name"] && parent[j]["name"].IsScalar() &&
          parent[j]["name"].Scalar() == key) {
        out = parent[j];
        return ConfigResult::success();
      }
    return ConfigResult::failure(file + ": override '" + o + "': " + key +
                                 " is neither an index nor the name of an element of a list of " +
                                 std::to_string(parent.size()));
  };
  std::vector<YAML::Node> path{root};
  for (std::size_t k = 0; k + 1 < keys.size(); ++k) {
    YAML::Node next;
    ConfigResult r = child(path.back(), keys[k], next);
    if (!r) return r;
    if (next && !next.IsMap() && !next.IsSequence())
      return ConfigResult::failure(file + ": override '" + o + "': " + keys[k] + " is not a map");
    path.push_back(next);
  }
  if (path.back().IsSequence()) {
    YAML::Node target;
    ConfigResult r = child(path.back(), keys.back(), target);
    if (!r) return r;
    target = value;
  } else {
    path.back()[keys.back()] = value;
  }
  return ConfigResult::success();
}

}  // namespace

ConfigResult loadScene(const std::string& file, Scene& s) { return loadScene(file, s, {}); }

namespace {

// One mounting transform {e}T{s}: the program's controller.sensor_mount (what
// the robot uses).
void mountPad(Scene& s) {
  const KDL::Frame& m = s.servo.sensor_mount;
  double x, y, z, qw;
  m.M.GetQuaternion(x, y, z, qw);
  s.world.pad.mount.p = {m.p.x(), m.p.y(), m.p.z()};
  s.world.pad.mount.q = {x, y, z, qw};
}

// The run's phase program, its base merged and the `program.` overrides
// applied; the controller the run names, or the program's controller.mode.
ConfigResult readProgram(const RunFiles& files, const std::vector<std::string>& program_overrides, Scene& s) {
  ConfigResult r = ConfigResult::success();
  if (files.program.empty())
    return ConfigResult::failure(files.scene + ": a run needs a phase program (params/programs/*.yaml) beside its scene");
  s.program_file = files.program;
  YAML::Node doc;  // its `base:` merged, then the overrides of its keys
  if (!(r = loadProgramDocument(s.program_file, doc))) return r;
  for (const std::string& o : program_overrides)
    if (!(r = applyOverride(doc, o, s.program_file))) return r;
  if (!(r = loadServoProgram(doc, s.program_file, s.servo))) return r;
  mountPad(s);
  s.controller = s.servo.mode;
  if (!files.controller.empty() && !parseControllerMode(files.controller, s.controller))
    return ConfigResult::failure(files.scene + ": controller '" + files.controller + "' must be " +
                                 kControllerModeNames);
  return ConfigResult::success();
}

// A scene names the world only: the keys a run binds are refused with where
// they belong.
ConfigResult refuseRunKeys(const YAML::Node& root, const Where& w) {
  for (const char* key : {"program", "controller"})
    if (root.IsMap() && root[key])
      return fail(w.child(key), "a scene does not name its run's " + std::string(key) +
                                     ": the experiment registry (experiments.yaml) binds scene, program and "
                                     "controller, as does `tactile_sim run SCENE --program FILE [--controller C]`");
  return ConfigResult::success();
}

// features_file: the features' parameters and the sensor's calibration.
ConfigResult readFeaturesFile(const YAML::Node& root, const Where& w, const std::string& file, const std::string& dir, Scene& s) {
  ConfigResult r = ConfigResult::success();
  std::string features_file;
  if (!(r = read(root, "features_file", features_file, w))) return r;
  if (!features_file.empty()) {
    YAML::Node fr;
    const std::string ff = resolve(dir, features_file);
    if (!(r = config::loadFile(ff, fr))) return ConfigResult::failure(file + ": features_file: " + r.message());
    if (!(r = loadFeatureParams(fr["features"], Where{ff, "features"}, s.features))) return r;
    // The sensor's calibration: the reader's (SensorStage) and, inverted, the
    // simulated sensor's response (TaxelResponse): one source for both.
    if (!(r = loadCalibrationParams(fr["calibration"], Where{ff, "calibration"}, s.features.rows, s.features.cols,
                                    s.calibration)))
      return r;
    s.world.pad.use_calibration = true;
    s.world.pad.calibration = s.calibration;
  }
  return ConfigResult::success();
}

// seed (a whole number; the rest of the run's keys: sceneSchema()).
ConfigResult readSeed(const YAML::Node& root, const Where& w, Scene& s) {
  int seed = 1;
  const ConfigResult r = read(root, "seed", seed, w);
  if (r) s.seed = static_cast<uint64_t>(seed);
  return r;
}

// The pad (sensor), sized as the features read it, and its calibration (its
// mount: the run's program, mountPad()).
ConfigResult readSensor(const YAML::Node& root, const Where& w, Scene& s) {
  ConfigResult r = ConfigResult::success();
  PadParams& pad = s.world.pad;
  if (const YAML::Node n = root["sensor"]) {
    const Where ws = w.child("sensor");
    if (!(r = config::readBlock(n, ws, sensorSchema(), pad))) return r;
  }
  pad.rows = s.features.rows;
  pad.cols = s.features.cols;
  pad.pitch = s.features.pitch;
  s.calibration = PadSensor::calibrationOf(pad);  // the file's (features_file), else the pad's default response
  // The reader is characterised for the sensor it reads: its noise figure
  // (SensorStage: alpha_z test, sub-threshold estimate) is the pad's.
  s.calibration.noise_counts = pad.noise_counts;
  return ConfigResult::success();
}

// The arm (arm) and its start (initial_flange).
ConfigResult readArm(const YAML::Node& root, const Where& w, Scene& s) {
  ConfigResult r = ConfigResult::success();
  if (const YAML::Node n = root["arm"]) {
    const Where wa = w.child("arm");
    if (!(r = config::readBlock(n, wa, armSchema(), s.world.arm))) return r;  // q_init_deg: below
    std::vector<double> q;
    if (!(r = read(n, "q_init_deg", q, wa))) return r;
    if (n["q_init_deg"]) {
      if (q.size() != 7) return fail(wa.child("q_init_deg"), "must have 7 entries (deg)");
      for (std::size_t i = 0; i < 7; ++i) s.world.arm.q_init[i] = q[i] * kDeg;
    }
    if (!(r = schema::checkRanges(armSchema(), s.world.arm, wa.str()))) return r;
  }
  if (const YAML::Node n = root["initial_flange"]) {
    InitialFlange f;
    const Where wi = w.child("initial_flange");
    if (!(r = config::readBlock(n, wi, initialFlangeSchema(), f))) return r;
    if (!(r = schema::checkRanges(initialFlangeSchema(), f, wi.str()))) return r;
    const Vec3& xyz = f.xyz;
    const Vec3& rpy = f.rpy_deg;
    const KDL::Rotation R = KDL::Rotation::RPY(rpy[0] * kDeg, rpy[1] * kDeg, rpy[2] * kDeg);
    double x, y, z, qw;
    R.GetQuaternion(x, y, z, qw);
    s.world.use_initial_flange_pose = true;
    s.world.initial_flange_pose.p = xyz;
    s.world.initial_flange_pose.q = {x, y, z, qw};
  }
  return ConfigResult::success();
}

// objects: the list, each with its per-body fidelity.
ConfigResult readObjects(const YAML::Node& root, const Where& w, Scene& s) {
  ConfigResult r = ConfigResult::success();
  if (const YAML::Node n = root["objects"]) {
    if (!n.IsSequence()) return fail(w.child("objects"), "must be a list");
    for (std::size_t i = 0; i < n.size(); ++i) {
      ObjectParams o;
      const Where wo = w.child("objects[" + std::to_string(i) + "]");
      if (!(r = readObject(n[i], wo, o))) return r;
      // Per-body fidelity (only the tray moves): dynamics on a quasi-static arm.
      if (o.type == ObjectType::Tray && n[i]["fidelity"]) {
        std::string f;
        Fidelity fo = Fidelity::QuasiStatic;
        if (!(r = read(n[i], "fidelity", f, wo))) return r;
        if (!parseFidelity(f, fo)) return fail(wo.child("fidelity"), "'" + f + "' must be quasi_static | dynamics");
        if (fo != s.world.fidelity && s.world.fidelity == Fidelity::Dynamics)
          return fail(wo.child("fidelity"), "quasi_static tray on a dynamics arm is not modelled: must be dynamics "
                                            "(or set fidelity: quasi_static for the arm)");
        s.world.tray_dynamics = fo == Fidelity::Dynamics && s.world.fidelity == Fidelity::QuasiStatic;
      }
      if (o.name.empty()) o.name = "objects[" + std::to_string(i) + "]";
      s.world.objects.push_back(o);
    }
  }
  return ConfigResult::success();
}

// effects: physics, timing, the sensor's effects and the wrench error.
ConfigResult readEffects(const YAML::Node& root, const Where& w, Scene& s) {
  ConfigResult r = ConfigResult::success();
  // Effects (each off by default): physics and timing are World's, the
  // sensor's are TaxelResponse's (readSensorEffects).
  if (const YAML::Node n = root["effects"]) {
    const Where we = w.child("effects");
    // The world's keys (declared: sim_schema.hpp) beside the sensor's effects
    // and the wrench error, each read by its own reader.
    std::vector<std::string> others = config::keysOf(sensorEffectsSchema());
    others.push_back("wrench_error");
    if (!(r = config::readBlock(n, we, worldEffectsSchema(), s.world, others))) return r;
    if (!(r = readSensorEffects(n, we, s.sensor_effects))) return r;
    if (!(r = readWrenchError(n["wrench_error"], we.child("wrench_error"), s.wrench_error))) return r;
    if (!(r = schema::checkRanges(worldEffectsSchema(), s.world, we.str()))) return r;
  }
  return ConfigResult::success();
}

// fri_file, and the KRC's script (krc) parsed to check it.
ConfigResult readFriKeys(const YAML::Node& root, const Where& w, const std::string& file, const std::string& dir, Scene& s) {
  ConfigResult r = ConfigResult::success();
  std::string fri_file;
  if (!(r = read(root, "fri_file", fri_file, w))) return r;
  s.fri_file = fri_file.empty() ? std::string() : resolve(dir, fri_file);
  {
    fri::KrcScript krc;
    if (!(r = krc.parse(s.krc, file + ": krc"))) return r;
  }
  return ConfigResult::success();
}

// metrics.criteria (the rest of metrics: sceneSchema()).
ConfigResult readCriteria(const YAML::Node& c, const Where& wc, Scene& s) {
  if (!c) return ConfigResult::success();
  if (!c.IsMap()) return fail(wc, "must be a map: metric: {min: .., max: ..}");
  ConfigResult r = ConfigResult::success();
  for (const auto& kv : c) {
    Criterion cr;
    cr.metric = kv.first.as<std::string>();
    const Where wk = wc.child(cr.metric);
    double probe = 0;
    if (!summaryMetric(Summary{}, cr.metric, probe)) return fail(wk, "not a summary.json metric");
    if (!kv.second.IsMap() || (!kv.second["min"] && !kv.second["max"]))
      return fail(wk, "must be {min: .., max: ..} (at least one bound)");
    if (!(r = checkKeys(kv.second, wk, {"min", "max"})) || !(r = read(kv.second, "min", cr.min, wk)) ||
        !(r = read(kv.second, "max", cr.max, wk)))
      return r;
    if (!(cr.min <= cr.max)) return fail(wk, "min must be <= max");
    s.metrics.criteria.push_back(cr);
  }
  return r;
}

}  // namespace

namespace {

/// The scene file with its own overrides applied; `program_overrides` gets
/// those of the run's program ("program.KEY.PATH=VALUE", without "program.").
ConfigResult sceneWithOverrides(const std::string& file, const std::vector<std::string>& overrides, YAML::Node& root,
                                std::vector<std::string>& program_overrides) {
  ConfigResult r = config::loadFile(file, root);
  if (!r) return r;
  for (const std::string& o : overrides) {
    const bool of_program = o.rfind("program.", 0) == 0 && o.find('=') > 8;
    if (of_program) program_overrides.push_back(o.substr(8));
    else if (!(r = applyOverride(root, o, file))) return r;
  }
  return r;
}

// The scene's own keys, read into `s` (its run's program aside).
ConfigResult readSceneKeys(const std::string& file, const YAML::Node& root, Scene& s) {
  const Where w{file, ""};
  s = Scene{};
  s.file = file;
  const std::string dir = dirOf(file);
  ConfigResult r = refuseRunKeys(root, w);
  if (!r) return r;
  if (!(r = config::readBlock(root, w, sceneSchema(), s))) return r;  // ranges: validateScene
  if (!(r = readFeaturesFile(root, w, file, dir, s))) return r;
  if (!(r = readSeed(root, w, s))) return r;
  if (!(r = readSensor(root, w, s))) return r;
  if (!(r = readArm(root, w, s))) return r;
  if (!(r = readObjects(root, w, s))) return r;
  if (!(r = readEffects(root, w, s))) return r;
  if (!(r = readFaults(root, w, s))) return r;
  if (!(r = readFriKeys(root, w, file, dir, s))) return r;
  return readCriteria(config::nodeAt(root, "metrics.criteria"), w.child("metrics").child("criteria"), s);
}

}  // namespace

ConfigResult runDocuments(const RunFiles& files, const std::vector<std::string>& overrides, YAML::Node& scene,
                          YAML::Node& program) {
  Scene s;
  ConfigResult r = loadRun(files, s, overrides);  // checked in full first
  std::vector<std::string> program_overrides;
  if (r) r = sceneWithOverrides(files.scene, overrides, scene, program_overrides);
  if (r) r = loadProgramDocument(s.program_file, program);
  for (const std::string& o : program_overrides)
    if (r) r = applyOverride(program, o, s.program_file);
  return r;
}

ConfigResult loadScene(const std::string& file, Scene& s, const std::vector<std::string>& overrides) {
  YAML::Node root;
  std::vector<std::string> program_overrides;
  ConfigResult r = sceneWithOverrides(file, overrides, root, program_overrides);
  if (!r) return r;
  if (!program_overrides.empty())
    return ConfigResult::failure(file + ": override 'program." + program_overrides.front() +
                                 "': a scene has no program; a run (a scene with its program) takes it");
  if (!(r = readSceneKeys(file, root, s))) return r;
  return validateScene(s);
}

ConfigResult loadRun(const RunFiles& files, Scene& s, const std::vector<std::string>& overrides) {
  YAML::Node root;
  std::vector<std::string> program_overrides;  // "program.KEY.PATH=VALUE": a key of the program
  ConfigResult r = sceneWithOverrides(files.scene, overrides, root, program_overrides);
  if (!r) return r;
  if (!(r = readSceneKeys(files.scene, root, s))) return r;
  if (!(r = readProgram(files, program_overrides, s))) return r;
  return validateScene(s);
}

TaxelResponseParams responseParams(const Scene& s) {
  TaxelResponseParams rp;
  rp.calibration = s.calibration;
  rp.noise_counts = s.world.pad.noise_counts;
  rp.threshold = s.world.pad.threshold;
  rp.seed = s.seed;
  rp.effects = s.sensor_effects;
  rp.effects.max_frame_rate_hz = s.rates.wts;  // sizes the transfer ring
  rp.faults = s.faults;
  return rp;
}

ConfigResult validateScene(const Scene& s) {
  const Where w{s.file, ""};
  // The physics step 1 / rates.sim must be one the world takes (a larger one
  // would be refused on every cycle, the arm never moving).
  if (1.0 / s.rates.sim > s.world.max_step_s + 1e-12) {
    char req[128];
    std::snprintf(req, sizeof req, "must be >= %g Hz (physics step 1 / rates.sim <= %g s)", 1.0 / s.world.max_step_s,
                  s.world.max_step_s);
    return rangeError(w.child("rates.sim").str(), s.rates.sim, req);
  }
  if (const ConfigResult r = schema::checkRanges(sceneSchema(), s, s.file + ": "); !r) return r;
  if (const ConfigResult sr = schema::checkRanges(sensorSchema(), s.world.pad, w.child("sensor").str()); !sr) return sr;
  auto known = [&](const std::string& ph) {
    for (const auto& p : s.servo.phases)
      if (p.name == ph) return true;
    return false;
  };
  if (!s.program_file.empty()) {  // a run: the metrics score its program's phases
    for (const auto& ph : s.metrics.force_phases)
      if (!known(ph)) return fail(w.child("metrics.force_phases"), "unknown phase '" + ph + "' in " + s.program_file);
    for (const auto& ph : {s.metrics.align_from, s.metrics.align_to})
      if (!ph.empty() && !known(ph))
        return fail(w.child("metrics.alignment"), "unknown phase '" + ph + "' in " + s.program_file);
  }
  {  // The sensor's response and effects (ranges: TaxelResponse::configure).
    TaxelResponse probe;
    const ConfigResult r = probe.configure(responseParams(s));
    if (!r) return ConfigResult::failure(s.file + ": " + r.message());
  }
  // The world validates objects (inside the sensor, unknown geometry...) on configure.
  World probe;
  const ConfigResult r = probe.configure(worldParams(s));
  if (!r) return ConfigResult::failure(s.file + ": " + r.message());
  return ConfigResult::success();
}

WorldParams worldParams(const Scene& s) {
  WorldParams wp = s.world;
  wp.seed = s.seed;
  wp.physics_step_s = 1.0 / s.rates.sim;
  return wp;
}

}  // namespace sim
}  // namespace tactile
