#!/usr/bin/python3
"""Per-minute table and checks of scripts/realtime/rt_soak.sh.

    scripts/realtime/rt_soak_report.py OUT_DIR MINUTES DEPLOYER_EXIT

Reads OUT_DIR/deployer.log ("soak minute N key value ..." lines of the soak
script), OUT_DIR/rss.txt ("N rss_kB") and OUT_DIR/krc.log (fri_sim_krc's
statistics line). Prints a Markdown table per minute (deltas of the counters)
and the checks listed in rt_soak.sh; exit status 1 when one fails.
"""
import re
import sys

out, minutes, dep_rc = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
rows = {}
with open(out + "/deployer.log", errors="replace") as f:
    for line in f:
        m = re.search(r"soak minute (\d+) (.*)$", line)
        if not m:
            continue
        kv = m.group(2).split()
        d = {}
        for k, v in zip(kv[0::2], kv[1::2]):
            try:
                d[k] = int(v)
            except ValueError:
                d[k] = v
        rows[int(m.group(1))] = d
rss = {}
with open(out + "/rss.txt") as f:
    for line in f:
        a = line.split()
        if len(a) == 2 and a[1] != "nan":
            rss[int(a[0])] = int(a[1])
krc = open(out + "/krc.log", errors="replace").read()
failures = []

keys = ["robot_received", "robot_replies", "robot_lost", "robot_timeouts", "robot_socket_errors",
        "sensor_frames", "sensor_timeouts", "features_frames"]
print("| minute | RSS (kB) | received | replies | lost | KRC silences | socket errors | WTS frames | WTS timeouts "
      "| feature frames | bridge status | WTS status | features status | servo status | phase |")
print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|")
prev = {k: 0 for k in keys}
for n in range(1, minutes + 1):
    r = rows.get(n)
    if r is None:
        failures.append("minute %d: no counters logged (the deployment stopped?)" % n)
        continue
    d = {k: r.get(k, 0) - prev[k] for k in keys}
    prev = {k: r.get(k, 0) for k in keys}
    print("| %d | %s | %d | %d | %d | %d | %d | %d | %d | %d | %s | %s | %s | %s | %s |" % (
        n, rss.get(n, "?"), d["robot_received"], d["robot_replies"], d["robot_lost"], d["robot_timeouts"],
        d["robot_socket_errors"], d["sensor_frames"], d["sensor_timeouts"], d["features_frames"],
        r.get("bridge_status"), r.get("sensor_status"), r.get("features_status"), r.get("servo_status"),
        r.get("phase")))
    edge = n == 1 or n == minutes  # the KRC starts 3 s after the deployer and stops a few s before it
    if d["robot_received"] < 0.9 * 60000:
        failures.append("minute %d: %d KRC packets received (< 90 %% of 60000)" % (n, d["robot_received"]))
    if d["robot_replies"] < d["robot_received"] - 10:
        failures.append("minute %d: %d replies for %d packets" % (n, d["robot_replies"], d["robot_received"]))
    if d["robot_socket_errors"] != 0:
        failures.append("minute %d: %d socket errors" % (n, d["robot_socket_errors"]))
    if d["robot_timeouts"] > (80 if edge else 0):
        failures.append("minute %d: the KRC was silent %d times" % (n, d["robot_timeouts"]))
    if d["sensor_frames"] <= 0:
        failures.append("minute %d: no WTS frame" % n)
if len(rss) >= 2:
    first = rss[min(rss)]
    growth = max(rss.values()) - first
    print("\nresident memory: minute 1 %d kB, max %d kB, growth %d kB" % (first, max(rss.values()), growth))
    if growth >= 1024:
        failures.append("resident memory grew by %d kB (>= 1 MiB)" % growth)
m = re.search(r"fri_sim_krc: .*", krc)
print("\n" + (m.group(0) if m else "fri_sim_krc: no statistics line"))
if not m:
    failures.append("the simulated KRC printed no statistics")
else:
    for k in ["flag_errors", "nonfinite", "mon_echo_errors", "remote_seq_errors"]:
        v = re.search(k + r" (\d+)", m.group(0))
        if v and int(v.group(1)) != 0:
            failures.append("simulated KRC: %s %s" % (k, v.group(1)))
if dep_rc != 0:
    failures.append("the deployer exited with %d (a failed step: see deployer.log)" % dep_rc)
print("\n" + ("rt_soak: all checks passed (%d min)" % minutes if not failures else
              "rt_soak: FAILED:\n  " + "\n  ".join(failures)))
sys.exit(1 if failures else 0)
