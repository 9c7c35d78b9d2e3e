"""ctest program_yaml_py: scripts/tools/program_yaml.py gives the scripts the
program as the servo merges it (`tactile_sim program`; the rules are
program_io.hpp's "Overlays", checked in C++ by ServoProgramBase.*). Each rule
on scratch files through the tool, then every shipped overlay: the merged
program is its base with exactly the overlay's changes. Usage:
test_program_yaml.py REPO (the tool: $TACTILE_SIM)."""
import copy
import os
import sys
import tempfile

ROOT = os.path.abspath(sys.argv[1]) if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "..")
sys.path.insert(0, os.path.join(ROOT, "scripts", "tools"))
import program_yaml as P  # noqa: E402

PROGRAMS = os.path.join(ROOT, "params", "programs")
BASE = """controller: {pose_update: measured, c_z: 0.0005}
force_estimate: {source: fused, tau_s: 0.3}
phases:
  - name: approach
    kp_per_s: {z: 2}
    transitions: [{on: contact, to: hold}]
  - name: hold
    s_d: {cop_y: 0.0017, force: 5.0}
    ki_per_s2: {y: 1, z: 1}
    transitions:
      - {on: contact_lost, to: approach, for_s: 0.5}
      - {on: force_above, to: approach, force_n: 20}
"""
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def error_of(path):
    try:
        P.load(path)
    except P.ProgramError as e:
        return str(e)
    return None


def rules(d):
    def write(name, text):
        path = os.path.join(d, name)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w") as f:
            f.write(text)
        return path

    write("base.yaml", BASE)
    m = P.load(write("o.yaml", "base: base.yaml\ncontroller: {c_z: 0.0004}\n"
                                "phases:\n  - name: hold\n    s_d: {cop_y: 0}\n"
                                "    transitions: [{on: contact_lost, to: approach, for_s: 0.1}]\n"
                                "    ki_per_s2: {z: ~}\nforce_estimate: ~\n"))
    check(m["controller"] == {"pose_update": "measured", "c_z": 0.0004}, "a scalar overrides, the mapping's other keys stay")
    check([p["name"] for p in m["phases"]] == ["approach", "hold"], "phases merge by name in the base's order")
    check(m["phases"][1]["s_d"] == {"cop_y": 0, "force": 5.0}, "nested override")
    check(m["phases"][1]["transitions"] == [{"on": "contact_lost", "to": "approach", "for_s": 0.1}], "a list replaces")
    check(m["phases"][1]["ki_per_s2"] == {"y": 1} and "force_estimate" not in m, "~ removes the base's key")
    check("base" not in m and m["phases"][0] == P.load(os.path.join(d, "base.yaml"))["phases"][0], "the rest is the base's")
    write("sub/b.yaml", "base: ../base.yaml\ncontroller: {c_z: 0.0004}\n")
    c = P.load(write("c.yaml", "base: sub/b.yaml\ncontroller: {pose_update: integrated}\n"))
    check(c["controller"] == {"pose_update": "integrated", "c_z": 0.0004}, "a chain, each base relative to its file")
    write("x.yaml", "base: y.yaml\n")
    write("y.yaml", "base: x.yaml\n")
    e = error_of(os.path.join(d, "x.yaml")) or ""
    check("y.yaml: base: 'x.yaml' is a cycle of bases" in e, "a cycle is an error: " + e)
    e = error_of(write("m.yaml", "base: none.yaml\n")) or ""
    check("m.yaml: base: 'none.yaml'" in e and "cannot open file" in e, "a missing base is an error: " + e)
    t = P.load(write("t.yaml", "base: base.yaml\ncontroller: {c_z: 0.0004, initial_phase: hold}\n"))
    check(t["controller"] == {"pose_update": "measured", "c_z": 0.0004, "initial_phase": "hold"},
          "a key the base lacks is added (the reader checks it)")
    e = error_of(write("t2.yaml", "base: base.yaml\nwatchdogs: ~\n")) or ""
    check("t2.yaml: watchdogs: not in the base" in e, "~ of a key the base lacks is an error: " + e)
    e = error_of(write("p.yaml", "base: base.yaml\nphases:\n  - {name: hodl, P: {z: 1}}\n")) or ""
    check("p.yaml: phases[hodl]: no element named 'hodl'" in e, "a phase the base lacks is an error: " + e)
    a = P.load(write("a.yaml", "base: base.yaml\nphases:\n  - name: hold\n"
                               "    transitions: [{on: timeout, to: check, timeout_s: 1}]\n"
                               "add_phases:\n  - {name: check, P: {z: 1}, terminal: true}\n"))
    check([p["name"] for p in a["phases"]] == ["approach", "hold", "check"] and "add_phases" not in a,
          "add_phases appends whole phases after the base's")
    e = error_of(write("a2.yaml", "base: base.yaml\nadd_phases:\n  - {name: hold, P: {z: 1}}\n")) or ""
    check("a2.yaml: add_phases[hold]: a phase of that name is in the base" in e, "add_phases of a base's phase: " + e)
    e = error_of(write("a3.yaml", "base: base.yaml\nadd_phases:\n  - {name: x}\n  - {name: x}\n")) or ""
    check("a3.yaml: add_phases[x]: given twice" in e, "add_phases twice: " + e)


def phase(prog, name):
    return next(p for p in prog["phases"] if p["name"] == name)


def shipped():
    def expect(overlay, base, edit):
        want = P.load(os.path.join(PROGRAMS, base))
        edit(want)
        got = P.load(os.path.join(PROGRAMS, overlay))
        check(got == want, f"{overlay} is {base} with its changes only")
        check(got != P.load(os.path.join(PROGRAMS, base)), f"{overlay} differs from {base}")

    def paper(phases_cop_y, ki_z=(), ki_all=(), along_rows=(), end_after=None):
        def edit(p):
            for n in phases_cop_y:
                phase(p, n)["s_d"]["cop_y"] = 0
            for n in ki_z:
                del phase(p, n)["ki_per_s2"]["z"]
            for n in ki_all:
                del phase(p, n)["ki_per_s2"]
            for n in along_rows:  # the edge along the taxel rows
                phase(p, n)["s_d"]["alpha_z"] = 0
            if end_after is not None:  # the end rule's wait (s) on a point contact
                phase(p, "explore")["transitions"][0]["for_s"] = end_after
            del p["force_estimate"]
        return edit

    expect("bent_bar_paper.yaml", "bent_bar.yaml", paper(["explore"]))
    expect("edge_exploration_paper.yaml", "edge_exploration.yaml",
           paper(["align", "edge_control", "explore"], ki_z=["align"], along_rows=["edge_control", "explore"],
                 end_after=0.2))
    expect("hold_edge_paper.yaml", "hold_edge.yaml", paper(["hold", "press"], ki_all=["hold"]))
    expect("co_manipulation_paper.yaml", "co_manipulation.yaml", paper([], ki_z=["balance"]))

    def end_cap(p):
        phase(p, "explore")["transitions"].insert(0, {"on": "point", "to": "done", "for_s": 0.2})
        p["force_estimate"].update(tau_s=0.08, max_correction_n=4.0)
        p["watchdogs"]["surface_too_curved"]["tau_s"] = 0.05
    expect("bent_bar_to_end_cap.yaml", "bent_bar.yaml", end_cap)

    def speed_law(p):
        p["safety"]["max_trans_speed"] = 0.12
        p["phase_defaults"]["kp_per_s"]["z"] = 8.0
        p["phase_defaults"]["ki_per_s2"]["z"] = 16.0
        p["phase_defaults"]["u_max_per_s"].update(x=0.12, y=0.12)
        ex = phase(p, "explore")
        ex["kp_per_s"]["x"] = 4.8
        ex["transitions"][0].update(to="end_check", for_s=0.08)
        p["phases"].append({"name": "end_check", "s_d": dict(ex["s_d"]), "jacobian": "touch",
                            "P": {"x": 1, "y": 1, "z": 1, "wx": 0, "wy": 1, "wz": 1},
                            "kp_per_s": {"x": 0.6}, "ki_per_s2": {"x": 0.0}, "reset_integrator": False,
                            "transitions": [{"on": "joint_margin", "to": "done", "angle_deg": 5},
                                            {"on": "edge", "to": "explore", "for_s": 0.1},
                                            {"on": "contact_lost", "to": "explore", "for_s": 0.02},
                                            {"on": "timeout", "to": "done", "timeout_s": 0.3}]})
        p["speed_law"].update(phases=["explore"], v_max=0.12, accel_mps2=1.0, rate_tau_s=0.1, force_deadband_n=0.4,
                              horizon_s=0.05, angle_rate_ref=8.0, excess_ref_n=4.0, extent_full_m=0.016, extent_min_m=0.0,
                              excess_against="tactile", excess_deadband_n=1.8, excess_deadband_per_m=40.0, excess_tau_s=0.03,
                              drive_fraction=0.6, guard_excess_n=1.4, guard_accel_mps2=0.6, crawl_mps=0.02)
        p["slope_feedforward"]["phases"] = ["explore"]
        p["force_estimate"].update(tau_s=0.02, max_correction_n=5.0)
    expect("bent_bar_speed_law.yaml", "bent_bar_to_end_cap.yaml", speed_law)

    def careful(p):
        p["safety"]["max_trans_speed"] = 0.08
        p["phase_defaults"]["u_max_per_s"].update(x=0.08, y=0.08)
        phase(p, "explore")["kp_per_s"]["x"] = 3.2
        phase(p, "explore")["transitions"][0]["for_s"] = 0.1
        p["speed_law"].update(v_max=0.08, accel_mps2=0.005, force_budget_n=0.35, force_deadband_n=0.15,
                              angle_rate_ref=1.0, excess_ref_n=1.2, extent_full_m=0.02, excess_deadband_n=0.0,
                              excess_deadband_per_m=0.0,
                              excess_against="estimate")
        p["slope_feedforward"]["phases"] = []
        p["force_estimate"].update(tau_s=0.08, max_correction_n=4.0)
    expect("bent_bar_speed_law_careful.yaml", "bent_bar_speed_law.yaml", careful)
    for f in sorted(os.listdir(PROGRAMS)):
        if f.endswith(".yaml"):
            check(isinstance(P.load(os.path.join(PROGRAMS, f)).get("phases"), list), f"{f} loads with its phases")


with tempfile.TemporaryDirectory() as tmp:
    rules(tmp)
shipped()
sys.exit(1 if failures else 0)
