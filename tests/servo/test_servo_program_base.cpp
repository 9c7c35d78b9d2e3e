// Program overlays (`base:`, program_io.hpp "Overlays"): the merge rules, each
// with a case that fails when the rule is broken, and the shipped overlays
// (*_paper.yaml, bent_bar_to_end_cap.yaml): each changes exactly the keys it
// names, every other key is its base's.
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <fstream>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "servo_test_util.hpp"

using namespace tactile;
using namespace servo_test;

namespace {

/// A fresh directory per call (ctest runs the cases of this binary in
/// parallel), for files that name each other by relative path.
struct Dir {
  std::string path;
  Dir() {
    std::string tmpl = ::testing::TempDir() + "tactile_program_base_XXXXXX";
    std::vector<char> buf(tmpl.begin(), tmpl.end());
    buf.push_back('\0');
    EXPECT_NE(::mkdtemp(buf.data()), nullptr);
    path = buf.data();
  }
  std::string write(const std::string& name, const std::string& text) const {
    const std::string f = path + "/" + name;
    std::ofstream(f) << text;
    return f;
  }
};

// A valid base program: two phases, a force estimate, lists of each kind.
const char* const kBase =
    "controller: {pose_update: measured, c_z: 0.0005}\n"
    "safety:\n"
    "  max_trans_speed: 0.05\n"
    "  workspace: {min: [-1, -1, 0], max: [1, 1, 1]}\n"
    "force_estimate: {source: fused, tau_s: 0.3, max_correction_n: 2.5}\n"
    "phases:\n"
    "  - name: approach\n"
    "    requires_contact: false\n"
    "    P: {z: 1}\n"
    "    kp_per_s: {z: 2}\n"
    "    transitions: [{on: contact, to: hold}]\n"
    "  - name: hold\n"
    "    s_d: {cop_x: 0, cop_y: 0.0017, force: 5.0}\n"
    "    P: {y: 1, z: 1}\n"
    "    kp_per_s: {y: 3, z: 3}\n"
    "    ki_per_s2: {y: 1, z: 1}\n"
    "    transitions:\n"
    "      - {on: contact_lost, to: approach, for_s: 0.5}\n"
    "      - {on: force_above, to: approach, force_n: 20}\n";

YAML::Node doc(const std::string& file) {
  YAML::Node n;
  const ConfigResult r = loadProgramDocument(file, n);
  EXPECT_TRUE(r.ok()) << r.message();
  return n;
}

void expectError(const std::string& file, std::initializer_list<std::string> parts) {
  YAML::Node n;
  const ConfigResult r = loadProgramDocument(file, n);
  ASSERT_FALSE(r.ok()) << file << " merged without an error";
  for (const std::string& part : parts) EXPECT_NE(r.message().find(part), std::string::npos) << r.message();
  ServoParams p;  // the servo's loader says the same
  const ConfigResult s = loadServoProgram(file, p);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.message(), r.message());
}

/// Merges, but the servo's reader refuses it.
void expectReadError(const std::string& file, std::initializer_list<std::string> parts) {
  YAML::Node n;
  const ConfigResult r = loadProgramDocument(file, n);
  ASSERT_TRUE(r.ok()) << r.message();
  ServoParams p;
  const ConfigResult s = loadServoProgram(file, p);
  ASSERT_FALSE(s.ok()) << file << " read without an error";
  for (const std::string& part : parts) EXPECT_NE(s.message().find(part), std::string::npos) << s.message();
}

/// Every node of a document by its path: "a.b" for mapping keys,
/// "phases[hold]" for named list elements, "x[2]" otherwise; scalars by
/// their text, mappings and lists as "{}" and "[]".
void flatten(const YAML::Node& n, const std::string& path, std::map<std::string, std::string>& out) {
  if (n.IsMap()) {
    out[path] = "{}";
    for (const auto& kv : n) flatten(kv.second, (path.empty() ? "" : path + ".") + kv.first.as<std::string>(), out);
  } else if (n.IsSequence()) {
    out[path] = "[]";
    bool named = n.size() > 0;
    for (const auto& e : n) named = named && e.IsMap() && e["name"] && e["name"].IsScalar();
    for (std::size_t i = 0; i < n.size(); ++i)
      flatten(n[i], path + "[" + (named ? n[i]["name"].Scalar() : std::to_string(i)) + "]", out);
  } else {
    out[path] = n.IsNull() ? "~" : n.Scalar();
  }
}

const std::string kAbsent = "<absent>";

/// `overlay` merged equals `base` merged but for `changed` (path -> the
/// overlay's value, kAbsent for a removed key and everything under it).
void expectOverlay(const std::string& overlay, const std::string& base,
                   const std::map<std::string, std::string>& changed) {
  std::map<std::string, std::string> o, b;
  flatten(doc(programPath(overlay)), "", o);
  flatten(doc(programPath(base)), "", b);
  ASSERT_FALSE(b.empty());
  auto under = [](const std::string& path, const std::string& prefix) {
    return path.size() > prefix.size() && path.compare(0, prefix.size(), prefix) == 0 &&
           (path[prefix.size()] == '.' || path[prefix.size()] == '[');
  };
  std::map<std::string, std::string> all = b;
  all.insert(o.begin(), o.end());
  for (const auto& kv : all) {
    const std::string& path = kv.first;
    const auto io = o.find(path), ib = b.find(path);
    const std::string ov = io == o.end() ? kAbsent : io->second, bv = ib == b.end() ? kAbsent : ib->second;
    const auto exact = changed.find(path);
    bool removed = false, replaced = false;  // under a removed key; under a changed one
    for (const auto& c : changed) {
      removed = removed || (under(path, c.first) && c.second == kAbsent);
      replaced = replaced || under(path, c.first);
    }
    if (exact != changed.end()) {
      EXPECT_EQ(ov, exact->second) << overlay << ": " << path;
    } else if (removed) {
      EXPECT_EQ(ov, kAbsent) << overlay << ": " << path << " should be removed";
    } else if (!replaced || ov == bv) {
      EXPECT_EQ(ov, bv) << overlay << ": " << path << " differs from " << base << "'s";
    } else {
      ADD_FAILURE() << overlay << ": " << path << " = " << ov << " (base " << bv << "): a change not in the list";
    }
  }
  for (const auto& c : changed) {  // every expected change is one (a spec the base already meets tests nothing)
    const auto ib = b.find(c.first);
    EXPECT_NE(ib == b.end() ? kAbsent : ib->second, c.second) << overlay << ": " << c.first << " is the base's";
  }
  EXPECT_EQ(o.count("base"), 0u) << overlay << ": the merged document keeps `base`";
}

}  // namespace

// ---- merge rules --------------------------------------------------------

TEST(ServoProgramBase, ScalarOverrideKeepsTheRestOfTheMapping) {
  Dir d;
  d.write("base.yaml", kBase);
  const std::string o = d.write("o.yaml", "base: base.yaml\ncontroller: {c_z: 0.0004}\n");
  const YAML::Node n = doc(o);
  EXPECT_EQ(n["controller"]["c_z"].Scalar(), "0.0004");
  EXPECT_EQ(n["controller"]["pose_update"].Scalar(), "measured");
  EXPECT_FALSE(n["base"]);
  ServoParams p;
  ASSERT_TRUE(loadServoProgram(o, p).ok());
  EXPECT_DOUBLE_EQ(p.c_z, 0.0004);
  EXPECT_EQ(p.pose_update, PoseUpdate::Measured);
  EXPECT_EQ(p.source, o);
}

TEST(ServoProgramBase, NestedOverrideMergesPhasesByName) {
  Dir d;
  d.write("base.yaml", kBase);
  const std::string o = d.write("o.yaml",
                                "base: base.yaml\n"
                                "phases:\n"
                                "  - name: hold\n"
                                "    s_d: {cop_y: 0}\n"
                                "    kp_per_s: {z: 4}\n");
  ServoParams p;
  const ConfigResult r = loadServoProgram(o, p);
  ASSERT_TRUE(r.ok()) << r.message();
  ASSERT_EQ(p.phases.size(), 2u);  // the base's phases, in the base's order
  EXPECT_EQ(p.phases[0].name, "approach");
  EXPECT_DOUBLE_EQ(p.phases[0].kp(kZ), 2.0);
  const PhaseParams& h = p.phases[1];
  EXPECT_EQ(h.name, "hold");
  EXPECT_DOUBLE_EQ(h.kp(kZ), 4.0);                // changed
  EXPECT_DOUBLE_EQ(h.kp(kY), 3.0);                // kept beside it
  EXPECT_DOUBLE_EQ(h.s_d(1), 0.0);                // cop_y changed
  EXPECT_DOUBLE_EQ(h.s_d(kZ), 0.0005 * 5.0);      // force kept (Eq. 2: d_z = C_z f)
  EXPECT_EQ(h.transitions.size(), 2u);            // untouched list kept
}

TEST(ServoProgramBase, ListsReplace) {
  Dir d;
  d.write("base.yaml", kBase);
  const std::string o = d.write("o.yaml",
                                "base: base.yaml\n"
                                "safety: {workspace: {min: [-2, -2, 0]}}\n"
                                "phases:\n"
                                "  - name: hold\n"
                                "    transitions: [{on: contact_lost, to: approach, for_s: 0.1}]\n");
  const YAML::Node n = doc(o);
  const YAML::Node t = n["phases"][1]["transitions"];
  ASSERT_EQ(t.size(), 1u);  // replaced, not merged element-wise into the base's two
  EXPECT_EQ(t[0]["for_s"].Scalar(), "0.1");
  EXPECT_EQ(n["safety"]["workspace"]["min"][0].Scalar(), "-2");
  EXPECT_EQ(n["safety"]["workspace"]["max"][0].Scalar(), "1");
  EXPECT_EQ(n["safety"]["max_trans_speed"].Scalar(), "0.05");
}

TEST(ServoProgramBase, NullRemovesAKey) {
  Dir d;
  d.write("base.yaml", kBase);
  const std::string o = d.write("o.yaml",
                                "base: base.yaml\n"
                                "force_estimate: ~\n"
                                "phases:\n"
                                "  - name: hold\n"
                                "    ki_per_s2: {z: ~}\n");
  const YAML::Node n = doc(o);
  EXPECT_FALSE(n["force_estimate"]);
  EXPECT_FALSE(n["phases"][1]["ki_per_s2"]["z"]);
  EXPECT_EQ(n["phases"][1]["ki_per_s2"]["y"].Scalar(), "1");
  ServoParams p, pb;
  ASSERT_TRUE(loadServoProgram(o, p).ok());
  ASSERT_TRUE(loadServoProgram(d.path + "/base.yaml", pb).ok());
  EXPECT_TRUE(pb.force_estimate.fused);
  EXPECT_FALSE(p.force_estimate.fused);  // the default: Eq. 2's tactile force
}

TEST(ServoProgramBase, ChainsResolveRelativeToEachFile) {
  Dir d;
  d.write("a.yaml", kBase);
  ASSERT_EQ(::mkdir((d.path + "/sub").c_str(), 0700), 0);
  d.write("sub/b.yaml", "base: ../a.yaml\ncontroller: {c_z: 0.0004}\nsafety: {max_trans_speed: 0.04}\n");
  const std::string c = d.write("c.yaml", "base: sub/b.yaml\nsafety: {max_trans_speed: 0.03}\n");
  ServoParams p;
  const ConfigResult r = loadServoProgram(c, p);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_DOUBLE_EQ(p.c_z, 0.0004);                  // from b
  EXPECT_DOUBLE_EQ(p.safety.max_trans_speed, 0.03);  // c over b
  EXPECT_EQ(p.pose_update, PoseUpdate::Measured);    // from a
}

TEST(ServoProgramBase, ParsedDocumentResolvesBaseBesideItsFile) {
  Dir d;
  d.write("base.yaml", kBase);
  const std::string o = d.path + "/o.yaml";  // never written: the document is given
  ServoParams p;
  const ConfigResult r = loadServoProgram(YAML::Load("base: base.yaml\ncontroller: {c_z: 0.0004}\n"), o, p);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_DOUBLE_EQ(p.c_z, 0.0004);
}

TEST(ServoProgramBase, CycleIsAnError) {
  Dir d;
  const std::string a = d.write("a.yaml", "base: b.yaml\n");
  d.write("b.yaml", "base: c.yaml\n");
  d.write("c.yaml", "base: a.yaml\n");
  expectError(a, {d.path + "/c.yaml: base: 'a.yaml' is a cycle of bases", "a.yaml -> ", "b.yaml -> "});
  const std::string self = d.write("self.yaml", "base: self.yaml\ncontroller: {c_z: 0.0004}\n");
  expectError(self, {self + ": base: 'self.yaml' is a cycle of bases"});
}

TEST(ServoProgramBase, MissingBaseIsAnError) {
  Dir d;
  const std::string o = d.write("o.yaml", "base: no_such_program.yaml\ncontroller: {c_z: 0.0004}\n");
  expectError(o, {o + ": base: 'no_such_program.yaml'", d.path + "/no_such_program.yaml: cannot open file"});
  const std::string bad = d.write("bad.yaml", "base: [a.yaml]\n");
  expectError(bad, {bad + ": base: must be the path of another program file"});
}

// A key the base lacks is added (the shared defaults leave out what each
// program sets); a typo is the reader's error at any level; a phase name
// the base lacks, a removal of a key it lacks and a phase given twice are
// errors naming the overlay.
TEST(ServoProgramBase, KeyTheBaseLacksIsAddedAndATypoIsTheReadersError) {
  Dir d;
  d.write("base.yaml", kBase);
  const std::string added =
      d.write("added.yaml", "base: base.yaml\nspeed_law: {phases: [hold], force_budget_n: 0.4}\n"
                            "phases:\n  - name: hold\n    feedforward: {vx: 0.001}\n");
  ServoParams p;
  const ConfigResult r = loadServoProgram(added, p);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(p.speed_law.phases, std::vector<std::string>{"hold"});
  EXPECT_EQ(p.speed_law.law.force_budget_n, 0.4);
  EXPECT_EQ(p.phases[1].feedforward(0), 0.001);
  const std::string typo = d.write("typo.yaml", "base: base.yaml\ncontroller: {c_zz: 0.0004}\n");
  expectReadError(typo, {typo + ": controller.c_zz: unknown key"});
  const std::string nested = d.write("nested.yaml", "base: base.yaml\nphases:\n  - name: hold\n    s_d: {cop_yy: 0}\n");
  expectReadError(nested, {nested + ": phases.hold.s_d.cop_yy: unknown feature name"});
  const std::string phase = d.write("phase.yaml", "base: base.yaml\nphases:\n  - name: hodl\n    s_d: {cop_y: 0}\n");
  expectError(phase, {phase + ": phases[hodl]: no element named 'hodl' in the base", "names: approach, hold"});
  const std::string removed = d.write("removed.yaml", "base: base.yaml\nwatchdogs: ~\n");
  expectError(removed, {removed + ": watchdogs: not in the base", "~ removes a key of the base"});
  const std::string twice =
      d.write("twice.yaml", "base: base.yaml\nphases:\n  - {name: hold, P: {y: 0}}\n  - {name: hold, P: {z: 0}}\n");
  expectError(twice, {twice + ": phases[hold]: given twice"});
}

// add_phases: whole phases appended after the base's (in the merged program
// and in ServoParams), reachable through the overlay's own transitions; a
// name the base has, a name given twice, a non-list and a phase no
// transition reaches are errors naming the overlay.
TEST(ServoProgramBase, AnOverlayAddsWholePhases) {
  Dir d;
  d.write("base.yaml", kBase);
  const std::string o = d.write("o.yaml",
                                "base: base.yaml\n"
                                "phases:\n"
                                "  - name: hold\n"
                                "    transitions: [{on: point, to: check, for_s: 0.1}]\n"
                                "add_phases:\n"
                                "  - name: check\n"
                                "    P: {z: 1}\n"
                                "    kp_per_s: {z: 3}\n"
                                "    transitions: [{on: edge, to: hold}, {on: joint_margin, to: approach, angle_deg: 3}]\n");
  const YAML::Node n = doc(o);
  ASSERT_EQ(n["phases"].size(), 3u);
  EXPECT_EQ(n["phases"][2]["name"].Scalar(), "check");
  EXPECT_FALSE(n["add_phases"]);
  ServoParams p;
  ASSERT_TRUE(loadServoProgram(o, p).ok());
  ASSERT_EQ(p.phases.size(), 3u);
  EXPECT_EQ(p.phases[1].transitions[0].to, "check");
  EXPECT_EQ(p.phases[2].name, "check");
  EXPECT_EQ(p.phases[2].transitions[1].on, TransitionEvent::JointMargin);
  EXPECT_NEAR(p.phases[2].transitions[1].angle_rad, 3.0 * 3.14159265358979323846 / 180.0, 1e-15);
  TactileServo servo;
  EXPECT_TRUE(servo.configure(p).ok());
  const std::string again = d.write("again.yaml", "base: base.yaml\nadd_phases:\n  - {name: hold, P: {z: 1}}\n");
  expectError(again, {again + ": add_phases[hold]: a phase of that name is in the base", "change it under phases"});
  const std::string twice =
      d.write("twice2.yaml", "base: base.yaml\nadd_phases:\n  - {name: x, P: {z: 1}}\n  - {name: x, P: {z: 1}}\n");
  expectError(twice, {twice + ": add_phases[x]: given twice"});
  const std::string bad = d.write("bad2.yaml", "base: base.yaml\nadd_phases: {name: x}\n");
  expectError(bad, {bad + ": add_phases: must be a list of phases"});
  // An added phase nothing reaches (a typo in a transition's target) fails the merged program.
  const std::string lone = d.write("lone.yaml", "base: base.yaml\nadd_phases:\n  - {name: chek, P: {z: 1}}\n");
  ServoParams q;
  const ConfigResult r = loadServoProgram(lone, q);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("chek"), std::string::npos) << r.message();
}

TEST(ServoProgramBase, MergedProgramIsValidatedAsAWhole) {
  Dir d;
  d.write("base.yaml", kBase);
  const std::string o = d.write("o.yaml", "base: base.yaml\nphases:\n  - name: hold\n    kp_per_s: {z: -1}\n");
  ServoParams p;
  const ConfigResult r = loadServoProgram(o, p);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find(o + ": phases.hold.kp_per_s.z"), std::string::npos) << r.message();
}

// ---- the shipped overlays -------------------------------------------------

TEST(ServoProgramBase, EveryShippedProgramLoads) {
  for (const char* f : {"bar_loop.yaml", "bent_bar.yaml", "bent_bar_paper.yaml", "bent_bar_to_end_cap.yaml",
                        "closed_contour.yaml", "co_manipulation.yaml", "co_manipulation_paper.yaml",
                        "edge_exploration.yaml", "edge_exploration_paper.yaml", "first_touch.yaml", "hold_edge.yaml",
                        "hold_edge_paper.yaml"}) {
    ServoParams p;
    const ConfigResult r = loadServoProgram(programPath(f), p);
    EXPECT_TRUE(r.ok()) << r.message();
  }
}

TEST(ServoProgramBase, PaperProgramsChangeOnlyTheForceCopYAndEdgeAngle) {
  expectOverlay("bent_bar_paper.yaml", "bent_bar.yaml",
                {{"phases[explore].s_d.cop_y", "0"}, {"force_estimate", kAbsent}});
  expectOverlay("edge_exploration_paper.yaml", "edge_exploration.yaml",
                {{"phases[align].s_d.cop_y", "0"},
                 {"phases[align].ki_per_s2.z", kAbsent},
                 {"phases[edge_control].s_d.cop_y", "0"},
                 {"phases[edge_control].s_d.alpha_z", "0"},
                 {"phases[explore].s_d.cop_y", "0"},
                 {"phases[explore].s_d.alpha_z", "0"},
                 {"phases[explore].transitions[0].for_s", "0.2"},
                 {"force_estimate", kAbsent}});
  expectOverlay("hold_edge_paper.yaml", "hold_edge.yaml",
                {{"phases[hold].s_d.cop_y", "0"},
                 {"phases[hold].ki_per_s2", kAbsent},
                 {"phases[press].s_d.cop_y", "0"},
                 {"force_estimate", kAbsent}});
  expectOverlay("co_manipulation_paper.yaml", "co_manipulation.yaml",
                {{"phases[balance].ki_per_s2.z", kAbsent}, {"force_estimate", kAbsent}});
  for (const char* f : {"bent_bar_paper.yaml", "edge_exploration_paper.yaml", "hold_edge_paper.yaml",
                        "co_manipulation_paper.yaml"})
    EXPECT_FALSE(loadShipped(f).force_estimate.fused) << f << ": the paper's program regulates Eq. 2's force alone";
}

TEST(ServoProgramBase, BentBarToEndCapAddsTheEndCapTransition) {
  expectOverlay("bent_bar_to_end_cap.yaml", "bent_bar.yaml",
                {{"phases[explore].transitions[0].on", "point"},
                 {"phases[explore].transitions[0].for_s", "0.2"},
                 {"phases[explore].transitions[1]", "{}"},
                 {"phases[explore].transitions[1].on", "contact_lost"},
                 {"phases[explore].transitions[1].to", "done"},
                 {"phases[explore].transitions[1].for_s", "0.5"},
                 {"force_estimate.tau_s", "0.08"},
                 {"force_estimate.max_correction_n", "4.0"},
                 {"watchdogs.surface_too_curved.tau_s", "0.05"}});
  const ServoParams p = loadShipped("bent_bar_to_end_cap.yaml");
  ASSERT_EQ(p.phases[0].name, "explore");
  ASSERT_EQ(p.phases[0].transitions.size(), 2u);
  EXPECT_EQ(p.phases[0].transitions[0].on, TransitionEvent::Point);
  EXPECT_EQ(p.phases[0].transitions[0].to, "done");
  EXPECT_TRUE(p.force_estimate.fused);
  EXPECT_DOUBLE_EQ(p.force_estimate.max_correction_n, 4.0);
}

TEST(ServoProgramBase, BentBarSpeedLawTurnsTheLawOnInExplore) {
  expectOverlay("bent_bar_speed_law.yaml", "bent_bar_to_end_cap.yaml",
                {{"safety.max_trans_speed", "0.12"},
                 {"phase_defaults.kp_per_s.z", "8.0"},
                 {"phase_defaults.ki_per_s2.z", "16.0"},
                 {"phase_defaults.u_max_per_s.x", "0.12"},
                 {"phase_defaults.u_max_per_s.y", "0.12"},
                 {"phases[explore].kp_per_s.x", "4.8"},
                 {"phases[explore].transitions[0].to", "end_check"},
                 {"phases[explore].transitions[0].for_s", "0.08"},
                 // the end rule's check, a phase the overlay adds (add_phases)
                 {"phases[end_check]", "{}"},
                 {"phases[end_check].name", "end_check"},
                 {"phases[end_check].s_d", "{}"},
                 {"phases[end_check].s_d.cop_x", "-0.025"},
                 {"phases[end_check].s_d.cop_y", "0.0017"},
                 {"phases[end_check].s_d.force", "5.0"},
                 {"phases[end_check].s_d.dzmp_x", "0"},
                 {"phases[end_check].s_d.dzmp_y", "0"},
                 {"phases[end_check].s_d.alpha_z", "0"},
                 {"phases[end_check].jacobian", "touch"},
                 {"phases[end_check].P", "{}"},
                 {"phases[end_check].P.x", "1"},
                 {"phases[end_check].P.y", "1"},
                 {"phases[end_check].P.z", "1"},
                 {"phases[end_check].P.wx", "0"},
                 {"phases[end_check].P.wy", "1"},
                 {"phases[end_check].P.wz", "1"},
                 {"phases[end_check].kp_per_s", "{}"},
                 {"phases[end_check].kp_per_s.x", "0.6"},
                 {"phases[end_check].ki_per_s2", "{}"},
                 {"phases[end_check].ki_per_s2.x", "0.0"},
                 {"phases[end_check].reset_integrator", "false"},
                 {"phases[end_check].transitions", "[]"},
                 {"phases[end_check].transitions[0]", "{}"},
                 {"phases[end_check].transitions[0].on", "joint_margin"},
                 {"phases[end_check].transitions[0].to", "done"},
                 {"phases[end_check].transitions[0].angle_deg", "5"},
                 {"phases[end_check].transitions[1]", "{}"},
                 {"phases[end_check].transitions[1].on", "edge"},
                 {"phases[end_check].transitions[1].to", "explore"},
                 {"phases[end_check].transitions[1].for_s", "0.1"},
                 {"phases[end_check].transitions[2]", "{}"},
                 {"phases[end_check].transitions[2].on", "contact_lost"},
                 {"phases[end_check].transitions[2].to", "explore"},
                 {"phases[end_check].transitions[2].for_s", "0.02"},
                 {"phases[end_check].transitions[3]", "{}"},
                 {"phases[end_check].transitions[3].on", "timeout"},
                 {"phases[end_check].transitions[3].to", "done"},
                 {"phases[end_check].transitions[3].timeout_s", "0.3"},
                 {"speed_law.phases[0]", "explore"},
                 {"speed_law.v_max", "0.12"},
                 {"speed_law.accel_mps2", "1.0"},
                 {"speed_law.rate_tau_s", "0.1"},
                 {"speed_law.excess_tau_s", "0.03"},
                 {"speed_law.force_deadband_n", "0.4"},
                 {"speed_law.horizon_s", "0.05"},
                 {"speed_law.angle_rate_ref", "8.0"},
                 {"speed_law.excess_against", "tactile"},
                 {"speed_law.excess_deadband_n", "1.8"},
                 {"speed_law.excess_deadband_per_m", "40.0"},
                 {"speed_law.excess_ref_n", "4.0"},
                 {"speed_law.extent_full_m", "0.016"},
                 {"speed_law.drive_fraction", "0.6"},
                 {"speed_law.guard_excess_n", "1.4"},
                 {"speed_law.guard_accel_mps2", "0.6"},
                 {"speed_law.crawl_mps", "0.02"},
                 {"speed_law.extent_min_m", "0.0"},
                 {"slope_feedforward.phases[0]", "explore"},
                 {"force_estimate.max_correction_n", "5.0"},
                 {"force_estimate.tau_s", "0.02"}});
  const ServoParams p = loadShipped("bent_bar_speed_law.yaml");
  ASSERT_EQ(p.speed_law.phases.size(), 1u);
  EXPECT_EQ(p.speed_law.phases[0], "explore");
  EXPECT_DOUBLE_EQ(p.speed_law.law.v_max, 0.12);
  EXPECT_EQ(p.speed_law.axis, 0);
  EXPECT_TRUE(p.speed_law.excess_against_tactile);  // the load the taxels miss
  EXPECT_DOUBLE_EQ(p.speed_law.law.excess_deadband_n, 1.8);
  EXPECT_DOUBLE_EQ(p.speed_law.excess_tau_s, 0.03);  // the excess on its own, faster low-pass
  EXPECT_DOUBLE_EQ(p.speed_law.law.excess_deadband_per_m, 40.0);  // a short image hides more
  EXPECT_DOUBLE_EQ(p.speed_law.law.excess_short_max_m, 0.04);
  ASSERT_EQ(p.slope_feedforward.phases.size(), 1u);  // and the slope feed-forward, in the same phase
  EXPECT_EQ(p.slope_feedforward.phases[0], "explore");
  EXPECT_DOUBLE_EQ(p.slope_feedforward.window_m, 0.0005);
  EXPECT_DOUBLE_EQ(p.force_estimate.tau_s, 0.02);  // the correction follows a load moving to the housing
  EXPECT_DOUBLE_EQ(p.force_estimate.max_correction_n, 5.0);  // all of it
  // The end rule leads to the check, which ends the run where the arm has no room.
  ASSERT_EQ(p.phases.back().name, "end_check");
  EXPECT_EQ(p.phases[0].transitions[0].to, "end_check");
  EXPECT_EQ(p.phases.back().transitions[0].on, TransitionEvent::JointMargin);
  EXPECT_NEAR(p.phases.back().transitions[0].angle_rad, 5.0 * 3.14159265358979323846 / 180.0, 1e-15);
  // The base programs keep both off.
  EXPECT_TRUE(loadShipped("bent_bar_to_end_cap.yaml").speed_law.phases.empty());
  EXPECT_TRUE(loadShipped("bent_bar.yaml").speed_law.phases.empty());
  EXPECT_TRUE(loadShipped("bent_bar_to_end_cap.yaml").slope_feedforward.phases.empty());
  EXPECT_TRUE(loadShipped("bent_bar.yaml").slope_feedforward.phases.empty());
}

TEST(ServoProgramBase, CarefulSpeedLawChangesTheBudgetAndTheRiseAndKeepsTheEndCapEstimate) {
  expectOverlay("bent_bar_speed_law_careful.yaml", "bent_bar_speed_law.yaml",
                {{"safety.max_trans_speed", "0.08"},
                 {"phase_defaults.u_max_per_s.x", "0.08"},
                 {"phase_defaults.u_max_per_s.y", "0.08"},
                 {"phases[explore].kp_per_s.x", "3.2"},
                 {"phases[explore].transitions[0].for_s", "0.1"},
                 {"speed_law.v_max", "0.08"},
                 {"speed_law.accel_mps2", "0.005"},
                 {"speed_law.force_budget_n", "0.35"},
                 {"speed_law.force_deadband_n", "0.15"},
                 {"speed_law.angle_rate_ref", "1.0"},
                 {"speed_law.excess_ref_n", "1.2"},
                 {"speed_law.excess_deadband_n", "0.0"},
                 {"speed_law.excess_deadband_per_m", "0.0"},
                 {"speed_law.excess_against", "estimate"},
                 {"speed_law.extent_full_m", "0.02"},
                 {"slope_feedforward.phases[0]", kAbsent},  // phases: [] (off)
                 {"force_estimate.max_correction_n", "4.0"},
                 {"force_estimate.tau_s", "0.08"}});
  const ServoParams p = loadShipped("bent_bar_speed_law_careful.yaml");
  EXPECT_DOUBLE_EQ(p.speed_law.law.accel_mps2, 0.005);
  EXPECT_DOUBLE_EQ(p.speed_law.law.force_budget_n, 0.35);
  EXPECT_EQ(p.speed_law.phases.size(), 1u);
  EXPECT_TRUE(p.slope_feedforward.phases.empty());
  // The end-cap program's force estimate (0.08 s), as with the law it was measured against.
  EXPECT_DOUBLE_EQ(p.force_estimate.tau_s, loadShipped("bent_bar_to_end_cap.yaml").force_estimate.tau_s);
}
