#include "tactile_sim_faults/fault_schema.hpp"

namespace tactile {
namespace sim {

const schema::Block<FaultSpec>& faultSchema() {
  using S = FaultSpec;
  using F = schema::Field<S>;
  static const char* const kOther =
      "saturated|stuck|dead|tare_creep|calibration|wrench_bias|wrench_drift|wrench_frame|wrench_sign|pad_mass";
  static const schema::Block<S> b{
      "faults[]",
      "one scheduled fault of the pad or of the arm's estimated wrench (SensorFaultSchedule, sensor_faults.hpp); "
      "its keys depend on its `kind`",
      {F::choice(
           "kind",
           "|stale|disconnect|nan|saturated|stuck|dead|tare_creep|repeat|calibration|wrench_bias|wrench_drift|"
           "wrench_frame|wrench_sign|pad_mass",
           [](const S& s) { return static_cast<int>(s.kind); },
           [](S& s, int i) { s.kind = static_cast<SensorFault>(i); },
           "the fault (each kind's effect: below; nan: the RTT simulated sensor's `fault` property only)")
           .needed(),
       F::num("start_s", "s", ">= 0", TACTILE_SCHEMA_REF(S, start_s), "when it starts, simulated time (0: static)"),
       F::num("duration_s", "s", "(0, 60]", TACTILE_SCHEMA_REF(S, duration_s), "the length of the window")
           .only("stale|repeat|disconnect"),
       F::num("duration_s", "s", ">= 0", TACTILE_SCHEMA_REF(S, duration_s), "how long it lasts (0: to the end)")
           .only(kOther),
       F::custom("rows", "", "[first, last] within the pad's rows, or one index", "all rows",
                 "the region's rows, indices from 0 in {s}, inclusive")
           .only("stuck|dead"),
       F::custom("cols", "", "[first, last] within the pad's columns, or one index", "all columns",
                 "the region's columns")
           .only("stuck|dead"),
       F::custom("counts", "counts", "[0, full scale]; this or force_n", "", "the region's reading per taxel")
           .only("stuck"),
       F::custom("force_n", "N", "[0, 1000]; this or counts", "",
                 "the load over the region, spread evenly through the reader's calibration")
           .only("stuck"),
       F::num("counts_per_min", "counts/min", "[-4095, 4095]", TACTILE_SCHEMA_REF(S, counts_per_min),
              "every taxel's zero drifts at this rate")
           .only("tare_creep"),
       F::num("scale", "", "[0.1, 10]", TACTILE_SCHEMA_REF(S, scale), "the reader's force / the true force")
           .only("calibration"),
       F::vector("bias_n", "N", "x|y|z", "[-100, 100]", TACTILE_SCHEMA_VEC(S, bias_n),
                 "added to the estimated wrench's force, {g}")
           .only("wrench_bias"),
       F::vector("drift_n_per_min", "N/min", "x|y|z", "[-100, 100]", TACTILE_SCHEMA_VEC(S, drift_n_per_min),
                 "this rate x (t - start_s) added to it, {g}")
           .only("wrench_drift"),
       F::choice(
           "axes", "flange|sensor", [](const S& s) { return static_cast<int>(s.axes) - 1; },
           [](S& s, int i) { s.axes = static_cast<WrenchAxes>(i + 1); },
           "the axes whose components the wrench reports as {g}'s")
           .only("wrench_frame"),
       F::num("mass_kg", "kg", "[-5, 5]", TACTILE_SCHEMA_REF(S, mass_kg),
              "the load model's pad mass is off by this (true - modelled)")
           .only("pad_mass")},
      "kind"};
  return b;
}

}  // namespace sim
}  // namespace tactile
