#!/usr/bin/python3
"""The fault x outcome table: each fault of the pad and of the arm's estimated
wrench injected during the edge exploration, each against its stated outcome.

usage: fault_table.py [--sim build/bin/tactile_sim] [--out out/faults] [--jobs N]
                      [--only a,b] [--robot] [--docs DIR | --no-docs]

Runs the edge exploration (params/scenes/edge_exploration.yaml: the unattended
robot experiment of Sec. 5.2) headless once per row of FAULTS, with the fault
given on the command line (`--set faults=[...]`, tactile_sim_faults/sensor_faults.hpp),
from FAULT_START_S (mid-slide: the slide runs from about 4.6 s to 27.7 s) or
from the start (a wrong calibration or load model), and the phantom contact
(params/scenes/faults/phantom_contact.yaml: the pad reports 8 N, nothing touches).
For each run it records the status and exit code (summary.json), the true
force's maximum over the run (N), the measured sensor's travel after the
fault started (m, timeseries.csv act_x..act_z), and whether the force targets
held after it (the true force in the explore phase: RMS error <= 0.4 N and
>= 95 % within +-0.5 N of the set point, as docs/results.md's).

Each row states the outcome a safe controller must reach: never a true force
above the program's force ceiling (safety.force_ceiling), and
  continue  the run ends ok, the experiment's criteria met (metrics.criteria:
            the slide's length among them), the force targets held after
            the fault;
  stop      a named servo stop (one of the row's statuses) with less than the
            row's travel after the fault;
  either    one of the two (any named servo stop); a named stop after the
            targets were held all along counts as the run going on;
  reach     a wrench drift below the drift check's reach: the run ends ok
            with the true force's RMS error within the check's
            max_change_n (watchdogs.correction_drift), or the check stops it.
            The fused estimate follows the wrench, so a drift it does not
            stop moves the true force by as much: on the robot path 1 N/min
            costs the 0.5 N band where the pad leaves the bar's end.
The verdict compares the observed outcome with the stated one.

With --robot each row also runs on the robot path: the unchanged robot
deployment against lab_sim (scripts/run_robot_lab.sh edge_exploration
--scene: the KRC over FRI on loopback UDP, the WTS0614 on a PTY) with the
same fault in lab_sim's world, one run at a time (about 10 min in all: lab_sim
runs in real time), the KRC's link quality held at PERFECT (lab_sim
--quality-rule off: the row measures the fault, not this host's timing; the
link's drops are the rehearsal's). Its outcome is judged against the same statement, on
lab_sim's ground truth (the run's summary.json: the state machine's verdict,
the servo's status, the true force; truth.csv: the flange's travel after the
fault, in lab_sim's clock, where the faults are scheduled). Writes
DOCS/faults.md (the table, with the commit and the machine), DOCS/results/faults.json
and DOCS/img/faults.png (default DOCS: docs/), the runs into --out; exits 1
when an outcome differs from the stated one (or a run wrote no summary).
"""
import csv
import json
import math
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import tactile_sweeps as ts  # noqa: E402
from tactile_sweeps.plot import plt, save  # noqa: E402

sys.path.insert(0, ts.TOOLS)
import results_docs  # noqa: E402  (machine(), head_commit(): the documents' header line)

SCENE = "edge_exploration"
FAULT_START_S = 12.0           # s: mid-slide (explore from ~4.6 s to ~27.7 s)
RMS_MAX_N = ts.FORCE_RMS_MAX_N
BAND_N = ts.FORCE_BAND_N
IN_BAND_MIN = ts.FORCE_IN_BAND_MIN
TRAVEL_SAMPLE_S = 0.1         # s: the travel's sampling
TRANSIENT_S = 2.0             # s: the explore phase's start left out of the targets (edge_exploration's transient_s)
# The detections of a pad contact the wrench contradicts (and the current force mismatch).
CONTRADICTION = ["servo_phantom_contact", "servo_force_mismatch"]

T = FAULT_START_S
REGION = "rows: [1, 4], cols: [5, 8]"  # 16 taxels under the pad's middle

# The correction of the force estimate held at its bound (a wrong calibration, a wrong wrench).
SATURATED = ["servo_correction_saturated"]
# The correction moving from its anchor (watchdogs.correction_drift: the wrench or the pad's tare drifting).
DRIFT = ["servo_correction_drift"]

# name, group, what (parameters), fault list (YAML) or scene, start (s), expected.
# expected: ("continue",) | ("stop", [statuses], max travel mm) | ("either", [statuses] or None: any named
# servo stop, max travel mm, or None: a fault that grows slowly, stopped with the force targets held up to
# the stop; in either case any named stop with the targets held up to it is as good as the run going on
# within them) | ("reach",): a drift below the
# drift check's reach: the run ends ok with the true force's RMS error within the check's max_change_n (the
# fused estimate follows the wrench: a drift it does not stop moves the set point by as much), or the
# check's stop. The no-fault row is scored from FAULT_START_S, as the faults that start there.
FAULTS = [
    ("none", "-", "no fault", "[]", T, ("continue",)),
    ("stuck_region", "pad", "16 taxels stuck at 8 N (0.5 N each), rows 1-4 x cols 5-8",
     f"[{{kind: stuck, start_s: {T}, {REGION}, force_n: 8}}]", T, ("stop", CONTRADICTION, 50)),
    ("tare_creep_small", "pad", "every zero +60 counts/min (below the 0.2 N threshold for the run)",
     f"[{{kind: tare_creep, start_s: {T}, counts_per_min: 60}}]", T, ("continue",)),
    ("tare_creep", "pad", "every zero +1200 counts/min (0.2 N threshold passed after ~25 s)",
     f"[{{kind: tare_creep, start_s: {T}, counts_per_min: 1200}}]", T, ("either", None, None)),
    ("dead_band", "pad", "columns 0-6 (half the pad along the edge) read 0",
     f"[{{kind: dead, start_s: {T}, cols: [0, 6]}}]", T, ("either", None, 50)),
    ("stale", "pad", "no frame for 0.5 s", f"[{{kind: stale, start_s: {T}, duration_s: 0.5}}]", T, ("continue",)),
    ("repeat", "pad", "the last frame re-sent for 2 s (new seq and time stamp)",
     f"[{{kind: repeat, start_s: {T}, duration_s: 2}}]", T, ("either", None, 50)),
    ("unplugged", "pad", "link down 1 s, then the reader's frames again",
     f"[{{kind: disconnect, start_s: {T}, duration_s: 1}}]", T, ("continue",)),
    # The correction carries the half the pad misses: at its bound (the headless pad, whose sub-threshold
    # load is the larger) a stop within a few cm; below it the run holds its targets, and the correction's
    # share of the load changes where the pad leaves the bar's end: a drift stop there, targets held.
    ("calibration_0.5x", "pad", "the reader reads 0.5 x the true force, from the start",
     "[{kind: calibration, scale: 0.5}]", 0.0, ("either", SATURATED, 100)),
    ("calibration_2x", "pad", "the reader reads 2 x the true force, from the start",
     "[{kind: calibration, scale: 2.0}]", 0.0, ("either", CONTRADICTION + SATURATED, 100)),
    ("wrench_bias", "wrench", "+5 N along z_g", f"[{{kind: wrench_bias, start_s: {T}, bias_n: [0, 0, 5]}}]", T,
     ("either", None, 50)),
    ("wrench_drift_small", "wrench", "+1 N/min along z_g",
     f"[{{kind: wrench_drift, start_s: {T}, drift_n_per_min: [0, 0, 1]}}]", T, ("reach",)),
    # A drift is stopped by the drift check (correction_drift: the correction 1 N from its anchor, low-passed
    # over 1 s) once it has added about 1 N and the filter caught up: 6 s + 1 s at 10 N/min, at the slide's
    # 8-10 mm/s up to 70 mm (the robot path's slide is the faster).
    ("wrench_drift", "wrench", "+10 N/min along z_g (reads more than the truth)",
     f"[{{kind: wrench_drift, start_s: {T}, drift_n_per_min: [0, 0, 10]}}]", T, ("either", None, 75)),
    # Reading less than the truth: the correction falls and the law pushes harder.
    ("wrench_drift_down", "wrench", "-10 N/min along z_g (reads less than the truth)",
     f"[{{kind: wrench_drift, start_s: {T}, drift_n_per_min: [0, 0, -10]}}]", T, ("either", None, 75)),
    ("wrench_frame", "wrench", "flange axes reported as base axes",
     f"[{{kind: wrench_frame, start_s: {T}, axes: flange}}]", T, ("either", None, 50)),
    ("wrench_sign", "wrench", "the wrench negated", f"[{{kind: wrench_sign, start_s: {T}}}]", T, ("either", None, 50)),
    ("pad_mass_static", "wrench", "load model 0.5 kg light, from the start (tared in free motion)",
     "[{kind: pad_mass, mass_kg: 0.5}]", 0.0, ("continue",)),
    ("pad_mass_mid_slide", "wrench", "load model 0.5 kg light from mid-slide (after the tare)",
     f"[{{kind: pad_mass, start_s: {T}, mass_kg: 0.5}}]", T, ("either", None, 50)),
    ("phantom_contact", "both", "8 N stuck press from t = 0, nothing in contact (faults/phantom_contact)",
     "scene:faults/phantom_contact", 0.0, ("stop", CONTRADICTION, 50)),
]


def expected_text(e, reach_n):
    if e[0] == "continue":
        return "continues within force targets (ends ok, criteria met)"
    if e[0] == "reach":
        return (f"continues with the true force within the drift check's reach (ends ok, RMS error <= "
                f"{reach_n:g} N), or named stop correction_drift")
    names = "a named stop" if not e[1] else "named stop " + " or ".join(s[len("servo_"):] for s in e[1])
    if e[0] == "stop":
        return f"{names}, travel < {e[2]} mm"
    if e[2] is None:
        return f"continues within force targets (ends ok, criteria met), or {names} with the targets held up to it"
    return (f"continues within force targets (ends ok, criteria met), or {names} with travel < {e[2]} mm, "
            f"or a named stop with the targets held up to it")


def program_limits(scene):
    """(safety.force_ceiling, watchdogs.correction_drift.max_change_n) of the scene's program (N)."""
    path = ts.scenes.program_of(scene)
    sys.path.insert(0, os.path.join(ts.scenes.ROOT, "scripts", "tools"))
    import program_yaml  # its `base:` merged, as the servo reads it (tactile_sim program)
    prog = program_yaml.load(path)
    drift = prog.get("watchdogs", {}).get("correction_drift", {})
    if "max_change_n" not in drift:
        sys.exit(f"fault_table: {path}: watchdogs.correction_drift.max_change_n is not stated (the drift rows need it)")
    return float(prog.get("safety", {}).get("force_ceiling", 40.0)), float(drift["max_change_n"])


def measure(run_dir, start):
    """From timeseries.csv: the true force's max over the run; the measured
    sensor origin's travel after `start`, sampled every TRAVEL_SAMPLE_S (the
    servo's 100 Hz steps zigzag by a fraction of a millimetre); the explore
    phase's true force against its set point after `start` and after the
    phase's first TRANSIENT_S (the summary's metrics.transient_s)."""
    with open(os.path.join(run_dir, "timeseries.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    fmax, travel, prev, t_prev, errs, phase_at = 0.0, 0.0, None, -1e9, [], ""
    explore_t0 = next((float(r["time"]) for r in rows if r["phase_name"] == "explore"), float("inf"))
    for r in rows:
        t = float(r["time"])
        fmax = max(fmax, float(r["force_true"]))
        if t < start:
            continue
        phase_at = phase_at or r["phase_name"]
        p = (float(r["act_x"]), float(r["act_y"]), float(r["act_z"]))
        if t - t_prev >= TRAVEL_SAMPLE_S - 1e-6 or r is rows[-1]:
            travel += math.dist(p, prev) if prev is not None else 0.0
            prev, t_prev = p, t
        if r["phase_name"] == "explore" and float(r["sd_force"]) > 0.0 and t >= explore_t0 + TRANSIENT_S:
            errs.append(float(r["force_true"]) - float(r["sd_force"]))
    rms = math.sqrt(sum(e * e for e in errs) / len(errs)) if errs else float("nan")
    band = sum(abs(e) <= BAND_N for e in errs) / len(errs) if errs else float("nan")
    t_end = float(rows[-1]["time"]) if rows else float("nan")
    return {"force_true_max_n": fmax, "travel_after_m": travel, "rms_after_n": rms, "in_band_after": band,
            "phase_at_fault": phase_at, "t_end_s": t_end, "scored_after_s": len(errs) / 100.0}


def verdict(e, m, s, limits):
    """(outcome text, matches the expectation) for one run (s: its summary.json;
    limits: program_limits())."""
    ceiling, reach_n = limits
    status = s["status"]
    held = m["rms_after_n"] <= RMS_MAX_N and m["in_band_after"] >= IN_BAND_MIN
    named = status.startswith("servo_")
    if status == "ok":
        outcome = (f"ended ok at {m['t_end_s']:.2f} s, criteria {'met' if s['criteria_passed'] else 'failed'}, "
                   f"targets {'held' if held else 'missed'}")
    elif named:
        outcome = f"stop {status[len('servo_'):]} at {m['t_end_s']:.2f} s"
    else:
        outcome = f"{status} at {m['t_end_s']:.2f} s (not a servo stop)"
    safe = m["force_true_max_n"] <= ceiling
    cont = status == "ok" and s["criteria_passed"] and held
    travel_ok = len(e) < 3 or (held if e[2] is None else m["travel_after_m"] * 1e3 < e[2])
    if e[0] == "continue":
        ok = cont
    elif e[0] == "reach":
        ok = (status == "ok" and m["rms_after_n"] <= reach_n) or status in DRIFT
    elif e[0] == "stop":
        ok = status in e[1] and travel_ok
    else:
        # A named stop after the targets were held all along is as good as the run going on within them.
        ok = cont or (named and (not e[1] or status in e[1]) and travel_ok) or (named and held)
    return outcome, ok and safe


def one(job):
    name, _group, _what, faults, start, _e, out = job
    d = os.path.join(out, "runs", name)
    if faults.startswith("scene:"):
        scene, args = faults[len("scene:"):], []
    else:
        scene, args = SCENE, ["--set", "faults=" + faults]
    s = ts.run.run(scene, d, args)
    m = measure(d, start) if s.get("status") != "no_summary" else None
    return name, scene, s, m


def robot_scene(fault, out):
    """The scene lab_sim simulates for a row: the fault's own scene, or the
    edge exploration with the row's `faults:` list, its paths made absolute."""
    import yaml
    if fault[3].startswith("scene:"):
        return ts.scene_path(fault[3][len("scene:"):])
    src = ts.scene_path(SCENE)
    with open(src) as f:
        sc = yaml.safe_load(f)
    base = os.path.dirname(src)
    for k, v in list(sc.items()):
        if isinstance(v, str) and os.path.exists(os.path.join(base, v)) and "/" in v:
            sc[k] = os.path.normpath(os.path.join(base, v))
    sc["faults"] = yaml.safe_load(fault[3])
    path = os.path.join(out, "robot_scenes", fault[0] + ".yaml")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(f"# {SCENE} with the fault row {fault[0]} (scripts/sweeps/fault_table.py --robot)\n")
        yaml.safe_dump(sc, f, sort_keys=False)
    return path


def robot_measure(run_dir, start):
    """From the robot path's summary.json and lab_sim's truth.csv (lab_sim's
    clock, where the faults start): the true force's max, the flange's travel
    after `start` (every TRAVEL_SAMPLE_S), the end in lab_sim's clock (the
    KRC's last cycle in command mode), and the
    force targets over the scored window (the explore phase after its
    transient, as the headless rows', before the fault and after it)."""
    with open(os.path.join(run_dir, "summary.json")) as f:
        s = json.load(f)
    travel, prev, t_prev, t_end = 0.0, None, -1e9, float("nan")
    with open(os.path.join(run_dir, "truth.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        t = float(r["t"])
        if r["krc_state"] == "CMD" or t_end != t_end:
            t_end = t  # the run's end: the KRC's last command cycle (lab_sim runs on after friStop)
        if t < start:
            continue
        p = (float(r["flange_x"]), float(r["flange_y"]), float(r["flange_z"]))
        if t - t_prev >= TRAVEL_SAMPLE_S - 1e-6 or r is rows[-1]:
            travel += math.dist(p, prev) if prev is not None else 0.0
            prev, t_prev = p, t
    fmax = s.get("force_true_run_max_n")
    return s, {"force_true_max_n": fmax if fmax is not None else float("nan"), "travel_after_m": travel,
               "rms_after_n": s.get("force_true_rms_error_n") or float("nan"),
               "in_band_after": s.get("force_true_in_band_fraction") or float("nan"), "t_end_s": t_end}


def robot_row(fault, out, k, n, limits):
    """One row on the robot path: run_robot_lab.sh on the row's scene; its outcome and verdict."""
    d = os.path.join(out, "robot")
    t0 = time.time()
    # The KRC's link held at PERFECT (lab_sim --quality-rule off): the row measures the fault, not this
    # host's timing (the link's own drops are the rehearsal's, rehearse_first_day.sh).
    r = subprocess.run(["bash", os.path.join(ts.ROOT, "scripts", "run_robot_lab.sh"), SCENE, "--scene",
                        robot_scene(fault, out), "--out", os.path.join(d, fault[0]), "--", "--quality-rule", "off"],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    run_dir = os.path.join(d, fault[0], SCENE)
    if not os.path.exists(os.path.join(run_dir, "summary.json")):
        tail = r.stdout.strip().splitlines()[-1:] or ["no output"]
        print(f"[robot {k}/{n}] {fault[0]}: no summary ({tail[0]})", flush=True)
        return {"robot_observed": "no run", "robot_as_expected": False}
    s, m = robot_measure(run_dir, fault[4])
    outcome, ok = verdict(fault[5], m, s, limits)
    ok = ok and s.get("robot_verdict") in ("pass", "fail") and s.get("force_true_run_max_n") is not None
    print(f"[robot {k}/{n}] {fault[0]}: {outcome}; true force max {m['force_true_max_n']:.2f} N, travel after "
          f"{m['travel_after_m'] * 1e3:.1f} mm -> {'as stated' if ok else 'DIFFERS'} ({time.time() - t0:.0f} s)",
          flush=True)
    return {"robot_observed": outcome, "robot_status": s["status"], "robot_force_true_max_n": m["force_true_max_n"],
            "robot_travel_after_m": m["travel_after_m"], "robot_as_expected": ok,
            "robot_rms_n": none_if_nan(m["rms_after_n"]), "robot_in_band": none_if_nan(m["in_band_after"])}


def none_if_nan(v):
    return None if isinstance(v, float) and v != v else v


def targets_text(rms, band):
    return "-" if rms is None else f"{ts.fmt(rms)}, {ts.fmt(band, 0, 100)} %"


def table(rows, header):
    robot = any("robot_observed" in r for r in rows)
    extra = (" robot path: observed | true force max (N) | travel after fault (mm) | targets, scored window (RMS N, "
             "in band) | verdict |") if robot else ""
    out = [header, "",
           "| fault | parameters | expected | headless: observed | exit | true force max (N) | travel after fault (mm) "
           "| targets after fault (RMS N, in band) | verdict |" + extra,
           "|---|---|---|---|---|---|---|---|---|" + ("---|---|---|---|---|" if robot else "")]
    for r in rows:
        tgt = targets_text(r["rms_after_n"], r["in_band_after"])
        line = (f"| {r['fault']} | {r['parameters']} | {r['expected']} | {r['observed']} | {r['exit_code']} | "
                f"{ts.fmt(r['force_true_max_n'])} | {ts.fmt(r['travel_after_m'], 1, 1e3)} | {tgt} | "
                f"{'as stated' if r['as_expected'] else '**differs**'} |")
        if robot:
            if r.get("robot_status") is None:
                line += f" {r.get('robot_observed', 'not run')} | - | - | - | **differs** |"
            else:
                line += (f" {r['robot_observed']} | {ts.fmt(r['robot_force_true_max_n'])} | "
                         f"{ts.fmt(r['robot_travel_after_m'], 1, 1e3)} | "
                         f"{targets_text(r.get('robot_rms_n'), r.get('robot_in_band'))} | "
                         f"{'as stated' if r['robot_as_expected'] else '**differs**'} |")
        out.append(line)
    return out


def plot(rows, runs_dir, path):
    fig = plt.figure(figsize=(13, 8))
    grid = fig.add_gridspec(2, 2, width_ratios=[3, 2])
    axes = {"pad": fig.add_subplot(grid[0, 0]), "wrench": fig.add_subplot(grid[1, 0])}
    for r in rows:
        ts_path = os.path.join(runs_dir, r["fault"], "timeseries.csv")
        if not os.path.exists(ts_path):
            continue
        with open(ts_path, newline="") as f:
            data = [(float(x["time"]) - r["start_s"], float(x["force_true"])) for x in csv.DictReader(f)]
        for g in ("pad", "wrench"):
            if r["group"] in (g, "-", "both"):
                axes[g].plot([d[0] for d in data], [d[1] for d in data], lw=1.0 if r["as_expected"] else 1.6,
                             ls="-" if r["as_expected"] else "--", label=r["fault"])
    for g, a in axes.items():
        a.axvline(0.0, color="k", lw=0.8)
        a.axhspan(5.0 - BAND_N, 5.0 + BAND_N, color="0.85", zorder=0)
        a.set_ylabel("true force (N)")
        a.set_title(f"edge exploration, {g} faults: the true force (dashed: the outcome differs)", fontsize=10)
        a.legend(fontsize=7, ncol=2)
    axes["wrench"].set_xlabel("time since the fault started (s)")
    b = fig.add_subplot(grid[:, 1])
    names = [r["fault"] for r in rows]
    travel = [r["travel_after_m"] * 1e3 for r in rows]
    b.barh(names, travel, color=["tab:green" if r["as_expected"] else "tab:red" for r in rows])
    b.set_xscale("symlog", linthresh=10.0)
    b.axvline(50.0, color="k", ls=":", lw=0.8)
    b.invert_yaxis()
    b.set_xlabel("travel after the fault (mm; green: as stated, red: differs)")
    save(fig, path)


def main():
    ap = ts.cli.parser(__doc__, "faults", seeds=None)
    ap.add_argument("--only", default="", help="comma-separated fault names (default: all)")
    ap.add_argument("--docs", default=os.path.join(ts.ROOT, "docs"))
    ap.add_argument("--no-docs", action="store_true", help="write the table to --out only")
    ap.add_argument("--robot", action="store_true",
                    help="also run each fault on the robot path against lab_sim (about 10 min)")
    a = ts.cli.finish(ap.parse_args())
    only = [x for x in a.only.split(",") if x]
    faults = [f for f in FAULTS if not only or f[0] in only]
    if only and len(faults) != len(only):
        ap.error(f"--only: unknown fault among {only}; known: {', '.join(f[0] for f in FAULTS)}")
    limits = program_limits(SCENE)
    ceiling = limits[0]
    rows, bad = [], 0
    for k, n, (name, scene, s, m) in ts.pmap(one, [(*f, a.out) for f in faults], a.jobs):
        f = next(x for x in faults if x[0] == name)
        if m is None:
            print(f"[{k}/{n}] {name}: no summary: {s.get('error', '')}")
            bad += 1
            continue
        outcome, ok = verdict(f[5], m, s, limits)
        bad += 0 if ok else 1
        rows.append({"fault": name, "group": f[1], "parameters": f[2], "scene": scene, "faults": f[3],
                     "start_s": f[4], "expected": expected_text(f[5], limits[1]), "observed": outcome,
                     "status": s["status"], "exit_code": s["returncode"], "as_expected": ok,
                     **{key: (None if isinstance(v, float) and v != v else v) for key, v in m.items()}})
        print(f"[{k}/{n}] {name}: {outcome}; true force max {m['force_true_max_n']:.2f} N, travel after "
              f"{m['travel_after_m'] * 1e3:.1f} mm -> {'as stated' if ok else 'DIFFERS'}")
    if a.robot:
        for k, r in enumerate(rows, 1):
            r.update(robot_row(next(x for x in faults if x[0] == r["fault"]), a.out, k, len(rows), limits))
            bad += 0 if r["robot_as_expected"] else 1
    mach = results_docs.machine()
    commit = results_docs.head_commit(ts.ROOT)
    short = commit.split("-")[0][:12] + ("-dirty" if commit.endswith("-dirty") else "")
    header = (f"Commit `{short}`, {mach['uname']}, {mach['cpu']}, {mach['nproc']} cores; "
              f"scene `{SCENE}`, faults from {FAULT_START_S:g} s (mid-slide) unless from the start; "
              f"program force ceiling {ceiling:g} N; {sum(r['as_expected'] for r in rows)} of {len(faults)} "
              f"as stated headless" + (f", {sum(r['robot_as_expected'] for r in rows)} of {len(rows)} on the robot "
                                       f"path" if a.robot else "") + ".")
    md = table(rows, header)
    with open(os.path.join(a.out, "faults.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    if not a.no_docs:
        write_docs(a.docs, md, rows, header, commit, mach, a.out)
    print("\n".join(md))
    return 1 if bad else 0


def write_docs(docs, md, rows, header, commit, mach, out):
    os.makedirs(os.path.join(docs, "results"), exist_ok=True)
    os.makedirs(os.path.join(docs, "img"), exist_ok=True)
    intro = ["# Faults and their outcomes", "",
             "<!-- generated by scripts/sweeps/fault_table.py; do not edit -->", "",
             "Each fault of the pad (the WTS0614) and of the arm's estimated wrench injected while the "
             "edge exploration runs headless (`tactile_sim run params/scenes/edge_exploration.yaml --set "
             "'faults=[...]'`; the keys: [formats.md](formats.md), \"Faults\"), against the outcome a safe "
             "controller must reach: never a true force above the program's force ceiling, and either "
             "the run continues with the force targets held (true-force RMS error <= 0.4 N, >= 95 % within "
             "+-0.5 N, in the explore phase after the fault) and ends ok with the experiment's criteria met "
             "(`metrics.criteria`: the slide's length among them), or a named servo stop. \"Travel after fault\" is "
             "the measured sensor origin's path (timeseries.csv `act_x..act_z`, every 0.1 s) from the fault's "
             "start to the run's end. The named stops are the servo's statuses (summary.json `status`): "
             "`phantom_contact`, a pad contact the wrench contradicts; `correction_saturated`, the fused "
             "force correction held at its bound; `correction_drift`, the correction moving on the straight "
             "edge (the two sensors drifting apart: the wrench, or the pad's tare); `force_mismatch`, the "
             "tactile force and the wrench apart "
             "(`tactile_servo/watchdog.hpp`). A wrench drift slower than the drift check's reach (the correction within "
             "`max_change_n` of its anchor) is not a fault the servo can see: the fused estimate follows it, "
             "so it moves the true force by as much; its row states that bound, not the 0.5 N band. "
             "A named stop that comes after the targets were held all along is as good as the run going on within them. "
             "A verdict **differs** is an outcome the servo does not "
             "reach: a detection it lacks, or one that comes too late. The robot path (where run: "
             "`fault_table.py --robot`, the main job) is the same fault in lab_sim's world, the unchanged "
             "robot deployment against it over FRI and the WTS link (`scripts/run_robot_lab.sh`; the KRC's link "
             "quality held at PERFECT, `lab_sim --quality-rule off`: the row measures the fault, the link's own "
             "drops are the rehearsal's); its force and "
             "travel are lab_sim's ground truth in lab_sim's clock, its targets those of the run's scored window "
             "(the explore phase after its transient, before and after the fault).", ""]
    with open(os.path.join(docs, "faults.md"), "w") as f:
        f.write("\n".join(intro + md + ["", "![faults](img/faults.png)", ""]))
    with open(os.path.join(docs, "results", "faults.json"), "w") as f:
        json.dump({"commit": commit, "machine": mach, "header": header, "scene": SCENE,
                   "fault_start_s": FAULT_START_S, "rows": rows}, f, indent=1)
        f.write("\n")
    plot(rows, os.path.join(out, "runs"), os.path.join(docs, "img", "faults.png"))


if __name__ == "__main__":
    sys.exit(main())
