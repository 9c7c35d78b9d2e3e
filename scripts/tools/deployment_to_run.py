#!/usr/bin/python3
"""Convert an OCL::FileReporting time series of an experiment deployment
(deployments/experiment_start.ops: the servo's `phase` and `pose_command`,
the robot's `flange_pose`, the features) into the headless runner's run
directory format, so that scripts/tools/plot_run.py and scripts/tools/experiment_report.py
read it: timeseries.csv (the columns of core/sim/runner/src/output.cpp, same
order) and summary.json.

usage: deployment_to_run.py REPORT.dat OUT_DIR (--program params/programs/x.yaml
                            [--controller-mode MODE] | --servo-cpf x.cpf)
                            [--scene params/scenes/x.yaml] [--experiment NAME]
                            [--source sim|robot] [--deployer-exit N] [--robot-status S]
                            [--verdict TEXT] [--wall-time S]

The reporter's file (ComplexDecompose = true, so that the typekit's arrays
and enums decompose): one header line with the leaf names of the reported
ports ("TimeStamp Servo.phase.time_s ... Servo.pose_command.pose.p.Element0
... Features.features.status"), then one line per period (100 Hz, sampled:
not synchronised with the servo's cycles), values separated by whitespace
(the phase name's 32 chars one per column, NULs included; enums by name).
FileReporting streams each value with the C++ stream default, 6 significant
digits: the TimeStamp keeps 10 us up to 10 s and 0.1 ms up to 100 s,
positions 1 um on a 1 m scale, forces and features 6 significant digits, but
the servo's own time_s (RTT's clock since boot, thousands of seconds) only
10 ms or worse: the converter takes time from TimeStamp. It writes what it
has with the runner's %.9g, i.e. it does not add precision.

From the servo's program (--program and --controller-mode: the experiment
registry's program and controller, experiments.yaml; or the program_file and
controller_mode of a servo .cpf): the sensor mount {e}T{s} (cmd_*/act_* are the sensor pose
{g}T{s}, as the runner logs them), c_z and each phase's s_d (the sd_*
columns). Quantities only the simulator knows (force_true, housing_force,
moment_*_true, tray_angle_deg, true_c*, u_*, beta, feature_age) are "nan":
a deployment sees what the robot sees. The summary's metrics that need them
are null; measured counterparts are given under their own names, over the
same two windows as the runner's (docs/formats.md, "summary.json"): the
slide (slide_duration_s, sensor_slide_path_m, sensor_slide_mean_speed_mps,
slide_force_measured_*) and the scored window (scored_duration_s,
sensor_scored_path_m, sensor_scored_mean_speed_mps, force_measured_*; and
sensor_path_length_m, sensor_slide_speed_mps, the same values), the sensor's
path standing for the true contact's; the scene (--scene) names the scored
phases and the transient. The final DZMP_y, the tray's DZMP recovery time and
translation along x_s follow the runner's definitions on measured data
(deployment time starts with the servo, a few ms after the simulated arm).

A run that stopped on a fault is converted up to its end: `status` names the
fault (servo_<status> at the first cycle with a fatal servo status, as the
runner; sim_/robot_<status> for the arm's; experiment_failed or
deployment_failed after a failed run or step, --verdict) and `fault_time_s`
when it happened (null for an ok run).
"""
import argparse
import json
import math
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np
import yaml

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import program_yaml  # noqa: E402

COLUMNS = ("time,phase,phase_name,servo_status,contact,feature_status,cmd_x,cmd_y,cmd_z,cmd_roll,cmd_pitch,cmd_yaw,"
           "act_x,act_y,act_z,act_roll,act_pitch,act_yaw,cop_x,cop_y,coc_x,coc_y,dzmp_x,dzmp_y,alpha_z,force,d_z,"
           "lambda1,lambda2,area,sd_cop_x,sd_cop_y,sd_d_z,sd_dzmp_x,sd_dzmp_y,sd_alpha_z,sd_force,force_true,"
           "force_layer,housing_force,moment_x_true,moment_y_true,tray_angle_deg,true_cx,true_cy,true_cz,u_x,u_y,"
           "u_z,u_wx,u_wy,u_wz,beta,feature_age").split(",")
CONTACT = {"none": 0, "point": 1, "edge": 2, "multiple": 3}
SD_KEYS = ("cop_x", "cop_y", "d_z", "dzmp_x", "dzmp_y", "alpha_z")
# The servo's fatal statuses (a watchdog or the force ceiling: the runner's servo_* end statuses) and the
# simulated arm's (Robot.statusName() at the end).
FATAL_SERVO = ("force_ceiling", "phase_timeout", "arm_stalled", "force_mismatch", "surface_too_curved", "phantom_contact",
               "unseen_load", "correction_saturated", "correction_drift")  # tactile::watchdogStatus and the ceiling
FATAL_ROBOT = ("joint_limit", "singularity", "force_ceiling", "numerical_failure")


def fail(msg):
    sys.exit(f"deployment_to_run.py: {msg}")


def read_cpf(path):
    """Simple properties of an RTT .cpf file -> {name: text}."""
    try:
        root = ET.parse(path).getroot()
    except (OSError, ET.ParseError) as e:
        fail(f"{path}: {e}")
    return {s.get("name"): (s.findtext("value") or "") for s in root.iter("simple")}


def rot_rpy(r, p, y):
    """KDL::Rotation::RPY(r, p, y) = Rz(y) Ry(p) Rx(r)."""
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def rpy_of(R):
    """KDL::Rotation::GetRPY."""
    eps = 1e-12
    pitch = math.atan2(-R[2, 0], math.sqrt(R[0, 0] ** 2 + R[1, 0] ** 2))
    if abs(pitch) > math.pi / 2 - eps:
        yaw = math.atan2(-R[0, 1], R[1, 1])
        roll = 0.0
    else:
        roll = math.atan2(R[2, 1], R[2, 2])
        yaw = math.atan2(R[1, 0], R[0, 0])
    return roll, pitch, yaw


def quat_rot(qx, qy, qz, qw):
    n = math.sqrt(qx * qx + qy * qy + qz * qz + qw * qw)
    if not n > 0:
        return None
    x, y, z, w = qx / n, qy / n, qz / n, qw / n
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def load_program(path, mode_override):
    try:
        prog = program_yaml.load(path)  # its `base:` merged, as the servo reads it
    except program_yaml.ProgramError as e:
        fail(str(e))
    ctl = prog.get("controller", {}) or {}
    c_z = float(ctl.get("c_z", 0.000555556))
    mount = ctl.get("sensor_mount", {}) or {}
    xyz = np.array(mount.get("xyz", [0.0, 0.0, 0.0]), dtype=float)
    rpy = [math.radians(v) for v in mount.get("rpy_deg", [0.0, 0.0, 0.0])]
    mode = mode_override or ctl.get("mode", "proposed")
    names, sds, scored_default = [], [], []
    for ph in prog.get("phases", []):
        names.append(ph["name"])
        scored_default.append(bool(ph.get("requires_contact", True)) and not bool(ph.get("terminal", False)))
        sd = np.zeros(6)
        s = ph.get("s_d")
        if isinstance(s, list):
            sd[:] = [float(v) for v in s]
        elif isinstance(s, dict):
            for i, k in enumerate(SD_KEYS):
                if k in s:
                    sd[i] = float(s[k])
            if "force" in s:
                sd[2] = c_z * float(s["force"])
        sds.append(sd)
    return dict(c_z=c_z, mount_p=xyz, mount_R=rot_rpy(*rpy), mode=mode, names=names, sds=sds,
                scored_default=scored_default)


def read_report(path):
    try:
        lines = open(path).read().splitlines()
    except OSError as e:
        fail(f"{path}: {e}")
    lines = [ln for ln in lines if ln.strip()]
    if not lines:
        fail(f"{path}: empty (did the reporter start?)")
    head = lines[0].split()
    rows = []
    for n, ln in enumerate(lines[1:], start=2):
        v = ln.split()
        if len(v) != len(head):
            fail(f"{path}:{n}: {len(v)} values for {len(head)} header names")
        rows.append(v)
    return head, rows


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("report")
    ap.add_argument("out_dir")
    ap.add_argument("--program", default="", help="the servo's program (the registry's program)")
    ap.add_argument("--controller-mode", default="", help="the registry's controller ('' = the program's)")
    ap.add_argument("--servo-cpf", default="", help="instead of --program: a servo .cpf (program_file, controller_mode)")
    ap.add_argument("--scene", default="", help="the registry's scene: its metrics (force_phases, transient_s, "
                                                "force_band_n) define the slide and the scored window")
    ap.add_argument("--experiment", default="")
    ap.add_argument("--source", default="sim", choices=("sim", "robot"))
    ap.add_argument("--deployer-exit", type=int, default=0)
    ap.add_argument("--wall-time", type=float, default=float("nan"))
    ap.add_argument("--robot-status", default="",
                    help="Robot.statusName() at the end (experiment_finish.ops logs it): a simulator's fatal status "
                         "(joint_limit, singularity, force_ceiling, numerical_failure) becomes the summary's status "
                         "sim_<status>, as in the runner")
    ap.add_argument("--verdict", default="",
                    help="the deployment's verdict as tactile::DeployGuard logged it ('FINISHED: ...', 'FAILED: ...'; "
                         "experiment_finish.ops): kept in the summary, and a failed run without a named fault is "
                         "experiment_failed, a failed deployment step deployment_failed")
    return ap.parse_args()


def load_inputs(a):
    if a.program:
        prog = load_program(os.path.normpath(os.path.abspath(a.program)), a.controller_mode)
    elif a.servo_cpf:
        cpf = read_cpf(a.servo_cpf)
        if "program_file" not in cpf:
            fail(f"{a.servo_cpf}: no program_file property")
        prog_path = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(a.servo_cpf)), cpf["program_file"]))
        prog = load_program(prog_path, cpf.get("controller_mode", ""))
    else:
        fail("--program (the registry's program) or --servo-cpf is needed")
    scene = {}
    if a.scene:
        try:
            scene = yaml.safe_load(open(a.scene)) or {}
        except (OSError, yaml.YAMLError) as e:
            fail(f"{a.scene}: {e}")
    return prog, scene


def convert_rows(report, prog):
    """The reporter's table as rows of timeseries.csv (COLUMNS), and the phase entries."""
    head, rows = read_report(report)
    col = {h: i for i, h in enumerate(head)}

    def need(name):
        if name not in col:
            fail(f"{report}: no column {name} (reported ports: Servo.phase, Servo.pose_command, "
                 f"Robot.flange_pose, Features.features)")
        return col[name]

    ph = "Servo.phase."
    cm = "Servo.pose_command.pose."
    fp = "Robot.flange_pose."
    ft = "Features.features."
    i_t, i_idx, i_st = need(ph + "time_s"), need(ph + "index"), need(ph + "status")
    i_stamp = need("TimeStamp")
    i_cp = [need(f"{cm}p.Element{k}") for k in range(3)]
    i_cq = [need(f"{cm}q.Element{k}") for k in range(4)]
    i_fp = [need(f"{fp}p.Element{k}") for k in range(3)]
    i_fq = [need(f"{fp}q.Element{k}") for k in range(4)]
    feat = ("cop_x", "cop_y", "coc_x", "coc_y", "dzmp_x", "dzmp_y", "alpha_z", "force", "d_z", "lambda1", "lambda2",
            "area")
    i_f = [need(ft + k) for k in feat]
    i_contact, i_fstatus = need(ft + "contact"), need(ft + "status")

    def sensor_pose(p, q):
        R = quat_rot(*q)
        if R is None:
            return [float("nan")] * 6
        Rs = R @ prog["mount_R"]
        ps = np.array(p) + R @ prog["mount_p"]
        return list(ps) + list(rpy_of(Rs))

    out_rows = []
    phases = []
    t0 = None
    last_idx = None
    for r in rows:
        if not float(r[i_t]) > 0:
            continue  # the servo had not run yet
        # Time: the reporter's TimeStamp (s since it started; 6 significant
        # digits: 0.1 ms at 10 s). The servo's time_s is RTT's clock since
        # boot, whose 6 digits would only resolve 10 ms after ~17 min of uptime.
        ts = float(r[i_stamp])
        if t0 is None:
            t0 = ts
        t = ts - t0
        idx = int(float(r[i_idx]))
        name = prog["names"][idx] if 0 <= idx < len(prog["names"]) else ""
        if idx != last_idx:
            phases.append({"name": name, "t_enter": round(t, 4)})
            last_idx = idx
        cmd = sensor_pose([float(r[i]) for i in i_cp], [float(r[i]) for i in i_cq])
        act = sensor_pose([float(r[i]) for i in i_fp], [float(r[i]) for i in i_fq])
        f = [float(r[i]) for i in i_f]
        sd = prog["sds"][idx] if 0 <= idx < len(prog["sds"]) else np.zeros(6)
        sd_force = sd[2] / prog["c_z"] if prog["c_z"] > 0 else float("nan")
        contact = CONTACT.get(r[i_contact], -1)
        truth = [float("nan")] * 17  # force_true .. feature_age: the simulator's truth, not in a deployment
        out_rows.append([t, idx, name, r[i_st], contact, r[i_fstatus]] + cmd + act + f + list(sd) + [sd_force] + truth)
    if not out_rows:
        fail(f"{report}: no row with the servo running (Servo.phase.time_s > 0)")
    return out_rows, phases


def write_timeseries(out_dir, out_rows):
    os.makedirs(out_dir, exist_ok=True)
    with open(os.path.join(out_dir, "timeseries.csv"), "w") as f:
        f.write(",".join(COLUMNS) + "\n")
        for r in out_rows:
            cells = [f"{r[0]:.4f}", str(r[1]), r[2], r[3], str(r[4]), r[5]]
            cells += ["nan" if not math.isfinite(v) else f"{v:.9g}" for v in r[6:]]
            f.write(",".join(cells) + "\n")


def scored_as(names, t, is_scored, transient):
    """Per row, the phase it is scored as (the runner's rule, core/sim/runner/src/metrics.cpp): its own, or for the
    rows of a detour (the run leaving a scored phase and back in it within `transient` s) the phase it left."""
    out = list(names)
    i = 1
    while i < len(names):
        if names[i] != names[i - 1] and is_scored(names[i - 1]) and not is_scored(names[i]):
            j = i
            while j < len(names) and not is_scored(names[j]):
                j += 1
            if j < len(names) and names[j] == names[i - 1] and t[j] - t[i] < transient:
                out[i:j] = [names[i - 1]] * (j - i)
            i = j
        i += 1
    return out


def windows(t, names, scored_names, transient):
    """The slide and the scored window as the runner defines them (docs/formats.md, "summary.json"): the rows
    scored as a scored phase, from the phase's first row; and of them those at least `transient` s after it."""
    as_ = scored_as(names, t, lambda n: n in scored_names, transient)
    slide = np.array([n in scored_names for n in as_], dtype=bool)
    scored = np.zeros(len(t), dtype=bool)
    t0, cur = 0.0, None
    for k, n in enumerate(as_):
        if n != cur:
            cur, t0 = n, t[k]
        scored[k] = slide[k] and t[k] - t0 >= transient
    return slide, scored


def window_figures(sel, t, force, sd_force, pos, in_contact, band):
    """Over the rows `sel`: the force's mean, max, RMS error and in-band fraction (per row); the path between
    consecutive rows of the window both in contact, the window's duration (the time steps between its consecutive
    rows) and its mean speed (the path over the part of the duration in contact)."""
    f, e = force[sel], force[sel] - sd_force[sel]
    path = duration = t_contact = 0.0
    for k in range(1, len(t)):
        if sel[k] and sel[k - 1]:
            duration += t[k] - t[k - 1]
            if in_contact[k] and in_contact[k - 1]:
                path += float(np.linalg.norm(pos[k] - pos[k - 1]))
                t_contact += t[k] - t[k - 1]
    return {"mean_n": float(np.mean(f)) if f.size else None,
            "max_n": float(np.max(f)) if f.size else None,
            "rms_error_n": float(np.sqrt(np.mean(e ** 2))) if f.size else None,
            "in_band_fraction": float(np.mean(np.abs(e) <= band)) if f.size else None,
            "path_m": path, "duration_s": duration, "speed_mps": path / t_contact if t_contact > 0 else None}


def tray_figures(scene, t_all, dz, in_contact, pos, rpy):
    """The tray's DZMP_y recovery time and the translation along x_s since its move (the runner's definitions on
    measured data); None, None without a tray."""
    trays = [o for o in scene.get("objects", []) or [] if o.get("type") == "tray"]
    if not trays:
        return None, None
    t_move = float(trays[0].get("move_start_s", 0.0))
    settled = None
    for k in range(len(t_all) - 1, -1, -1):
        if t_all[k] < t_move or abs(dz[k]) > 0.0005 or not in_contact[k]:
            break
        settled = t_all[k]
    recovery = None if settled is None else settled - t_move
    before = [k for k in range(len(t_all)) if t_all[k] <= t_move]
    translation = None
    if before:
        b = before[-1]
        xs = rot_rpy(*rpy[b])[:, 0]
        translation = float(np.dot(pos[-1] - pos[b], xs))
    return recovery, translation


def run_status(out_rows, phases, a):
    """The run's status and the time (s) of the fault that ended it: the first cycle with a fatal servo status
    (servo_<status>, the runner's names); else the robot's fatal status at the end (sim_/robot_<status>, at the last
    row); else, after a failed run or deployment step (deployer exit != 0), experiment_failed or deployment_failed
    (the Guard's verdict says which) at the entry of the phase the run ended in (the program's own failure phase,
    or the stop phase the state machine switched to); else ok, None."""
    for r in out_rows:
        if r[3] in FATAL_SERVO:
            return "servo_" + r[3], r[0]
    if a.robot_status in FATAL_ROBOT:
        return ("sim_" if a.source == "sim" else "robot_") + a.robot_status, out_rows[-1][0]
    if a.deployer_exit != 0:
        step = not a.verdict.startswith("FAILED") or "deployment step failed" in a.verdict
        return ("deployment_failed" if step else "experiment_failed"), phases[-1]["t_enter"]
    return "ok", None


def measured_figures(out_rows, prog, scene):
    """Measured counterparts of the runner's metrics (core/sim/runner/src/metrics.cpp) from what a deployment sees:
    the slide and the scored window (the scene's metrics.force_phases, default the phases that need contact and
    are not terminal; metrics.transient_s) give the measured force and the sensor's path (the runner uses the true
    contact point); the final DZMP_y and, with a tray, its recovery time and the translation along x_s follow the
    runner's definitions on measured data."""
    arr = lambda k: np.array([r[COLUMNS.index(k)] for r in out_rows], dtype=float)  # noqa: E731
    t_all, force, sdf = arr("time"), arr("force"), arr("sd_force")
    in_contact = arr("contact") > 0
    pos = np.stack([arr("act_x"), arr("act_y"), arr("act_z")], axis=1)
    metrics = scene.get("metrics", {}) or {}
    scored_names = metrics.get("force_phases") or [n for n, d in zip(prog["names"], prog["scored_default"]) if d]
    transient = float(metrics.get("transient_s", 0.0))
    band = float(metrics.get("force_band_n", 1.0))
    slide, scored = windows(t_all, [r[2] for r in out_rows], scored_names, transient)
    sw = window_figures(slide, t_all, force, sdf, pos, in_contact, band)
    sc = window_figures(scored, t_all, force, sdf, pos, in_contact, band)
    last = (t_all >= t_all[-1] - 0.5) & in_contact
    fm = force[in_contact]
    rpy = np.stack([arr("act_roll"), arr("act_pitch"), arr("act_yaw")], axis=1)
    recovery, translation = tray_figures(scene, t_all, arr("dzmp_y"), in_contact, pos, rpy)
    return {
        "force_measured_mean_n": sc["mean_n"], "force_measured_max_n": sc["max_n"],
        "force_measured_rms_error_n": sc["rms_error_n"], "force_measured_in_band_fraction": sc["in_band_fraction"],
        "force_measured_max_any_phase_n": float(np.max(fm)) if fm.size else None,
        "scored_duration_s": sc["duration_s"],
        "sensor_scored_path_m": sc["path_m"], "sensor_scored_mean_speed_mps": sc["speed_mps"],
        "sensor_path_length_m": sc["path_m"], "sensor_slide_speed_mps": sc["speed_mps"],
        "slide_duration_s": sw["duration_s"],
        "sensor_slide_path_m": sw["path_m"], "sensor_slide_mean_speed_mps": sw["speed_mps"],
        "slide_force_measured_mean_n": sw["mean_n"], "slide_force_measured_max_n": sw["max_n"],
        "slide_force_measured_rms_error_n": sw["rms_error_n"],
        "slide_force_measured_in_band_fraction": sw["in_band_fraction"],
        "dzmp_final_m": float(np.mean(arr("dzmp_y")[last])) if last.any() else None,
        "dzmp_recovery_time_s": recovery,
        "translation_x_m": translation,
    }


# The simulator's ground truth, which a deployment's table does not carry: null in its summary.
TRUTH_KEYS = ("contact_lost_count", "force_true_mean_n", "force_true_max_n", "force_true_rms_error_n",
              "force_true_in_band_fraction", "alignment_time_s", "scored_path_m", "scored_mean_speed_mps",
              "path_length_m", "slide_speed_mps", "slide_path_m", "slide_mean_speed_mps", "slide_force_true_mean_n",
              "slide_force_true_max_n", "slide_force_true_rms_error_n", "slide_force_true_in_band_fraction",
              "tray_angle_max_deg")


def main():
    a = parse_args()
    prog, scene = load_inputs(a)
    out_rows, phases = convert_rows(a.report, prog)
    write_timeseries(a.out_dir, out_rows)
    status, fault_time = run_status(out_rows, phases, a)
    name = a.experiment or scene.get("name", "")
    summary = {
        "scene": name,
        "scene_file": a.scene,
        "figure": scene.get("figure", ""),
        "controller": prog["mode"],
        "fidelity": "deployment (" + a.source + ")",
        "source": "deployer (" + a.source + "): " + os.path.basename(a.report),
        "status": status,
        "fault_time_s": None if fault_time is None else round(fault_time, 4),
        "verdict": a.verdict or None,
        "exit_code": a.deployer_exit,
        "robot_status": a.robot_status or None,
        "rates_hz": {"servo": 100, "report": 100},
        "sim_time_s": round(out_rows[-1][0], 4),
        "wall_time_s": a.wall_time if math.isfinite(a.wall_time) else None,
        "real_time_factor": 1.0,
        "phases": phases,
    }
    summary.update({k: None for k in TRUTH_KEYS})
    summary.update(measured_figures(out_rows, prog, scene))
    summary["report_precision"] = "6 significant digits (OCL FileReporting, C++ stream default)"
    with open(os.path.join(a.out_dir, "summary.json"), "w") as f:
        json.dump(summary, f, indent=2)
        f.write("\n")
    when = "" if fault_time is None else f" at {fault_time:.2f} s"
    print(f"{a.out_dir}: {len(out_rows)} rows, phases {[p['name'] for p in phases]}, status {status}{when}")


if __name__ == "__main__":
    main()
