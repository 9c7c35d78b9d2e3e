// Phase-program files: the shipped ones load; bad ones are rejected at
// configure time with a message naming the file, the phase and the field.
#include <cstdio>
#include <fstream>

#include "servo_test_util.hpp"
#include "temp_file.hpp"

using namespace tactile;
using namespace servo_test;

namespace {

std::string writeTemp(const std::string& name, const std::string& text) {
  return tactile::test::writeTempFile("servo_" + name + ".yaml", text);
}

// A valid two-phase program; `phase2` is spliced in as the second phase's body.
std::string program(const std::string& phase1_extra, const std::string& phase2 = "") {
  return "controller: {pose_update: measured}\n"
         "phases:\n"
         "  - name: approach\n"
         "    P: {}\n"
         "    requires_contact: false\n"
         "    transitions: [{on: contact, to: hold}]\n" +
         phase1_extra +
         "  - name: hold\n" +
         (phase2.empty() ? std::string("    P: {y: 1, z: 1}\n    kp_per_s: {y: 3, z: 3}\n") : phase2);
}

void expectRejected(const std::string& name, const std::string& text, std::initializer_list<const char*> parts) {
  const std::string path = writeTemp(name, text);
  ServoParams p;
  const ConfigResult r = loadServoProgram(path, p);
  ASSERT_FALSE(r.ok()) << name;
  EXPECT_NE(r.message().find(path), std::string::npos) << r.message();
  for (const char* part : parts) EXPECT_NE(r.message().find(part), std::string::npos) << name << ": " << r.message();
}

}  // namespace

TEST(ServoProgramIo, ShippedProgramsLoadAndConfigure) {
  for (const char* f : {"edge_exploration.yaml", "co_manipulation.yaml", "bent_bar.yaml", "closed_contour.yaml"}) {
    ServoParams p;
    const ConfigResult r = loadServoProgram(programPath(f), p);
    ASSERT_TRUE(r.ok()) << r.message();
    TactileServo s;
    EXPECT_TRUE(s.configure(p).ok());
    // Shipped speed limits: at most 0.1 m/s and 50 deg/s (0.5 mm, 0.5 deg per 10 ms).
    EXPECT_LE(p.safety.max_trans_speed, 0.1);
    EXPECT_LE(p.safety.max_rot_speed, 50.0 * kPi / 180 + 1e-12);
    for (const PhaseParams& ph : p.phases)
      for (const TransitionParams& t : ph.transitions) EXPECT_GE(t.for_s, 0.0);
  }
  ServoParams p = loadShipped("edge_exploration.yaml");
  EXPECT_EQ(p.initial_phase, "free_motion");
  EXPECT_EQ(p.pose_update, PoseUpdate::Integrated);
  EXPECT_EQ(p.safety.contact_loss, ContactLossMode::Search);
  EXPECT_EQ(p.motion_sign, defaultMotionSign());
  EXPECT_NEAR(p.sensor_mount.p.z(), 0.03, 1e-15);
  EXPECT_NEAR(p.phases[0].feedforward(kZ), 0.01, 1e-15);
  EXPECT_EQ(p.phases[2].transitions[0].on, TransitionEvent::Aligned);
  EXPECT_DOUBLE_EQ(p.phases[2].transitions[0].for_s, 0.2);  // 20 cycles at 100 Hz
  EXPECT_DOUBLE_EQ(p.phases[1].kp(kWY), 20.0);                // 1/s
  EXPECT_DOUBLE_EQ(p.safety.max_trans_speed, 0.05);           // m/s
  EXPECT_EQ(p.phases[2].transitions[0].tolerance[kTolAlphaZ], 0.035);
  EXPECT_EQ(p.phases[2].transitions[0].tolerance[kTolCocX], -1.0);  // unused
  // The closed-contour program: the wrist and loop events with their units.
  ServoParams c = loadShipped("closed_contour.yaml");
  const PhaseParams* explore = nullptr;
  const PhaseParams* unwind = nullptr;
  for (const PhaseParams& ph : c.phases) {
    if (ph.name == "explore") explore = &ph;
    if (ph.name == "unwind") unwind = &ph;
  }
  ASSERT_TRUE(explore && unwind);
  EXPECT_EQ(explore->transitions[0].on, TransitionEvent::LoopClosed);
  EXPECT_DOUBLE_EQ(explore->transitions[0].radius_m, 0.002);
  EXPECT_EQ(explore->transitions[1].on, TransitionEvent::WristWound);
  EXPECT_NEAR(explore->transitions[1].angle_rad, 150.0 * kPi / 180.0, 1e-12);
  EXPECT_DOUBLE_EQ(unwind->unwind_rate, 0.7);
  EXPECT_EQ(unwind->transitions[0].on, TransitionEvent::WristUnwound);
}

TEST(ServoProgramIo, AlternativeFormsParse) {
  const std::string text =
      "controller: {mode: baseline, motion_sign: [-1, -1, 1, 1, -1, -1], sensor_mount: {xyz: [0, 0, 0.01], rpy_deg: [180, 0, 0]}}\n"
      "phases:\n"
      "  - name: only\n"
      "    s_d: [0, 0, 0.002, 0, 0, 0]\n"
      "    jacobian: {point: [[1,0,0,0,0,0],[0,1,0,0,0,0],[0,0,1,0,0,0],[0,0,0,0,0,0],[0,0,0,0,0,0],[0,0,0,0,0,0]],\n"
      "               edge:  [[1,0,0,0,0,0],[0,1,0,0,0,0],[0,0,1,0,0,0],[0,1,0,0,-0.5,0],[1,0,0,-0.5,0,0],[0,0,0,0,0,1]]}\n"
      "    P: [[1,0,0,0,0,0],[0,1,0,0,0,0],[0,0,1,0,0,0],[0,0,0,1,0,0],[0,0,0,0,1,0],[0,0,0,0,0,1]]\n"
      "    kp_per_s: [0.1, 0.1, 0.1, 1, 1, 0.1]\n";
  ServoParams p;
  const ConfigResult r = loadServoProgram(writeTemp("alt", text), p);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(p.mode, ControllerMode::Baseline);
  EXPECT_EQ(p.phases[0].jinv_edge(3, 4), -0.5);
  EXPECT_EQ(p.phases[0].P, Mat6::Identity());
  EXPECT_EQ(p.phases[0].kp(kWX), 1.0);
  EXPECT_NEAR(p.sensor_mount.M(1, 1), -1.0, 1e-15);
}

TEST(ServoProgramIo, BadProgramsNameFilePhaseField) {
  expectRejected("unknown_feature", program("", "    s_d: {cop_z: 0}\n"), {"phases.hold", "s_d.cop_z", "unknown feature name"});
  expectRejected("unknown_tol_feature",
                 program("", "    transitions: [{on: aligned, to: approach, tolerance: {dzmp_q: 0.1}}]\n"),
                 {"phases.hold", "tolerance.dzmp_q", "unknown feature name"});
  expectRejected("short_jinv",
                 program("", "    jacobian: {point: [[1,0,0,0,0,0]], edge: [[1,0,0,0,0,0]]}\n"),
                 {"phases.hold", "jacobian.point", "6x6"});
  expectRejected("short_P_row",
                 program("", "    P: [[1,0,0,0,0,0],[0,1,0,0,0],[0,0,1,0,0,0],[0,0,0,1,0,0],[0,0,0,0,1,0],[0,0,0,0,0,1]]\n"),
                 {"phases.hold", "P.1", "6 entries"});
  expectRejected("short_sd", program("", "    s_d: [0, 0, 0, 0, 0]\n"), {"phases.hold", "s_d", "6 entries"});
  expectRejected("negative_kp", program("", "    ki_per_s2: {wy: -0.5}\n"), {"phases.hold", "ki_per_s2.wy", "-0.5", ">= 0"});
  expectRejected("negative_default", "phase_defaults: {kp_per_s: {x: -1}}\n" + program(""), {"phase_defaults.kp_per_s.x"});
  expectRejected("unknown_target", program("", "    transitions: [{on: contact_lost, to: nowhere}]\n"),
                 {"phases.hold", "transitions[0].to", "nowhere", "unknown phase"});
  expectRejected("unreachable",
                 program("", "    P: {z: 1}\n  - name: orphan\n    P: {z: 1}\n"),
                 {"phases.orphan", "unreachable", "approach"});
  expectRejected("unknown_key", program("", "    gain: 3\n"), {"phases.hold.gain", "unknown key"});
  expectRejected("unknown_event", program("", "    transitions: [{on: bump, to: approach}]\n"),
                 {"phases.hold", "transitions[0].on", "bump"});
  expectRejected("unknown_gamma", program("", "    P: {q: 1}\n"), {"phases.hold", "P.q"});
  expectRejected("bad_beta", program("", "    jacobian: {beta: 0.5}\n"), {"phases.hold", "jacobian.beta"});
  expectRejected("aligned_without_tol", program("", "    transitions: [{on: aligned, to: approach}]\n"),
                 {"phases.hold", "tolerance", "required"});
  expectRejected("timeout_without_time", program("", "    transitions: [{on: timeout, to: approach}]\n"),
                 {"phases.hold", "timeout_s"});
  expectRejected("duplicate", program("", "    P: {z: 1}\n  - name: hold\n"), {"phases.hold", "duplicate"});
  expectRejected("bad_sign", "controller: {motion_sign: {x: 2}}\n" + program(""), {"motion_sign.x", "+1 or -1"});
  expectRejected("bad_initial", "controller: {initial_phase: zzz}\n" + program(""), {"initial_phase", "zzz"});
  expectRejected("bad_safety", "safety: {max_trans_speed: -1}\n" + program(""), {"safety.max_trans_speed", "(0, 1] m/s"});
  expectRejected("bad_for_s", program("", "    transitions: [{on: contact_lost, to: approach, for_s: -0.1}]\n"),
                 {"phases.hold", "transitions[0].for_s", "[0, 3600] s"});
  expectRejected("bad_filter_s", program("", "    transitions: [{on: contact_lost, to: approach, filter_s: 0.1}]\n"),
                 {"transitions[0].filter_s", "only for 'aligned'"});
  expectRejected("bad_max_duration", program("", "    max_duration_s: -1\n"), {"phases.hold", "max_duration_s", ">= 0"});
  expectRejected("bad_loss", "safety: {contact_loss: {mode: pray}}\n" + program(""), {"contact_loss.mode", "pray"});
  expectRejected("bad_frozen_travel", "safety: {frozen_image: {travel_m: 0.5}}\n" + program(""),
                 {"safety.frozen_image.travel_m", "[0, 0.05] m"});
  expectRejected("bad_frozen_key", "safety: {frozen_image: {travel: 0.002}}\n" + program(""),
                 {"safety.frozen_image", "travel"});
  expectRejected("not_a_number", program("", "    kp_per_s: {y: fast}\n"), {"phases.hold", "kp_per_s.y", "fast"});
  expectRejected("no_phases", "controller: {mode: proposed}\n", {"phases", "non-empty"});
  // The speed law's block: its ranges and phase names, named with the file and key.
  expectRejected("bad_speed_vmin", "speed_law: {phases: [hold], v_min: 1.0}\n" + program(""),
                 {"speed_law.v_min", "[0, v_max]"});
  expectRejected("bad_speed_tau", "speed_law: {rate_tau_s: 0}\n" + program(""), {"speed_law.rate_tau_s", "(0, 10] s"});
  expectRejected("bad_speed_excess_tau", "speed_law: {excess_tau_s: -0.01}\n" + program(""),
                 {"speed_law.excess_tau_s", "[0, 10] s"});
  expectRejected("bad_speed_phase", "speed_law: {phases: [hlod]}\n" + program(""), {"speed_law.phases", "'hlod'"});
  expectRejected("bad_speed_axis", "speed_law: {axis: z}\n" + program(""), {"speed_law.axis", "'z'", "must be one of x, y"});
  expectRejected("bad_speed_key", "speed_law: {vmax: 0.1}\n" + program(""), {"speed_law.vmax", "unknown key"});
  expectRejected("bad_speed_excess_against", "speed_law: {excess_against: wrench}\n" + program(""),
                 {"speed_law.excess_against", "'wrench'", "estimate", "tactile"});
  expectRejected("bad_speed_excess_deadband", "speed_law: {phases: [hold], excess_ref_n: 2.0, excess_deadband_n: 2.0}\n" + program(""),
                 {"speed_law.excess_deadband_n", "[0, excess_ref_n)"});
  expectRejected("bad_speed_excess_per_m", "speed_law: {phases: [hold], excess_deadband_per_m: -40}\n" + program(""),
                 {"speed_law.excess_deadband_per_m", "-40", "[0, 1e4] N/m"});
  expectRejected("bad_speed_excess_short", "speed_law: {phases: [hold], excess_short_max_m: 2}\n" + program(""),
                 {"speed_law.excess_short_max_m", "[0, 1] m"});
  // The slope feed-forward's block likewise.
  expectRejected("bad_slope_window", "slope_feedforward: {phases: [hold], window_m: 0.1}\n" + program(""),
                 {"slope_feedforward.window_m", "[0, 0.05] m"});
  expectRejected("bad_slope_phase", "slope_feedforward: {phases: [hlod]}\n" + program(""),
                 {"slope_feedforward.phases", "'hlod'"});
  expectRejected("bad_slope_axis", "slope_feedforward: {axis: z}\n" + program(""),
                 {"slope_feedforward.axis", "'z'", "must be one of x, y"});
  expectRejected("bad_slope_key", "slope_feedforward: {window: 0.001}\n" + program(""),
                 {"slope_feedforward.window", "unknown key"});
  {
    const std::string body = program("").substr(program("").find('\n') + 1);  // without its controller: line
    expectRejected("bad_mode", "controller: {mode: li}\n" + body,
                   {"controller.mode", "'li'", "must be one of proposed, baseline, no_rotation"});
    expectRejected("bad_mode_case", "controller: {mode: No_Rotation}\n" + body, {"controller.mode", "No_Rotation"});
    for (const char* m : {"proposed", "baseline", "no_rotation"}) {
      ServoParams p;
      const ConfigResult r = loadServoProgram(writeTemp(std::string("mode_") + m, std::string("controller: {mode: ") + m + "}\n" + body), p);
      ASSERT_TRUE(r.ok()) << m << ": " << r.message();
      EXPECT_STREQ(toString(p.mode), m);
    }
  }
  expectRejected("yaml_syntax", "phases: [ {name: a\n", {"YAML error"});
  // The wrist and loop events (closed contours).
  expectRejected("wound_without_angle", program("", "    transitions: [{on: wrist_wound, to: approach}]\n"),
                 {"phases.hold", "transitions[0].angle_deg", "required"});
  expectRejected("angle_elsewhere", program("", "    transitions: [{on: contact_lost, to: approach, angle_deg: 10}]\n"),
                 {"transitions[0].angle_deg", "only for 'wrist_wound', 'wrist_unwound' and 'joint_margin'"});
  expectRejected("margin_without_angle", program("", "    transitions: [{on: joint_margin, to: approach}]\n"),
                 {"phases.hold", "transitions[0].angle_deg", "required for 'joint_margin'"});
  expectRejected("bad_margin", program("", "    transitions: [{on: joint_margin, to: approach, angle_deg: 31}]\n"),
                 {"phases.hold", "transitions[0].angle_deg", "31", "(0, 30] deg"});
  expectRejected("bad_angle", program("", "    transitions: [{on: wrist_unwound, to: approach, angle_deg: 0}]\n"),
                 {"transitions[0].angle_deg", "(0, 720] deg"});
  expectRejected("loop_without_radius", program("", "    transitions: [{on: loop_closed, to: approach, leave_m: 0.03}]\n"),
                 {"transitions[0].radius_m", "required"});
  expectRejected("loop_leave_too_small",
                 program("", "    transitions: [{on: loop_closed, to: approach, radius_m: 0.005, leave_m: 0.005}]\n"),
                 {"phases.hold", "leave_m", "(radius_m, 10] m"});
  expectRejected("bad_unwind_rate", program("", "    unwind_rate: 2\n"), {"phases.hold.unwind_rate", "[0, 0.87] rad/s"});
}

// Rates in physical units: the per-cycle keys of earlier programs are rejected
// (never silently reinterpreted as per second), naming the file, the key and
// its replacement with the unit.
TEST(ServoProgramIo, PerCycleKeysAreRejectedNamingTheNewKey) {
  expectRejected("old_kp", program("", "    kp: {y: 0.03}\n"), {"phases.hold.kp", "kp_per_s", "1/s", "per-cycle"});
  expectRejected("old_ki", program("", "    ki: {y: 0.02}\n"), {"phases.hold.ki", "ki_per_s2", "1/s^2"});
  expectRejected("old_ilim", program("", "    integral_limit: {y: 0.0002}\n"),
                 {"phases.hold.integral_limit", "integral_limit_per_s", "m/s"});
  expectRejected("old_umax", program("", "    u_max: {y: 0.0005}\n"), {"phases.hold.u_max", "u_max_per_s", "m/s"});
  expectRejected("old_default", "phase_defaults: {kp: {x: 0.03}}\n" + program(""), {"phase_defaults.kp", "kp_per_s"});
  expectRejected("old_cycles", program("", "    transitions: [{on: contact_lost, to: approach, cycles: 50}]\n"),
                 {"phases.hold.transitions[0].cycles", "for_s", "cycles 20 at 100 Hz = for_s 0.2"});
  expectRejected("old_trans_step", "safety: {max_trans_step: 0.0005}\n" + program(""),
                 {"safety.max_trans_step", "max_trans_speed", "m/s"});
  expectRejected("old_rot_step", "safety: {max_rot_step_deg: 0.5}\n" + program(""),
                 {"safety.max_rot_step_deg", "max_rot_speed_deg", "deg/s"});
}

TEST(ServoProgramIo, MissingFileIsReported) {
  ServoParams p;
  const ConfigResult r = loadServoProgram("/nonexistent/dir/prog.yaml", p);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("/nonexistent/dir/prog.yaml"), std::string::npos);
  EXPECT_NE(r.message().find("cannot open"), std::string::npos);
}
