// One entry of a fault list from YAML (tactile_sim/sensor_faults_io.hpp).
#include "tactile_sim/sensor_faults_io.hpp"

#include <array>
#include <cmath>
#include <vector>

namespace tactile {
namespace sim {

using config::checkKeys;
using config::read;
using config::readVec3;
using config::Where;

namespace {

ConfigResult fail(const Where& w, const std::string& msg) { return ConfigResult::failure(w.str() + ": " + msg); }

// rows / cols of a fault: [first, last] or one index.
ConfigResult readSpan(const YAML::Node& n, const char* key, const Where& w, int& a, int& b) {
  const YAML::Node v = n[key];
  if (!v) return ConfigResult::success();
  std::vector<int> span;
  if (v.IsScalar()) {
    int i = 0;
    ConfigResult r = read(n, key, i, w);
    if (!r) return r;
    span = {i, i};
  } else if (ConfigResult r = read(n, key, span, w); !r) {
    return r;
  }
  if (span.size() != 2) return fail(w.child(key), "must be [first, last] (taxel indices from 0, inclusive) or one index");
  a = span[0];
  b = span[1];
  return ConfigResult::success();
}

// The keys a fault of this kind takes besides kind, start_s and duration_s.
ConfigResult checkFaultKeys(const YAML::Node& n, const Where& w, SensorFault k) {
  switch (k) {
    case SensorFault::Stuck:
      return checkKeys(n, w, {"kind", "start_s", "duration_s", "rows", "cols", "counts", "force_n"});
    case SensorFault::Dead: return checkKeys(n, w, {"kind", "start_s", "duration_s", "rows", "cols"});
    case SensorFault::TareCreep: return checkKeys(n, w, {"kind", "start_s", "duration_s", "counts_per_min"});
    case SensorFault::Calibration: return checkKeys(n, w, {"kind", "start_s", "duration_s", "scale"});
    case SensorFault::WrenchBias: return checkKeys(n, w, {"kind", "start_s", "duration_s", "bias_n"});
    case SensorFault::WrenchDrift: return checkKeys(n, w, {"kind", "start_s", "duration_s", "drift_n_per_min"});
    case SensorFault::WrenchFrame: return checkKeys(n, w, {"kind", "start_s", "duration_s", "axes"});
    case SensorFault::PadMass: return checkKeys(n, w, {"kind", "start_s", "duration_s", "mass_kg"});
    default: return checkKeys(n, w, {"kind", "start_s", "duration_s"});
  }
}

}  // namespace

// Ranges: SensorFaultSchedule::configure (a scene's through validateScene).
ConfigResult readFaultSpec(const YAML::Node& n, const Where& w, FaultSpec& f) {
  if (!n.IsMap()) return fail(w, "must be a mapping {kind: .., start_s: .., ...}");
  std::string kind;
  ConfigResult r = read(n, "kind", kind, w);
  if (!r) return r;
  if (kind.empty() || kind == "none") return fail(w.child("kind"), std::string("required: ") + kSensorFaultNames);
  if (!parseSensorFault(kind, f.kind)) return fail(w.child("kind"), "'" + kind + "' must be " + kSensorFaultNames);
  if (f.kind == SensorFault::Nan)
    return fail(w.child("kind"), "nan is the RTT simulated sensor's `fault` property only (raw counts cannot carry a NaN)");
  if (!(r = checkFaultKeys(n, w, f.kind))) return r;
  std::array<double, 3> bias{0, 0, 0}, drift{0, 0, 0};
  std::string axes = "flange";
  for (auto rr : {read(n, "start_s", f.start_s, w), read(n, "duration_s", f.duration_s, w),
                  readSpan(n, "rows", w, f.row0, f.row1), readSpan(n, "cols", w, f.col0, f.col1),
                  read(n, "counts", f.counts, w), read(n, "force_n", f.force_n, w),
                  read(n, "counts_per_min", f.counts_per_min, w), read(n, "scale", f.scale, w),
                  readVec3(n, "bias_n", bias, w), readVec3(n, "drift_n_per_min", drift, w), read(n, "axes", axes, w),
                  read(n, "mass_kg", f.mass_kg, w)})
    if (!rr) return rr;
  if ((n["counts"] && !(f.counts >= 0.0)) || (n["force_n"] && !(f.force_n >= 0.0)))
    return fail(w.child(n["counts"] ? "counts" : "force_n"), "must be >= 0");
  f.bias_n = bias;
  f.drift_n_per_min = drift;
  if (axes == "flange") f.axes = WrenchAxes::Flange;
  else if (axes == "sensor") f.axes = WrenchAxes::Sensor;
  else return fail(w.child("axes"), "'" + axes + "' must be flange or sensor");
  return ConfigResult::success();
}

}  // namespace sim
}  // namespace tactile
