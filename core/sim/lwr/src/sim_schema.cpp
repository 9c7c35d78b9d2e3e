#include "tactile_sim_lwr/sim_schema.hpp"


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

const schema::Block<ObjectParams>& objectSchema() {
  using S = ObjectParams;
  using F = schema::Field<S>;
  static const std::string kVerticesValid = "a list of [x, y, z]: 2 for a bar, 2 to " + std::to_string(kMaxVertices) +
                                            " for a bent bar, no two in a row equal";
  static const schema::Block<S> b{
      "objects[]",
      "one object of the world (ObjectSet, objects.hpp); its keys depend on its `type`; positions in {g}, a tray's "
      "in its own frame {t} at the bearing",
      {F::choice(
           "type", "plane|sphere|bar|bent_bar|tray", [](const S& s) { return static_cast<int>(s.type); },
           [](S& s, int i) { s.type = static_cast<ObjectType>(i); }, "the shape (table: a plane)")
           .needed(),
       F::str("name", TACTILE_SCHEMA_REF(S, name), "the object's name in messages (default: objects[i])"),
       F::xyz("point", "m", TACTILE_SCHEMA_REF(S, point), "a point of the plane").only("plane"),
       F::xyz("normal", "", TACTILE_SCHEMA_REF(S, normal), "its outward normal (out of the solid), not zero")
           .only("plane"),
       F::xyz("center", "m", TACTILE_SCHEMA_REF(S, center), "the sphere's centre").only("sphere"),
       F::num("radius", "m", "(0, 10)", TACTILE_SCHEMA_REF(S, radius), "the sphere's radius").only("sphere"),
       F::num("radius", "m", "(0, 1)", TACTILE_SCHEMA_REF(S, radius), "the bar's rounding radius")
           .only("bar|bent_bar"),
       F::custom("vertices", "m", kVerticesValid.c_str(), "[]", "the centreline")
           .only("bar|bent_bar"),
       F::xyz("bearing", "m", TACTILE_SCHEMA_REF(S, tray.bearing), "the bearing point, {g}").only("tray"),
       F::xyz("bar_from", "m", TACTILE_SCHEMA_REF(S, tray.bar_from), "the bar's centreline start, {t}").only("tray"),
       F::xyz("bar_to", "m", TACTILE_SCHEMA_REF(S, tray.bar_to), "its end, {t}, not bar_from").only("tray"),
       F::num("bar_radius", "m", "(0, 0.1)", TACTILE_SCHEMA_REF(S, tray.bar_radius), "the bar's radius")
           .only("tray"),
       F::num("tray_mass", "kg", "(0, 100)", TACTILE_SCHEMA_REF(S, tray.tray_mass), "the plate and the bar")
           .only("tray"),
       F::xyz("tray_com", "m", TACTILE_SCHEMA_REF(S, tray.tray_com), "their centre of mass, {t}").only("tray"),
       F::num("mass", "kg", "[0, 100)", TACTILE_SCHEMA_REF(S, tray.mass), "the movable weight (Sec. 5.3)")
           .only("tray"),
       F::xyz("mass_from", "m", TACTILE_SCHEMA_REF(S, tray.mass_from), "the weight before the move, {t}")
           .only("tray"),
       F::xyz("mass_to", "m", TACTILE_SCHEMA_REF(S, tray.mass_to), "after it, {t}").only("tray"),
       F::num("move_start_s", "s", "", TACTILE_SCHEMA_REF(S, tray.move_start_s), "the scripted move's start")
           .only("tray"),
       F::num("move_duration_s", "s", ">= 0", TACTILE_SCHEMA_REF(S, tray.move_duration_s),
              "the move, linear in time (0: a jump)")
           .only("tray"),
       F::num("pitch_stiffness", "N m/rad", ">= 0", TACTILE_SCHEMA_REF(S, tray.pitch_stiffness),
              "a torsional spring about x_g at the bearing")
           .only("tray"),
       F::num("roll_stiffness", "N m/rad", ">= 0", TACTILE_SCHEMA_REF(S, tray.roll_stiffness), "... about y_g")
           .only("tray"),
       F::num("bearing_damping", "N m s/rad", ">= 0", TACTILE_SCHEMA_REF(S, tray.bearing_damping),
              "the bearing's friction, both axes (dynamics)")
           .only("tray"),
       F::num("inertia_x", "kg m^2", ">= 0", TACTILE_SCHEMA_REF(S, tray.inertia_x),
              "about the bearing's x (0: from the masses)")
           .only("tray"),
       F::num("inertia_y", "kg m^2", ">= 0", TACTILE_SCHEMA_REF(S, tray.inertia_y), "... y").only("tray"),
       F::num("initial_pitch", "rad", "(-0.5, 0.5)", TACTILE_SCHEMA_REF(S, tray.initial_pitch), "the start pitch")
           .only("tray"),
       F::num("initial_roll", "rad", "(-0.5, 0.5)", TACTILE_SCHEMA_REF(S, tray.initial_roll),
              "the start roll (the tray angle)")
           .only("tray"),
       F::custom("fidelity", "", "quasi_static, dynamics (a dynamics arm: dynamics)", "the scene's",
                 "the tray's own: its inertia, springs and damping integrated in time on a quasi-static arm")
           .only("tray")},
      "type"};
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
