#include "tactile_sim/sim_schema.hpp"


namespace tactile {
namespace sim {

const schema::Block<PadParams>& sensorSchema() {
  using S = PadParams;
  using F = schema::Field<S>;
  static const schema::Block<S> b{
      "sensor",
      "the simulated pad (PadSensor, pad_sensor.hpp); its rows, columns and pitch are the features file's",
      {F::whole("subsamples", "", "[1, 32]", TACTILE_SCHEMA_REF(S, subsamples),
                "K: K x K samples per taxel for the tactile image"),
       F::whole("physics_subsamples", "", "[1, 6]", TACTILE_SCHEMA_REF(S, physics_subsamples),
                "samples per taxel side for the wrench the arm feels"),
       F::num("noise_counts", "counts", "[0, 1000]", TACTILE_SCHEMA_REF(S, noise_counts),
              "Gaussian noise of a taxel, 1 sigma"),
       F::num("modulus", "Pa/m", "(0, 1e12]", TACTILE_SCHEMA_REF(S, modulus),
              "the foundation modulus of the elastic layer (Eq. 2's compliance)"),
       F::num("layer_thickness", "m", "(0, 0.05]", TACTILE_SCHEMA_REF(S, layer_thickness),
              "an object deeper than this at the start is inside the sensor"),
       F::num("housing_size_x", "m", "(0, 1]", TACTILE_SCHEMA_REF(S, housing_size_x),
              "the housing's outline along x_s (at least cols x pitch)"),
       F::num("housing_size_y", "m", "(0, 1]", TACTILE_SCHEMA_REF(S, housing_size_y),
              "the housing's outline along y_s (at least rows x pitch)"),
       F::num("housing_recess", "m", "[0, 0.05]", TACTILE_SCHEMA_REF(S, housing_recess),
              "the housing's top face below the layer's surface"),
       F::num("housing_modulus", "Pa/m", "(0, 1e13]", TACTILE_SCHEMA_REF(S, housing_modulus),
              "the penalty modulus of the rigid housing"),
       F::num("threshold", "N", ">= 0", TACTILE_SCHEMA_REF(S, threshold), "taxels below it read 0")}};
  return b;
}

const schema::Block<ArmParams>& armSchema() {
  using S = ArmParams;
  using F = schema::Field<S>;
  static const schema::Block<S> b{
      "arm",
      "the simulated LWR 4+ (LwrArm, lwr_arm.hpp): its start and the KRC's Cartesian impedance (Eq. 11)",
      {F::custom("q_init_deg", "deg", "7 values, each within its joint's range (+-170, +-120 deg)",
                 "0, -34.4, 0, 80.2, 0, -65.4, 0", "the start joints; also the null space's rest posture"),
       F::num("k_trans", "N/m", "> 0", TACTILE_SCHEMA_REF(S, k_trans), "the translational stiffness"),
       F::num("k_rot", "N m/rad", "> 0", TACTILE_SCHEMA_REF(S, k_rot), "the rotational stiffness"),
       F::num("damping_ratio", "", "[0, 10]", TACTILE_SCHEMA_REF(S, damping_ratio),
              "zeta of the impedance's damping"),
       F::num("dyn_refresh_q", "rad", "[0, 0.1]", TACTILE_SCHEMA_REF(S, dyn_refresh_q),
              "dynamics: M(q) and C(q, qd) qd re-evaluated when a joint moved more than this (0: every step)"),
       F::num("dyn_refresh_qd", "rad/s", "[0, 1]", TACTILE_SCHEMA_REF(S, dyn_refresh_qd),
              "... or a joint speed changed more than this")}};
  return b;
}

const schema::Block<WorldParams>& worldEffectsSchema() {
  using S = WorldParams;
  using F = schema::Field<S>;
  static const schema::Block<S> b{
      "effects",
      "the world's physics and timing effects, each off by default (World, world.hpp)",
      {F::num("friction_mu", "", "[0, 2]", TACTILE_SCHEMA_REF(S, friction_mu),
              "Coulomb friction of the pad on the objects (rubber on metal about 0.5-1; 0: off)"),
       F::num("friction_stiffness", "N/m", "(0, 1e7]", TACTILE_SCHEMA_REF(S, friction_stiffness),
              "the tangential stiffness of the stuck contact"),
       F::num("fri_delay_s", "s", "[0, 1]", TACTILE_SCHEMA_REF(S, fri_delay_s),
              "the delay of a command over FRI (a whole number of physics steps)"),
       F::num("krc_cycle_s", "s", "[0, 1]", TACTILE_SCHEMA_REF(S, krc_cycle_s),
              "the KRC's cycle: commands taken every this many seconds (0: every physics step)")}};
  return b;
}

const schema::Block<SensorEffects>& sensorEffectsSchema() {
  using S = SensorEffects;
  using F = schema::Field<S>;
  static const schema::Block<S> b{
      "effects",
      "the sensor's effects, each off by default (TaxelResponse, taxel_response.hpp; docs/simulator.md)",
      {F::num("wts_transfer_delay_s", "s", "[0, 1]", TACTILE_SCHEMA_REF(S, wts_transfer_delay_s),
              "the frame sampled at t reaches the reader at t + d (the serial transfer)"),
       F::num("gain_spread", "", "[0, 0.5]", TACTILE_SCHEMA_REF(S, gain_spread),
              "1-sigma relative per-taxel sensitivity spread (seeded)"),
       F::custom("dead_taxels", "", "a count in [0, rows x cols], or a list of [row, col]", "0",
                 "dead taxels: that many at seeded positions, or those listed"),
       F::num("calibration_error", "", "[0, 0.5]", TACTILE_SCHEMA_REF(S, calibration_error),
              "1-sigma relative error of the reader's calibration per taxel (seeded)"),
       F::num("crosstalk", "", "[0, 0.25]", TACTILE_SCHEMA_REF(S, crosstalk),
              "the fraction of a taxel's load spread to each 4-neighbour"),
       F::num("creep.fraction", "", "[0, 1]", TACTILE_SCHEMA_REF(S, creep_fraction),
              "under a constant load the signal tends to (1 + fraction) x its instant value"),
       F::num("creep.tau_s", "s", "(0, 1000]", TACTILE_SCHEMA_REF(S, creep_tau_s), "... with this time constant"),
       F::num("hysteresis", "", "[0, 0.5]", TACTILE_SCHEMA_REF(S, hysteresis),
              "relative half-width of the loading/unloading band"),
       F::yesNo("device_noise", TACTILE_SCHEMA_REF(S, device_noise),
                "the sensor's noise at the WTS's level (the bound the firing threshold implies), not noise_counts")}};
  return b;
}

std::string sceneSchemaMarkdown() {
  return schema::markdownSection(sensorSchema()) + "\n" + schema::markdownSection(armSchema()) + "\n" +
         schema::markdownSection(worldEffectsSchema()) +
         "\nIn the same `effects` map, the sensor's effects, each off by default (TaxelResponse, taxel_response.hpp; "
         "docs/simulator.md).\n\n" +
         schema::markdownTable(sensorEffectsSchema());
}

}  // namespace sim
}  // namespace tactile
