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

std::string sceneSchemaMarkdown() { return schema::markdownSection(sensorSchema()) + "\n" + schema::markdownSection(worldEffectsSchema()); }

}  // namespace sim
}  // namespace tactile
