#!/usr/bin/python3
"""ctest urdf_fk: the robot model of the ROS face
(ros/tactile_ros/urdf/lwr4plus_wts.urdf) against the simulator's kinematics
(tactile::sim::LwrArm, printed by tests/ros/lwr_fk_table) and the project's
parameters.

usage: check_urdf.py URDF FK_TABLE_TOOL PROGRAM_YAML [--mutate JOINT:DZ]

Checks (each printed; exit 1 when one fails):
  - the tree: root lwr_base, revolute joints lwr_a1_joint..lwr_a7_joint about
    their z axes, in that order from lwr_base to lwr_flange ({e}), then
    wts0614 ({s}) fixed on the flange;
  - the joint limits: A1, A3, A5, A7 +-170 deg, A2, A4, A6 +-120 deg
    (LIMIT_TOL), and the simulator's own limits inside them;
  - forward kinematics on N_CONFIGS configurations (zero, the simulator's
    start posture, joints at their limits, random within the limits): the
    URDF's lwr_flange against LwrArm::forward(), and the URDF's frame of every
    joint A2..A7 (before its own rotation) against the tip frame of the
    simulator's KDL segment before it, within FK_POS_TOL and FK_ROT_TOL;
  - the mount lwr_flange -> wts0614 equal to the program's sensor_mount
    (PROGRAM_YAML, controller.sensor_mount: xyz, rpy_deg), same tolerances;
  - the inertials: each link's mass, centre of mass and principal moments
    those of the simulator's segment (in the segment's tip frame, which the
    URDF gives as the next joint's origin), the tool's on lwr_flange
    (INERTIA_TOL);
  - the pad: a box visual on wts0614 of (cols + 1) x (rows + 1) pitches
    (51.0 x 23.8 mm for 14 x 6 taxels at 3.4 mm), its top face at z = 0.

--mutate JOINT:DZ adds DZ (m) to that joint's origin z before the checks (a
deliberately wrong model); the forward kinematics must then fail, and the
script exits 0 only if it does (ctest urdf_fk_detects).
"""
import math
import os
import subprocess
import sys

import numpy as np
import yaml

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import urdf_fk  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "tools"))
import program_yaml  # noqa: E402  (a program as the servo merges it: tactile_sim program)

# The brief of the model: its forward kinematics within a micrometre and a
# microradian of the simulator's. The URDF carries the simulator's numbers
# (pi/2 to 17 digits), so the differences measured are rounding (~1e-16).
FK_POS_TOL = 1e-6  # m
FK_ROT_TOL = 1e-6  # rad
# Limits written as degrees converted to radians (17 digits).
LIMIT_TOL = 1e-12  # rad
# The inertials are the simulator's numbers, written with their decimals.
INERTIA_TOL = 1e-12  # kg, m, kg m^2
N_RANDOM = 50
SEED = 20201
JOINTS = [f"lwr_a{k}_joint" for k in range(1, 8)]
LINKS = [f"lwr_link_{k}" for k in range(1, 8)]
LIMIT_DEG = [170, 120, 170, 120, 170, 120, 170]
SIM_LIMIT = [2.967, 2.094, 2.967, 2.094, 2.967, 2.094, 2.967]  # ArmParams q_min/q_max (rad)
Q_INIT = [0.0, -0.6, 0.0, 1.4, 0.0, -1.1416, 0.0]  # ArmParams::q_init
ROWS, COLS, PITCH = 6, 14, 0.0034

failures = []


def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok:
        failures.append(what)
    return ok


def frame_from_row(v):
    t = np.eye(4)
    t[:3, 3] = v[:3]
    t[:3, :3] = np.asarray(v[3:12]).reshape(3, 3)
    return t


def frame_error(a, b):
    return float(np.linalg.norm(a[:3, 3] - b[:3, 3])), urdf_fk.rotation_angle(a[:3, :3].T @ b[:3, :3])


def configurations():
    lim = [math.radians(d) for d in LIMIT_DEG]
    qs = [[0.0] * 7, list(Q_INIT)]
    qs.append([s * l for s, l in zip([1, -1, 1, -1, 1, -1, 1], lim)])
    qs.append([s * l for s, l in zip([-1, 1, -1, 1, -1, 1, -1], lim)])
    qs.append([l for l in lim])
    rng = np.random.default_rng(SEED)
    for _ in range(N_RANDOM):
        qs.append([float(rng.uniform(-l, l)) for l in lim])
    return qs


def main():
    args = sys.argv[1:]
    mutate = None
    if "--mutate" in args:
        i = args.index("--mutate")
        name, dz = args[i + 1].split(":")
        mutate = (name, float(dz))
        del args[i:i + 2]
    if len(args) != 3:
        print(__doc__)
        return 2
    urdf_path, tool, program = args
    model = urdf_fk.Urdf(urdf_path)
    if mutate:
        model.joints[mutate[0]].xyz[2] += mutate[1]
        print(f"mutated: {mutate[0]} origin z + {mutate[1]} m")

    # ---- the tree -------------------------------------------------------------
    check(model.root == "lwr_base", f"root link lwr_base (is {model.root})")
    for l in ["lwr_flange", "wts0614"] + LINKS:
        check(l in model.links, f"link {l} defined")
    if failures:
        return 1
    chain = model.chain("lwr_flange")
    moving = [j for j in chain if j.type != "fixed"]
    check([j.name for j in moving] == JOINTS, f"joints lwr_base -> lwr_flange: {[j.name for j in moving]}")
    check(all(j.type == "revolute" and np.allclose(j.axis, [0, 0, 1], atol=0) for j in moving),
          "A1..A7 revolute about their z axes")
    check([j.child for j in moving] == LINKS, "A1..A7 move lwr_link_1..lwr_link_7")
    mount = model.parent_joint["wts0614"]
    check(mount.type == "fixed" and mount.parent == "lwr_flange", "wts0614 fixed on lwr_flange")
    if failures:
        return 1

    # ---- limits ---------------------------------------------------------------
    for j, deg, sim in zip(moving, LIMIT_DEG, SIM_LIMIT):
        lim = j.limit or {}
        want = math.radians(deg)
        ok = (abs(lim.get("lower", 0) + want) <= LIMIT_TOL and abs(lim.get("upper", 0) - want) <= LIMIT_TOL
              and lim.get("effort", 0) > 0 and lim.get("velocity", 0) > 0)
        check(ok and sim <= want, f"{j.name}: limits +-{deg} deg ({lim.get('lower')}, {lim.get('upper')}), "
              f"effort {lim.get('effort')} N m, velocity {lim.get('velocity')} rad/s; the simulator's +-{sim} inside")

    # ---- forward kinematics against the simulator ------------------------------
    qs = configurations()
    run = subprocess.run([tool], input="".join(" ".join(f"{v:.17g}" for v in q) + "\n" for q in qs),
                         capture_output=True, text=True, timeout=60)
    if not check(run.returncode == 0, f"{os.path.basename(tool)} ran (exit {run.returncode}) {run.stderr.strip()}"):
        return 1
    lines = run.stdout.splitlines()
    sim_links = {}
    tool_line = None
    rows = []
    for line in lines:
        f = line.split()
        if f[0] == "link":
            sim_links[int(f[1])] = [float(x) for x in f[2:]]
        elif f[0] == "tool":
            tool_line = [float(x) for x in f[1:]]
        else:
            rows.append([float(x) for x in f])
    check(len(rows) == len(qs) and all(len(r) == 8 * 12 for r in rows),
          f"{len(rows)} FK rows of 96 numbers for {len(qs)} configurations")
    if failures:
        return 1
    worst_flange = [0.0, 0.0]
    worst_joint = [0.0, 0.0]
    bad = []
    for q, row in zip(qs, rows):
        qd = dict(zip(JOINTS, q))
        sim_flange = frame_from_row(row[7 * 12:8 * 12])
        dp, dr = frame_error(model.fk("lwr_flange", qd), sim_flange)
        worst_flange = [max(worst_flange[0], dp), max(worst_flange[1], dr)]
        if dp > FK_POS_TOL or dr > FK_ROT_TOL:
            bad.append(f"flange at q = {np.round(q, 4).tolist()}: {dp:.3g} m, {dr:.3g} rad")
        # tip of the simulator's segment k (k = 1..7) = the URDF's frame of
        # joint k+1 before its rotation (k = 7: the flange).
        for k in range(1, 7):
            urdf_joint = model.fk(LINKS[k], qd) @ urdf_fk.transform(urdf_fk.rot_axis([0, 0, 1], -q[k]))
            dp, dr = frame_error(urdf_joint, frame_from_row(row[(k - 1) * 12:k * 12]))
            worst_joint = [max(worst_joint[0], dp), max(worst_joint[1], dr)]
            if dp > FK_POS_TOL or dr > FK_ROT_TOL:
                bad.append(f"{JOINTS[k]} at q = {np.round(q, 4).tolist()}: {dp:.3g} m, {dr:.3g} rad")
        dp, dr = frame_error(frame_from_row(row[6 * 12:7 * 12]), sim_flange)  # the simulator's own two FKs
        worst_joint = [max(worst_joint[0], dp), max(worst_joint[1], dr)]
    check(not bad, f"lwr_flange on {len(qs)} configurations within {FK_POS_TOL} m, {FK_ROT_TOL} rad of "
          f"LwrArm::forward (largest {worst_flange[0]:.2g} m, {worst_flange[1]:.2g} rad)"
          + ("" if not bad else "; " + "; ".join(bad[:5]) + (f" ... ({len(bad)} in all)" if len(bad) > 5 else "")))
    check(worst_joint[0] <= FK_POS_TOL and worst_joint[1] <= FK_ROT_TOL,
          f"joints A2..A7 against the simulator's KDL segment tips: largest {worst_joint[0]:.2g} m, "
          f"{worst_joint[1]:.2g} rad")
    check(abs(model.fk("lwr_flange", {})[2, 3] - 1.178) <= FK_POS_TOL, "q = 0: the flange at z = 1.178 m")

    # ---- the sensor mount -------------------------------------------------------
    sm = program_yaml.load(program)["controller"]["sensor_mount"]  # its base merged
    want = urdf_fk.transform(urdf_fk.rot_rpy(*[math.radians(a) for a in sm["rpy_deg"]]), sm["xyz"])
    dp, dr = frame_error(model.relative("lwr_flange", "wts0614", {}), want)
    check(dp <= FK_POS_TOL and dr <= FK_ROT_TOL,
          f"lwr_flange -> wts0614 = {os.path.basename(program)}'s sensor_mount {sm} ({dp:.2g} m, {dr:.2g} rad)")

    # ---- inertials --------------------------------------------------------------
    for k in range(1, 8):
        link = model.links[LINKS[k - 1]]
        sim = sim_links.get(k)
        if not check(link.inertial is not None and sim is not None, f"{LINKS[k - 1]}: inertial and the simulator's link {k}"):
            continue
        nxt = model.joints[JOINTS[k]] if k < 7 else model.parent_joint["lwr_flange"]
        tip = nxt.origin()  # the simulator's segment tip in the URDF link's frame
        inert = urdf_fk.transform(urdf_fk.rot_rpy(*link.inertial["rpy"]), link.inertial["xyz"])
        in_tip = np.linalg.inv(tip) @ inert
        i = link.inertial["inertia"]
        ok = (abs(link.inertial["mass"] - sim[0]) <= INERTIA_TOL
              and np.max(np.abs(in_tip[:3, 3] - sim[1:4])) <= INERTIA_TOL
              and urdf_fk.rotation_angle(in_tip[:3, :3]) <= FK_ROT_TOL
              and max(abs(i["ixy"]), abs(i["ixz"]), abs(i["iyz"])) == 0.0
              and np.max(np.abs(np.array([i["ixx"], i["iyy"], i["izz"]]) - sim[4:7])) <= INERTIA_TOL)
        check(ok, f"{LINKS[k - 1]}: mass {link.inertial['mass']} kg, COM {np.round(in_tip[:3, 3], 6).tolist()} m in the "
              f"segment's tip frame, moments {[i['ixx'], i['iyy'], i['izz']]} = the simulator's {sim}")
    fl = model.links["lwr_flange"].inertial
    check(fl is not None and tool_line is not None and abs(fl["mass"] - tool_line[0]) <= INERTIA_TOL
          and np.max(np.abs(fl["xyz"] - tool_line[1:4])) <= INERTIA_TOL,
          f"lwr_flange: the simulator's tool {tool_line} (kg, m in {{e}})")

    # ---- the pad ----------------------------------------------------------------
    want_size = [(COLS + 1) * PITCH, (ROWS + 1) * PITCH]
    pads = [b for b in model.links["wts0614"].boxes
            if abs(b[2][0] - want_size[0]) <= 1e-9 and abs(b[2][1] - want_size[1]) <= 1e-9]
    check(len(pads) == 1 and abs(pads[0][0][2] + pads[0][2][2] / 2) <= 1e-9 and np.allclose(pads[0][0][:2], 0)
          and np.allclose(pads[0][1], 0),
          f"wts0614: a pad box {want_size[0] * 1e3:.1f} x {want_size[1] * 1e3:.1f} mm centred on {{s}}, top face at z = 0")

    fk_failed = any("configurations within" in f or "segment tips" in f or "1.178" in f for f in failures)
    if mutate:
        print(f"mutated model: forward kinematics {'fails (detected)' if fk_failed else 'still passes (NOT detected)'}")
        return 0 if fk_failed else 1
    print(f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
