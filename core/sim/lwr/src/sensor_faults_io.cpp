// One entry of a fault list from YAML (tactile_sim_faults/sensor_faults_io.hpp).
#include "tactile_sim_faults/sensor_faults_io.hpp"

#include "tactile_config/schema_yaml.hpp"
#include "tactile_sim_faults/fault_schema.hpp"

#include <array>
#include <cmath>
#include <vector>

namespace tactile {
namespace sim {

using config::read;
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

}  // namespace

// The keys and their ranges: faultSchema() (sim_schema.hpp); the region and
// the stuck reading: SensorFaultSchedule::configure (a scene's through validateScene).
ConfigResult readFaultSpec(const YAML::Node& n, const Where& w, FaultSpec& f) {
  if (!n.IsMap()) return fail(w, "must be a mapping {kind: .., start_s: .., ...}");
  std::string kind;
  ConfigResult r = read(n, "kind", kind, w);
  if (!r) return r;
  if (kind.empty() || kind == "none") return fail(w.child("kind"), std::string("required: ") + kSensorFaultNames);
  if (kind == "nan")
    return fail(w.child("kind"), "nan is the RTT simulated sensor's `fault` property only (raw counts cannot carry a NaN)");
  FaultSpec g;
  if (!(r = config::readBlock(n, w, faultSchema(), g))) return r;
  for (auto rr : {readSpan(n, "rows", w, g.row0, g.row1), readSpan(n, "cols", w, g.col0, g.col1),
                  read(n, "counts", g.counts, w), read(n, "force_n", g.force_n, w)})
    if (!rr) return rr;
  if ((n["counts"] && !(g.counts >= 0.0)) || (n["force_n"] && !(g.force_n >= 0.0)))
    return fail(w.child(n["counts"] ? "counts" : "force_n"), "must be >= 0");
  f = g;
  return ConfigResult::success();
}

}  // namespace sim
}  // namespace tactile
