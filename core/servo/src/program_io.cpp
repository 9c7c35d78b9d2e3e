#include "tactile_servo/program_io.hpp"

#include <yaml-cpp/yaml.h>

#include <climits>
#include <initializer_list>
#include <cmath>
#include <cstdlib>
#include <utility>
#include <vector>

#include "tactile_config/schema_yaml.hpp"
#include "tactile_config/yaml_params.hpp"
#include "tactile_servo/servo_schema.hpp"

namespace tactile {

using config::checkKeys;
using config::read;
using config::Where;

namespace {

ConfigResult fail(const Where& w, const std::string& msg) { return ConfigResult::failure(w.str() + ": " + msg); }

bool number(const YAML::Node& n, double& v) {
  if (!n || !n.IsScalar()) return false;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    return false;
  }
  return true;
}

/// The per-cycle keys of earlier programs are rejected, never reinterpreted:
/// the error names the key and its replacement in physical units.
struct Renamed {
  const char* old_key;
  const char* new_key;
  const char* how;
};
const Renamed kRenamedGains[] = {
    {"kp", "kp_per_s", "1/s; = per-cycle kp x servo rate (x100 at 100 Hz)"},
    {"ki", "ki_per_s2", "1/s^2; = old ki (1/s) x servo rate"},
    {"integral_limit", "integral_limit_per_s", "m/s or rad/s; = per-cycle limit x servo rate"},
    {"u_max", "u_max_per_s", "m/s or rad/s; = per-cycle limit x servo rate"}};

ConfigResult rejectRenamed(const YAML::Node& n, const config::Where& w, const Renamed* r, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i)
    if (n[r[i].old_key])
      return ConfigResult::failure(w.child(r[i].old_key).str() + ": per-cycle key no longer accepted: use '" +
                                   r[i].new_key + "' (" + r[i].how + ")");
  return ConfigResult::success();
}

std::string list(const char* const* names, int n) {
  std::string s;
  for (int i = 0; i < n; ++i) s += std::string(i ? ", " : "") + names[i];
  return s;
}

/// A 6-vector as a list of 6 numbers or a mapping over `names` (absent keys
/// keep their value). `kind` is used in messages ("feature name", "axis").
ConfigResult readVec6(const YAML::Node& n, const Where& w, const char* const* names, const char* kind, Vec6& v) {
  if (!n) return ConfigResult::success();
  if (n.IsSequence()) {
    if (n.size() != 6) return fail(w, "must have 6 entries, has " + std::to_string(n.size()));
    for (std::size_t i = 0; i < 6; ++i)
      if (!number(n[i], v(static_cast<int>(i))))
        return fail(w.child(std::to_string(i)), "cannot parse '" + YAML::Dump(n[i]) + "' as a number");
    return ConfigResult::success();
  }
  if (!n.IsMap()) return fail(w, "must be a list of 6 numbers or a mapping");
  for (const auto& kv : n) {
    const std::string k = kv.first.as<std::string>();
    int idx = -1;
    for (int i = 0; i < 6; ++i)
      if (k == names[i]) idx = i;
    if (idx < 0) return fail(w.child(k), std::string("unknown ") + kind + " (allowed: " + list(names, 6) + ")");
    if (!number(kv.second, v(idx))) return fail(w.child(k), "cannot parse '" + YAML::Dump(kv.second) + "' as a number");
  }
  return ConfigResult::success();
}

ConfigResult readMat6(const YAML::Node& n, const Where& w, Mat6& m) {
  if (!n.IsSequence() || n.size() != 6)
    return fail(w, "must be a 6x6 matrix (a list of 6 rows), has " + std::to_string(n.IsSequence() ? n.size() : 0) +
                       " rows");
  for (std::size_t r = 0; r < 6; ++r) {
    const YAML::Node row = n[r];
    if (!row.IsSequence() || row.size() != 6)
      return fail(w.child(std::to_string(r)), "row must have 6 entries, has " +
                                                  std::to_string(row.IsSequence() ? row.size() : 0));
    for (std::size_t c = 0; c < 6; ++c)
      if (!number(row[c], m(static_cast<int>(r), static_cast<int>(c))))
        return fail(w.child(std::to_string(r)).child(std::to_string(c)), "cannot parse '" + YAML::Dump(row[c]) + "'");
  }
  return ConfigResult::success();
}

ConfigResult readFrame(const YAML::Node& n, const Where& w, KDL::Frame& f) {
  if (!n) return ConfigResult::success();
  ConfigResult r = checkKeys(n, w, {"xyz", "rpy_deg"});
  if (!r) return r;
  std::vector<double> xyz{0, 0, 0}, rpy{0, 0, 0};
  if (!(r = read(n, "xyz", xyz, w)) || !(r = read(n, "rpy_deg", rpy, w))) return r;
  if (xyz.size() != 3) return fail(w.child("xyz"), "must have 3 entries (m)");
  if (rpy.size() != 3) return fail(w.child("rpy_deg"), "must have 3 entries (deg)");
  const double d = kPi / 180.0;
  f = KDL::Frame(KDL::Rotation::RPY(rpy[0] * d, rpy[1] * d, rpy[2] * d), KDL::Vector(xyz[0], xyz[1], xyz[2]));
  return ConfigResult::success();
}

/// The tolerances of an `aligned` transition: a mapping over
/// kToleranceNames, each >= 0 (its presence: transitionSchema()).
ConfigResult readTolerance(const YAML::Node& tol, const Where& w, TransitionParams& t) {
  if (!tol) return ConfigResult::success();
  if (!tol.IsMap()) return fail(w, "must be a mapping feature: tolerance");
  for (const auto& kv : tol) {
    const std::string k = kv.first.as<std::string>();
    int idx = -1;
    for (int i = 0; i < kNumTol; ++i)
      if (k == kToleranceNames[i]) idx = i;
    const Where wk = w.child(k);
    if (idx < 0) return fail(wk, "unknown feature name (allowed: " + list(kToleranceNames, kNumTol) + ")");
    double v = 0;
    if (!number(kv.second, v)) return fail(wk, "cannot parse '" + YAML::Dump(kv.second) + "'");
    if (!(v >= 0)) return rangeError(wk.str(), v, "must be >= 0 (feature units: m, rad or N)");
    t.tolerance[static_cast<std::size_t>(idx)] = v;
  }
  return ConfigResult::success();
}

ConfigResult readTransition(const YAML::Node& n, const Where& w, TransitionParams& t) {
  const Renamed cyc[] = {{"cycles", "for_s", "s the condition must hold; = cycles / servo rate (cycles 20 at 100 Hz = for_s 0.2)"}};
  ConfigResult r = rejectRenamed(n, w, cyc, 1);
  if (!r) return r;
  if (!(r = config::readBlock(n, w, transitionSchema(), t))) return r;  // ranges: PhaseProgram::configure
  return readTolerance(n["tolerance"], w.child("tolerance"), t);
}

/// s_d: the rows of the feature error; `force` (N) gives the d_z row (Eq. 2:
/// d_z = C_z f).
ConfigResult readDesired(const YAML::Node& sd, const Where& w, double c_z, Vec6& s_d) {
  if (!sd) return ConfigResult::success();
  if (!(sd.IsMap() && sd["force"])) return readVec6(sd, w, kToleranceNames, "feature name", s_d);
  if (sd["d_z"]) return fail(w, "give either d_z or force, not both");
  YAML::Node copy = YAML::Clone(sd);
  double f = 0;
  if (!number(sd["force"], f)) return fail(w.child("force"), "cannot parse");
  copy.remove("force");
  ConfigResult r = readVec6(copy, w, kToleranceNames, "feature name", s_d);
  if (r) s_d(kZ) = c_z * f;
  return r;
}

/// jacobian (Eq. 8): `touch`, a fixed beta, one matrix, or a point and an
/// edge matrix chosen by the contact type.
ConfigResult readJacobian(const YAML::Node& j, const Where& wj, PhaseParams& ph) {
  if (!j) return ConfigResult::success();
  if (j.IsScalar()) {
    if (j.Scalar() != "touch") return fail(wj, "'" + j.Scalar() + "': must be 'touch' or a mapping");
    ph.jacobian = JacobianMode::Touch;
    return ConfigResult::success();
  }
  ConfigResult r = checkKeys(j, wj, {"beta", "point", "edge", "matrix"});
  if (!r) return r;
  if (j["beta"]) {
    double b = -1;
    if (!number(j["beta"], b) || (b != 0.0 && b != 1.0)) return fail(wj.child("beta"), "must be 0 (point) or 1 (edge)");
    ph.jacobian = JacobianMode::Fixed;
    ph.fixed_edge = b == 1.0;
  } else if (j["matrix"]) {
    if (!(r = readMat6(j["matrix"], wj.child("matrix"), ph.jinv_edge))) return r;
    ph.jinv_point = ph.jinv_edge;
    ph.jacobian = JacobianMode::Fixed;
    ph.fixed_edge = true;
  } else {
    if (!j["point"] || !j["edge"]) return fail(wj, "give both 'point' and 'edge' 6x6 matrices");
    if (!(r = readMat6(j["point"], wj.child("point"), ph.jinv_point))) return r;
    if (!(r = readMat6(j["edge"], wj.child("edge"), ph.jinv_edge))) return r;
    ph.jacobian = JacobianMode::Touch;
  }
  return ConfigResult::success();
}

/// P (Eq. 10): the gammas of projection(), or a 6x6 matrix.
ConfigResult readProjection(const YAML::Node& p, const Where& wp, Mat6& P) {
  if (!p) return ConfigResult::success();
  if (p.IsSequence()) return readMat6(p, wp, P);
  if (!p.IsMap()) return fail(wp, "must be a mapping of gammas or a 6x6 matrix");
  const char* const g[7] = {"x", "y", "z", "wx", "wy", "wz", "com"};
  double v[7] = {0, 0, 0, 0, 0, 0, 0};
  for (const auto& kv : p) {
    const std::string k = kv.first.as<std::string>();
    int idx = -1;
    for (int i = 0; i < 7; ++i)
      if (k == g[i]) idx = i;
    if (idx < 0) return fail(wp.child(k), "unknown gamma (allowed: " + list(g, 7) + ")");
    if (!number(kv.second, v[idx])) return fail(wp.child(k), "cannot parse '" + YAML::Dump(kv.second) + "'");
  }
  P = projection(v[0], v[1], v[2], v[3], v[4], v[5], v[6]);
  return ConfigResult::success();
}

/// A phase: `defaults` (phase_defaults) gives the gains it does not.
ConfigResult readPhase(const YAML::Node& n, const Where& w0, const PhaseParams& defaults, double c_z, PhaseParams& ph) {
  if (!n.IsMap()) return fail(w0, "each phase must be a mapping");
  if (!n["name"]) return fail(w0.child("name"), "required");
  ConfigResult r = read(n, "name", ph.name, w0);
  if (!r) return r;
  const Where w{w0.file, "phases." + ph.name};
  if (!(r = rejectRenamed(n, w, kRenamedGains, 4))) return r;
  ph.kp = defaults.kp;
  ph.ki = defaults.ki;
  ph.integral_limit = defaults.integral_limit;
  ph.u_max = defaults.u_max;
  bool terminal = false;
  if (!(r = read(n, "terminal", terminal, w))) return r;
  ph.max_duration_s = terminal ? 0.0 : defaults.max_duration_s;  // a terminal phase is meant to last
  if (!(r = config::readBlock(n, w, phaseSchema(), ph))) return r;  // ranges: ControlLaw::configure
  if (!(r = readDesired(n["s_d"], w.child("s_d"), c_z, ph.s_d))) return r;
  if (!(r = readJacobian(n["jacobian"], w.child("jacobian"), ph))) return r;
  if (!(r = readProjection(n["P"], w.child("P"), ph.P))) return r;
  if (const YAML::Node ts = n["transitions"]) {
    if (!ts.IsSequence()) return fail(w.child("transitions"), "must be a list");
    for (std::size_t i = 0; i < ts.size(); ++i) {
      TransitionParams t;
      if (!(r = readTransition(ts[i], w.child("transitions[" + std::to_string(i) + "]"), t))) return r;
      ph.transitions.push_back(t);
    }
  }
  return ConfigResult::success();
}

/// speed_law: one block in the file over two structs, the law's own keys
/// (SpeedLawParams) and the servo's (SpeedLawConfig); the ranges and the phase
/// names are checked by TactileServo::configure (loadImpl's last step).
ConfigResult readSpeedLaw(const YAML::Node& sl, const Where& w, SpeedLawConfig& c) {
  ConfigResult r = config::readBlock(sl, w, speedLawServoSchema(), c, config::keysOf(speedLawSchema()));
  if (!r) return r;
  return config::readBlock(sl, w, speedLawSchema(), c.law, config::keysOf(speedLawServoSchema()));
}

// loadImpl's blocks, each its own step: the node given, `w` the block's key.
ConfigResult readController(const YAML::Node& c, const Where& w, ServoParams& p) {
  ConfigResult r = config::readBlock(c, w, controllerSchema(), p, {"motion_sign", "sensor_mount"});
  if (!r) return r;
  if (!(r = readVec6(c["motion_sign"], w.child("motion_sign"), kAxisNames, "axis", p.motion_sign))) return r;
  return readFrame(c["sensor_mount"], w.child("sensor_mount"), p.sensor_mount);
}

ConfigResult readSafety(const YAML::Node& s, const Where& w, SafetyParams& sp) {
  const Renamed steps[] = {
      {"max_trans_step", "max_trans_speed", "m/s; = per-cycle step x servo rate (0.0005 m at 100 Hz = 0.05 m/s)"},
      {"max_rot_step_deg", "max_rot_speed_deg", "deg/s; = per-cycle step x servo rate (0.5 deg at 100 Hz = 50 deg/s)"}};
  const ConfigResult r = rejectRenamed(s, w, steps, 2);
  if (!r) return r;
  return config::readBlock(s, w, safetySchema(), sp);
}

ConfigResult readForceEstimate(const YAML::Node& fe, const Where& w, ForceEstimateParams& fp) {
  ConfigResult r = config::readBlock(fe, w, forceEstimateSchema(), fp);
  if (!r) return r;
  ForceEstimator probe;
  return probe.configure(fp, w.str().c_str());
}

ConfigResult readPhaseDefaults(const YAML::Node& pd, const Where& w, PhaseParams& d) {
  ConfigResult r;
  if (!(r = rejectRenamed(pd, w, kRenamedGains, 4))) return r;
  if (!(r = config::readBlock(pd, w, phaseDefaultsSchema(), d))) return r;
  return schema::checkRanges(phaseDefaultsSchema(), d, w.str());
}

ConfigResult loadImpl(const YAML::Node& root, const std::string& file, ServoParams& out) {
  ServoParams p;
  p.source = file;
  const Where top{file, ""};
  ConfigResult r = checkKeys(root, top, {"controller", "safety", "watchdogs", "force_estimate", "speed_law", "slope_feedforward",
                                         "phase_defaults", "phases"});
  if (!r) return r;
  if (const YAML::Node c = root["controller"]) {
    if (!(r = readController(c, top.child("controller"), p))) return r;
  }
  if (const YAML::Node s = root["safety"]) {
    if (!(r = readSafety(s, top.child("safety"), p.safety))) return r;
  }
  if (const YAML::Node wd = root["watchdogs"]) {
    if (!(r = config::readBlock(wd, top.child("watchdogs"), watchdogSchema(), p.watchdogs))) return r;
  }
  if (const YAML::Node fe = root["force_estimate"]) {
    if (!(r = readForceEstimate(fe, top.child("force_estimate"), p.force_estimate))) return r;
  }
  if (const YAML::Node sl = root["speed_law"]) {
    if (!(r = readSpeedLaw(sl, top.child("speed_law"), p.speed_law))) return r;
  }
  if (const YAML::Node sf = root["slope_feedforward"]) {
    if (!(r = config::readBlock(sf, top.child("slope_feedforward"), slopeFeedforwardSchema(), p.slope_feedforward)))
      return r;
  }
  PhaseParams d;  // phase_defaults: the gains and time limit of every phase
  if (const YAML::Node pd = root["phase_defaults"]) {
    if (!(r = readPhaseDefaults(pd, top.child("phase_defaults"), d))) return r;
  }
  const YAML::Node phases = root["phases"];
  if (!phases || !phases.IsSequence() || phases.size() == 0)
    return fail(top.child("phases"), "required: a non-empty list of phases");
  for (std::size_t i = 0; i < phases.size(); ++i) {
    PhaseParams ph;
    if (!(r = readPhase(phases[i], top.child("phases[" + std::to_string(i) + "]"), d, p.c_z, ph))) return r;
    p.phases.push_back(ph);
  }
  TactileServo scratch;  // full validation (ranges, targets, reachability)
  if (!(r = scratch.configure(p))) return r;
  out = p;
  return ConfigResult::success();
}

}  // namespace

// ---- `base:` overlays (configuration time only) ----------------------------

namespace {

std::string dirOf(const std::string& file) {
  const std::size_t slash = file.rfind('/');
  return slash == std::string::npos ? std::string() : file.substr(0, slash + 1);
}

/// The file's absolute path with links resolved (the identity a cycle is
/// detected on); the path as given when it cannot be resolved.
std::string identity(const std::string& file) {
  char buf[PATH_MAX];
  return ::realpath(file.c_str(), buf) ? std::string(buf) : file;
}

/// A list merged element by element: every element of both lists is a
/// mapping with a scalar `name` (the phases).
bool namedList(const YAML::Node& n) {
  if (!n.IsSequence() || n.size() == 0) return false;
  for (const auto& e : n)
    if (!e.IsMap() || !e["name"] || !e["name"].IsScalar()) return false;
  return true;
}

const char* const kOverlayRule = "an overlay changes its base's phases by name; new phases go under add_phases";

/// Merges `over` into `base` (a private copy, changed in place): a mapping key
/// by key, recursively (a key the base lacks is added); a named list element
/// by element by name (a name the base lacks is an error naming it); anything
/// else (scalar, other list, a change of kind) replaces. `~` removes the
/// base's key (one the base lacks is an error).
ConfigResult mergeInto(YAML::Node base, const YAML::Node& over, const Where& w, const std::string& base_file) {
  const YAML::Node& cbase = base;  // const lookups never insert
  if (namedList(cbase) && namedList(over)) {
    std::vector<std::string> seen;
    for (const auto& item : over) {
      const std::string name = item["name"].Scalar();
      const Where wi{w.file, w.path + "[" + name + "]"};
      for (const std::string& s : seen)
        if (s == name) return fail(wi, "given twice");
      seen.push_back(name);
      std::size_t idx = cbase.size();
      std::string names;
      for (std::size_t i = 0; i < cbase.size(); ++i) {
        const std::string bn = cbase[i]["name"].Scalar();
        names += (i ? ", " : "") + bn;
        if (bn == name) idx = i;
      }
      if (idx == cbase.size())
        return fail(wi, "no element named '" + name + "' in the base " + base_file + " (names: " + names + "; " +
                            kOverlayRule + ")");
      ConfigResult r = mergeInto(base[idx], item, wi, base_file);
      if (!r) return r;
    }
    return ConfigResult::success();
  }
  for (const auto& kv : over) {
    const std::string k = kv.first.as<std::string>();
    const Where wk = w.child(k);
    const YAML::Node b = cbase[k];
    const YAML::Node& v = kv.second;
    if (!b) {  // added: the reader rejects a key it does not know, at every level
      if (v.IsNull()) return fail(wk, "not in the base " + base_file + " (~ removes a key of the base)");
      base[k] = YAML::Clone(v);
      continue;
    }
    if (v.IsNull()) {
      base.remove(k);
    } else if (b.IsMap() && v.IsMap()) {
      ConfigResult r = mergeInto(base[k], v, wk, base_file);
      if (!r) return r;
    } else if (namedList(b) && namedList(v)) {
      ConfigResult r = mergeInto(base[k], v, wk, base_file);
      if (!r) return r;
    } else {
      base[k] = YAML::Clone(v);
    }
  }
  return ConfigResult::success();
}

/// An overlay's `add_phases`: whole phases appended after the base's, each
/// with a name the base's phases do not have (those change under `phases`).
ConfigResult appendPhases(YAML::Node merged, const YAML::Node& added, const Where& w, const std::string& base_file) {
  if (!namedList(added)) return fail(w, "must be a list of phases, each a mapping with a name");
  const YAML::Node& cmerged = merged;
  if (!cmerged["phases"] || !namedList(cmerged["phases"]))
    return fail(w, "the base " + base_file + " has no list of phases to add to");
  YAML::Node phases = merged["phases"];
  const std::size_t in_base = phases.size();
  for (const auto& item : added) {
    const std::string name = item["name"].Scalar();
    for (std::size_t i = 0; i < phases.size(); ++i)
      if (phases[i]["name"].Scalar() == name)
        return fail(Where{w.file, w.path + "[" + name + "]"},
                    i < in_base ? "a phase of that name is in the base " + base_file + " (change it under phases)"
                                : std::string("given twice"));
    phases.push_back(YAML::Clone(item));
  }
  return ConfigResult::success();
}

/// `root` (read from `file`) with its `base:` chain resolved; `chain` holds
/// the identities of the files that lead here (a cycle is an error).
ConfigResult resolveBase(const YAML::Node& root, const std::string& file, std::vector<std::string>& chain,
                         YAML::Node& out) {
  const YAML::Node base_key = root.IsMap() ? root["base"] : YAML::Node();
  if (!base_key) {
    out = root;
    return ConfigResult::success();
  }
  const Where wb{file, "base"};
  if (!base_key.IsScalar() || base_key.Scalar().empty())
    return fail(wb, "must be the path of another program file (relative to this file)");
  const std::string rel = base_key.Scalar();
  const std::string base_file = !rel.empty() && rel[0] == '/' ? rel : dirOf(file) + rel;
  chain.push_back(identity(file));
  const std::string id = identity(base_file);
  for (std::size_t i = 0; i < chain.size(); ++i)
    if (chain[i] == id) {
      std::string loop;
      for (std::size_t j = i; j < chain.size(); ++j) loop += chain[j] + " -> ";
      return fail(wb, "'" + rel + "' is a cycle of bases: " + loop + id);
    }
  YAML::Node base_root;
  ConfigResult r = config::loadFile(base_file, base_root);
  if (!r) return fail(wb, "'" + rel + "': " + r.message());
  YAML::Node merged;
  if (!(r = resolveBase(base_root, base_file, chain, merged))) return r;
  merged = YAML::Clone(merged);
  YAML::Node own = YAML::Clone(root);
  own.remove("base");
  const YAML::Node& cown = own;
  const bool adds = static_cast<bool>(cown["add_phases"]);
  const YAML::Node added = adds ? YAML::Clone(cown["add_phases"]) : YAML::Node();
  if (adds) own.remove("add_phases");
  if (!(r = mergeInto(merged, own, Where{file, ""}, base_file))) return r;
  if (adds && !(r = appendPhases(merged, added, Where{file, "add_phases"}, base_file))) return r;
  out = merged;
  return ConfigResult::success();
}

}  // namespace

ConfigResult resolveProgramBase(const YAML::Node& root, const std::string& file, YAML::Node& out) {
  try {
    std::vector<std::string> chain;
    return resolveBase(root, file, chain, out);
  } catch (const YAML::Exception& e) {
    return ConfigResult::failure((file.empty() ? std::string("<memory>") : file) + ": " + e.what());
  }
}

ConfigResult loadProgramDocument(const std::string& file, YAML::Node& out) {
  YAML::Node root;
  ConfigResult r = config::loadFile(file, root);
  if (!r) return r;
  return resolveProgramBase(root, file, out);
}

ConfigResult loadServoProgram(const YAML::Node& root, const std::string& file, ServoParams& out) {
  YAML::Node merged;
  ConfigResult r = resolveProgramBase(root, file, merged);
  if (!r) return r;
  try {
    return loadImpl(merged, file, out);
  } catch (const YAML::Exception& e) {
    return ConfigResult::failure((file.empty() ? std::string("<memory>") : file) + ": " + e.what());
  }
}

ConfigResult loadServoProgram(const std::string& file, ServoParams& out) {
  YAML::Node root;
  ConfigResult r = config::loadFile(file, root);
  if (!r) return r;
  return loadServoProgram(root, file, out);
}

}  // namespace tactile
