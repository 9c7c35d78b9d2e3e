#include "tactile_sim_runner/scene_schema.hpp"

#include "tactile_sim_lwr/sim_schema.hpp"

namespace tactile {
namespace sim {

const schema::Block<Scene>& sceneSchema() {
  using S = Scene;
  using F = schema::Field<S>;
  static const schema::Block<S> b{
      "scene",
      "the top level of a scene file (Scene, scene.hpp)",
      {F::str("name", TACTILE_SCHEMA_REF(S, name), "the scene's name (the run's report)").needed(),
       F::str("description", TACTILE_SCHEMA_REF(S, description), "what the scene is, in one line").form("text"),
       F::str("figure", TACTILE_SCHEMA_REF(S, figure),
              "the paper figure its plots mirror (fig10, fig12, fig14, none)"),
       F::custom("features_file", "", "a path, relative to the scene", "none: the defaults",
                 "the sensor's features and calibration (params/sensors/wts0614.yaml, below)"),
       F::num("duration", "s", "> 0", TACTILE_SCHEMA_REF(S, duration), "simulated seconds"),
       F::custom("seed", "", "a whole number", "1", "the seed of every random effect"),
       F::choice(
           "fidelity", "quasi_static|dynamics", [](const S& s) { return static_cast<int>(s.world.fidelity); },
           [](S& s, int i) { s.world.fidelity = static_cast<Fidelity>(i); },
           "the arm's model (docs/simulator.md)"),
       F::yesNo("start_in_equilibrium", TACTILE_SCHEMA_REF(S, world.start_in_equilibrium),
                "the run starts with the pad settled on the objects"),
       F::num("rates.sim", "Hz", "> 0", TACTILE_SCHEMA_REF(S, rates.sim),
              "the arm's physics, the KRC's impedance loop (the defaults: the paper's Table 2)"),
       F::num("rates.servo", "Hz", "(0, rates.sim]", TACTILE_SCHEMA_REF(S, rates.servo), "the tactile servo"),
       F::num("rates.wts", "Hz", "(0, rates.sim]", TACTILE_SCHEMA_REF(S, rates.wts), "the WTS's frames"),
       F::num("rates.features", "Hz", "(0, rates.sim]", TACTILE_SCHEMA_REF(S, rates.features),
              "the feature extraction"),
       F::custom("sensor", "", "the block below", "", "the simulated pad: sampling, noise, threshold, layer, housing"),
       F::custom("arm", "", "the block below", "",
                 "the arm's start joints and impedance"),
       F::custom("initial_flange", "", "the block below", "none: from q_init_deg",
                 "the flange's start pose {g}T{e}"),
       F::custom("objects", "", "a list of plane, sphere, bar, bent_bar, tray", "[]", "the objects in the world"),
       F::custom("effects", "", "the block below; the sensor's effects: docs/simulator.md", "",
                 "physics, timing and sensor effects, each off by default"),
       F::custom("faults", "", "a list (Faults, below)", "[]",
                 "scheduled faults of the pad and of the arm's estimated wrench"),
       F::yesNo("through_fri", TACTILE_SCHEMA_REF(S, through_fri),
                "every command goes through FRI packets and the bridge"),
       F::custom("fri_file", "", "a path, relative to the scene", "none: the defaults", "the bridge's parameters"),
       F::str("krc", TACTILE_SCHEMA_REF(S, krc),
              "the KRC's script (friOpen, friStart, ...; '': command mode from the start)")
           .form("TIME:WORD,... (docs/lab_sim.md)"),
       F::num("metrics.transient_s", "s", ">= 0", TACTILE_SCHEMA_REF(S, metrics.transient_s),
              "the start of the scored window after the first force phase"),
       F::list("metrics.force_phases", TACTILE_SCHEMA_REF(S, metrics.force_phases),
               "the program's phases whose force error is scored"),
       F::str("metrics.alignment.from", TACTILE_SCHEMA_REF(S, metrics.align_from),
              "the phase whose entry starts the alignment time")
           .form("a phase"),
       F::str("metrics.alignment.to", TACTILE_SCHEMA_REF(S, metrics.align_to),
              "the phase whose entry ends it")
           .form("a phase"),
       F::num("metrics.force_band_n", "N", "> 0", TACTILE_SCHEMA_REF(S, metrics.force_band_n),
              "the band of the force's in-band fraction"),
       F::custom("metrics.criteria", "", "summary.json key: {min, max}", "{}",
                 "what \"the experiment passes\" means: criteria_passed")}};
  return b;
}

const schema::Block<InitialFlange>& initialFlangeSchema() {
  using S = InitialFlange;
  using F = schema::Field<S>;
  static const schema::Block<S> b{
      "initial_flange",
      "the flange's start pose {g}T{e}, reached by IK from q_init_deg; given, it replaces the arm's start",
      {F::xyz("xyz", "m", TACTILE_SCHEMA_REF(S, xyz), "the flange's origin in {g}"),
       F::xyz("rpy_deg", "deg", TACTILE_SCHEMA_REF(S, rpy_deg), "roll, pitch, yaw of {e} in {g} (KDL's RPY)")}};
  return b;
}

const schema::Block<WrenchErrorParams>& wrenchErrorSchema() {
  using S = WrenchErrorParams;
  using F = schema::Field<S>;
  static const schema::Block<S> b{
      "effects.wrench_error",
      "the error of the arm's estimated wrench (estExtTcpFT, from the joint torques) against the contact wrench: "
      "(1 + scale) F + bias + drift |p - p_0| + noise, the moments exact (EstimatedWrench); all 0: none",
      {F::vector("bias_n", "N", "x|y|z", "[-20, 20]", TACTILE_SCHEMA_VEC(S, bias_n), "a constant force offset, {g}"),
       F::vector("drift_n_per_m", "N/m", "x|y|z", "[-100, 100]", TACTILE_SCHEMA_VEC(S, drift_n_per_m),
                 "an offset growing with the flange's distance from its start (a model error that depends on the "
                 "posture), {g}"),
       F::num("scale", "", "[-0.5, 0.5]", TACTILE_SCHEMA_REF(S, scale), "the relative gain error of the force"),
       F::num("noise_n", "N", "[0, 10]", TACTILE_SCHEMA_REF(S, noise_n),
              "1-sigma noise per axis, a function of (seed, time) only")}};
  return b;
}

std::string sceneFileSchemaMarkdown() {
  return schema::markdownSection(sceneSchema()) + "\n" + schema::markdownSection(initialFlangeSchema()) + "\n" +
         schema::markdownSection(objectSchema()) + "\n" + sceneSchemaMarkdown() + "\n" +
         schema::markdownSection(wrenchErrorSchema());
}

}  // namespace sim
}  // namespace tactile
