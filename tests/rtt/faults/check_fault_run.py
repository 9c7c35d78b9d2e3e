#!/usr/bin/python3
"""ctest rtt_fault_<name>: checks the time series of one fault run of the
simulated deployment (tests/rtt/faults/fault_<name>.ops, the reporter's table,
one row per servo cycle) against what the program says must happen.

usage: check_fault_run.py NAME REPORT.dat FAULT_OPS PROGRAM_YAML

Every run (each check prints ok/FAIL; exit 1 on any FAIL):
  * no NaN/Inf in any command, measured flange pose or feature;
  * every command step within the program's step limits, which bound the
    servo's increment in {s} (safety_supervisor.hpp): the sensor origin's
    translation (the flange pose times controller.sensor_mount) at most
    safety.max_trans_speed * dt, the rotation at most
    safety.max_rot_speed_deg * dt (dt = 10 ms); the reporter keeps 6
    significant digits, so within 3e-6 m and 1e-5 rad of rounding;
  * the slide ran at the step limit before the fault (the fastest speed the
    controller supports: mean >= 90 % of max_trans_speed);
and per fault (its start and duration are read from FAULT_OPS):
  none        the bar's end: explore ends on the point contact (the program's
              rule), then `done` holds the command, the run ends 1 s later
  contact_lost  the bar's end with the shipped end rule only: `contact_lost`
              only there, each cycle searching along +z_s at most
              search_speed * dt (no rotation), at most search_max_distance per
              loss, `done` after 0.5 s of continuous loss, held, the end 1 s later
  stale       `holding` exactly on the cycles whose features are older than
              safety.stale_timeout, the command held, then the slide resumes
  disconnect  the same, the sensor's link_status Disconnected (5) in the
              window and Reconnected (4) at the first frame after it
  nan         the NaN frame's features are `invalid_input`, the servo holds
              for that cycle only, then resumes
  saturated   the saturated frame's features are `saturated`, the servo
              latches `force_ceiling` and retreats along -z_s within the
              step limit; the run ends there (the runner's end rule)
The runs other than saturated must also reach the bar's end as `none` does.
"""
import math
import re
import sys

import yaml
import os

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "scripts", "tools"))
import program_yaml  # noqa: E402  (a program as the servo merges it: tactile_sim program)

name, report, fault_ops, program = sys.argv[1:5]
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


# ---- inputs
ops = open(fault_ops).read()
m_start = re.search(r"Sensor\.fault_start\s*=\s*([0-9.eE+-]+)", ops)
m_dur = re.search(r"Sensor\.fault_duration\s*=\s*([0-9.eE+-]+)", ops)
t0 = float(m_start.group(1))
dur = float(m_dur.group(1))
prog = program_yaml.load(program)
safety = prog["safety"]
v_max = float(safety["max_trans_speed"])
w_max = math.radians(float(safety["max_rot_speed_deg"]))
stale_timeout = float(safety["stale_timeout"])
mount = [float(v) for v in prog["controller"]["sensor_mount"]["xyz"]]
assert all(float(a) == 0.0 for a in prog["controller"]["sensor_mount"]["rpy_deg"]), "mount rotation not handled"
TOL_P, TOL_R = 3e-6, 1e-5  # the reporter's 6 significant digits
search_speed = float(safety["contact_loss"]["search_speed"])
search_max = float(safety["contact_loss"]["search_max_distance"])

lines = [l.split() for l in open(report) if l.strip()]
head = lines[0]
col = {n: i for i, n in enumerate(head)}
rows = [r for r in lines[1:] if len(r) == len(head)]  # the reporter's last line may be cut at stop
check(len(rows) > 100, f"{len(rows)} servo cycles in {report}")


def f(r, key):
    return float(r[col[key]])


def s(r, key):
    return r[col[key]]


P = [f"Servo.pose_command.pose.p.Element{i}" for i in range(3)]
Q = [f"Servo.pose_command.pose.q.Element{i}" for i in range(4)]
FP = [f"Robot.flange_pose.p.Element{i}" for i in range(3)]
FQ = [f"Robot.flange_pose.q.Element{i}" for i in range(4)]
FEAT = ["Features.features." + k for k in ("cop_x", "cop_y", "dzmp_x", "dzmp_y", "alpha_z", "force", "d_z")]


def t(r):
    return f(r, "Servo.pose_command.time_s")


def pos(r, keys=P):
    return [f(r, k) for k in keys]


def quat(r, keys=Q):
    return [f(r, k) for k in keys]


def rot_angle(a, b):
    d = abs(sum(x * y for x, y in zip(a, b))) / (math.sqrt(sum(x * x for x in a)) * math.sqrt(sum(x * x for x in b)))
    return 2.0 * math.acos(min(1.0, d))


def rotate(q, v):
    x, y, z, w = q
    n = math.sqrt(x * x + y * y + z * z + w * w)
    x, y, z, w = x / n, y / n, z / n, w / n
    R = [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
         [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
         [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]
    return [sum(R[i][j] * v[j] for j in range(3)) for i in range(3)]


def sensor_origin(r):
    return [a + b for a, b in zip(pos(r), rotate(quat(r), mount))]


def z_axis(q):
    x, y, z, w = q
    return [2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)]


status = [s(r, "Servo.pose_command.status") for r in rows]
phase = [int(f(r, "Servo.phase.index")) for r in rows]
times = [t(r) for r in rows]

# ---- every run
finite = all(math.isfinite(f(r, k)) for r in rows for k in P + Q + FP + FQ + FEAT)
check(finite, "no NaN/Inf in commands, measured flange poses and features")
max_dp = max_dr = 0.0
over = []
for a, b in zip(rows, rows[1:]):
    if int(f(b, "Servo.pose_command.seq")) != int(f(a, "Servo.pose_command.seq")) + 1:
        continue
    dt = t(b) - t(a)
    dp = math.dist(sensor_origin(a), sensor_origin(b))
    dr = rot_angle(quat(a), quat(b))
    max_dp, max_dr = max(max_dp, dp), max(max_dr, dr)
    if dp > v_max * dt + TOL_P or dr > w_max * dt + TOL_R:
        over.append((t(b), dp, dr))
check(not over, f"every command step of the sensor frame within {v_max * 0.01 * 1e3:.3f} mm / "
      f"{math.degrees(w_max * 0.01):.3f} deg per 10 ms cycle: max {max_dp * 1e3:.4f} mm, {math.degrees(max_dr):.4f} deg" +
      (f"; exceeded at t = {over[0][0]}" if over else ""))
print(f"measured: max command step (sensor frame) {max_dp * 1e3:.4f} mm {math.degrees(max_dr):.4f} deg")

explore = [i for i, r in enumerate(rows) if phase[i] == 0]
check(bool(explore), "the program reached explore")
e0 = times[explore[0]]
slide = [i for i in explore if e0 + 1.0 <= times[i] < min(t0, 100.0)] if name not in ("none", "contact_lost") else \
        [i for i in explore if e0 + 1.0 <= times[i] < e0 + 5.0]
if len(slide) > 10:
    a, b = rows[slide[0]], rows[slide[-1]]
    v = math.dist(pos(a, FP)[:2], pos(b, FP)[:2]) / (t(b) - t(a))
    limited = sum(1 for i in slide if status[i] == "limited") / len(slide)
    print(f"measured: slide speed {v * 1e3:.1f} mm/s over [{t(a):.2f}, {t(b):.2f}] s, {100 * limited:.0f} % of the cycles limited")
    check(v >= 0.9 * v_max, f"sliding at the step limit before the fault: {v * 1e3:.1f} mm/s >= 90 % of {v_max * 1e3:.0f} mm/s")
else:
    check(False, "explore cycles before the fault to measure the slide speed")


def held(i):
    """The command of row i equals the previous one (hold), as written."""
    return all(s(rows[i], k) == s(rows[i - 1], k) for k in P + Q)


def bar_end_reached(on_point=True):
    """The program ends explore at the bar's end: a point contact (or the
    contact lost for 0.5 s), then done holding the command, and the run ends
    1 s after done."""
    done = [i for i, p in enumerate(phase) if p == 1]
    check(bool(done), "the program reached done")
    if not done:
        return
    d = done[0]
    last_explore = rows[d - 1]
    if on_point:
        check(s(last_explore, "Features.features.contact") == "point",
              f"explore ended on a point contact (the bar's end), contact {s(last_explore, 'Features.features.contact')}")
    else:
        run = 0
        while run < d and status[d - 1 - run] == "contact_lost":
            run += 1
        check(run >= 49, f"explore ended after the contact was lost for 0.5 s: {run} contact_lost cycles before done")
    x = f(rows[d], FP[0])
    check(x < 0.43, f"at the bar's end (x = 0.42 m): flange x {x:.4f} m at done (t = {times[d]:.2f} s)")
    check(all(status[i] == "done" for i in done), "status done on every cycle after it")
    check(all(held(i) for i in done[1:]), "done holds the command")
    check(0.95 <= times[-1] - times[d] <= 1.05, f"the run ended 1 s after done ({times[-1] - times[d]:.2f} s)")
    print(f"measured: done at {times[d]:.2f} s, flange x {x:.4f} m, run end {times[-1]:.2f} s")


def hold_window(kind):
    """stale / disconnect: holding exactly while the features are older than stale_timeout."""
    win = [i for i in range(len(rows)) if t0 <= times[i] < t0 + dur]
    hold = [i for i in range(len(rows)) if status[i] == "holding"]
    check(bool(hold), f"the servo reports holding ({len(hold)} cycles)")
    if not hold:
        return
    wrong = [times[i] for i in win if (status[i] == "holding") !=
             (times[i] - f(rows[i], "Features.features.time_s") > stale_timeout + 1e-9)]
    check(not wrong, "holding exactly on the window's cycles with features older than stale_timeout "
          f"({stale_timeout} s)" + (f"; wrong at {wrong[:3]}" if wrong else ""))
    check(all(t0 <= times[i] < t0 + dur for i in hold), f"holding only within the fault window [{t0}, {t0 + dur}) s")
    age = times[hold[0]] - f(rows[hold[0]], "Features.features.time_s")
    check(stale_timeout < age <= stale_timeout + 0.01, f"the first holding cycle comes when the features' age passes "
          f"stale_timeout: {age * 1e3:.1f} ms")
    check(all(held(i) for i in hold), "the command is held (unchanged) on every holding cycle")
    moved = max(math.dist(pos(rows[i], FP), pos(rows[hold[0]], FP)) for i in hold)
    print(f"measured: holding {times[hold[0]]:.2f}-{times[hold[-1]]:.2f} s ({len(hold)} cycles), flange moved "
          f"{moved * 1e3:.3f} mm while holding")
    after = hold[-1] + 1
    check(after < len(rows) and status[after] in ("ok", "limited") and phase[after] == 0,
          f"the slide resumes at the first frame after the window (t = {times[min(after, len(rows) - 1)]:.2f} s, "
          f"{status[min(after, len(rows) - 1)]})")
    if kind == "disconnect":
        link = [int(f(r, "Sensor.link_status")) for r in rows]
        check(all(link[i] == 5 for i in win), "link_status Disconnected (5) on every cycle of the window")
        rec = [i for i in range(len(rows)) if link[i] == 4]
        check(bool(rec) and abs(times[rec[0]] - (t0 + dur)) <= 0.01,
              "link_status Reconnected (4) at the first frame after the window" +
              (f" (t = {times[rec[0]]:.2f} s)" if rec else ""))
        check(all(link[i] == 0 for i in range(len(rows)) if times[i] < t0 - 0.01 or times[i] > t0 + dur + 0.02),
              "link_status NewFrame (0) outside the fault")


def one_frame(kind):
    fseq = [int(f(r, "Sensor.fault_seq")) for r in rows]
    k = [i for i, r in enumerate(rows) if fseq[i] >= 0 and int(f(r, "Features.features.seq")) == fseq[i]]
    check(bool(k), "the servo read the faulty frame's features (Features.features.seq == Sensor.fault_seq)")
    if not k:
        return
    i = k[0]
    fs = s(rows[i], "Features.features.status")
    print(f"measured: faulty frame seq {fseq[i]} read at t = {times[i]:.2f} s: features {fs}, servo {status[i]}")
    if kind == "nan":
        check(fs == "invalid_input", f"the NaN frame's features are invalid_input ({fs})")
        check(status[i] == "holding", f"the servo holds on it ({status[i]})")
        check(held(i), "the command is held on that cycle")
        hold = [j for j in range(len(rows)) if status[j] == "holding"]
        check(hold == [i], f"holding on that cycle only ({len(hold)} cycles)")
        check(status[i + 1] in ("ok", "limited") and phase[i + 1] == 0, f"the slide resumes at the next cycle ({status[i + 1]})")
    else:
        check(fs == "saturated", f"the saturated frame's features are saturated ({fs})")
        check(status[i] == "force_ceiling", f"the servo latches force_ceiling ({status[i]})")
        check(all(st != "force_ceiling" for st in status[:i]), "no force_ceiling before the saturated frame")
        check(i == len(rows) - 1, "the run ends on that cycle (the end rule at a force ceiling)")
        dp = [b - a for a, b in zip(pos(rows[i - 1]), pos(rows[i]))]
        z = z_axis(quat(rows[i - 1]))
        along = sum(x * y for x, y in zip(dp, z))
        n = math.dist(pos(rows[i - 1]), pos(rows[i]))
        check(along < 0.0 and abs(abs(along) - n) < 1e-9, f"the command retreats along -z_s: {along * 1e3:.4f} mm "
              f"(|step| {n * 1e3:.4f} mm)")
        check(rot_angle(quat(rows[i - 1]), quat(rows[i])) < 1e-9, "no rotation while retreating")


def contact_lost_at_end():
    lost = [i for i in range(len(rows)) if status[i] == "contact_lost"]
    check(bool(lost), f"the servo reports contact_lost ({len(lost)} cycles)")
    if not lost:
        return
    xs = [f(rows[i], FP[0]) for i in lost]
    check(max(xs) < 0.43, f"contact_lost only at the bar's end (x = 0.42 m): flange x in [{min(xs):.4f}, {max(xs):.4f}] m "
          f"from t = {times[lost[0]]:.2f} s")
    bad, episode, worst = [], 0.0, 0.0
    for i in lost:
        if status[i - 1] != "contact_lost":
            episode = 0.0
        dp = [b - a for a, b in zip(sensor_origin(rows[i - 1]), sensor_origin(rows[i]))]
        z = z_axis(quat(rows[i - 1]))
        along = sum(x * y for x, y in zip(dp, z))
        n = math.sqrt(sum(x * x for x in dp))
        episode += along
        worst = max(worst, episode)
        if (along < -TOL_P or n > search_speed * 0.01 + TOL_P or abs(n - abs(along)) > TOL_P or
                rot_angle(quat(rows[i - 1]), quat(rows[i])) > TOL_R):
            bad.append(times[i])
    check(not bad, f"each contact_lost cycle searches along +z_s by at most search_speed x dt = "
          f"{search_speed * 0.01 * 1e3:.3f} mm, no rotation" + (f"; not at {bad[:3]}" if bad else ""))
    check(worst <= search_max + 10 * TOL_P, f"at most search_max_distance ({search_max * 1e3:.1f} mm) per loss: "
          f"{worst * 1e3:.3f} mm")
    print(f"measured: contact_lost {len(lost)} cycles from {times[lost[0]]:.2f} s, search at most {worst * 1e3:.3f} mm per loss")


if name == "contact_lost":
    check(not any(st in ("holding", "force_ceiling", "invalid_input") for st in status),
          "no holding, force_ceiling or invalid_input without a sensor fault")
    contact_lost_at_end()
    bar_end_reached(on_point=False)
elif name == "none":
    check(not any(st in ("holding", "contact_lost", "force_ceiling", "invalid_input") for st in status),
          "no holding, contact_lost, force_ceiling or invalid_input without a fault")
    bar_end_reached()
elif name in ("stale", "disconnect"):
    hold_window(name)
    bar_end_reached()
elif name == "nan":
    one_frame("nan")
    bar_end_reached()
elif name == "saturated":
    one_frame("saturated")
else:
    sys.exit(f"check_fault_run.py: unknown fault {name}")

print(f"{len(failures)} failed")
sys.exit(1 if failures else 0)
