#!/usr/bin/python3
"""ctest krc_config_matches_fri_yaml: krc/check_krc_config.py passes on the
shipped KRC template (krc/TactileServo.src, krc/dlrrc.ini) and fri.yaml, and
fails, naming the disagreement, on copies with one value changed on one side:

  friOpen(2)                          -> "cycle"
  fri.cycle_time_s 0.002              -> "cycle"
  $STIFFNESS.STRATEGY = 30 (joint impedance) before friStart -> "control strategy"
  a strategy-20 line moved after friStart (the KRC would start in position control)
                                      -> "control strategy"
  FRISOCK=49939,0                     -> "port"
  fri.udp.port 49939                  -> "port"
  CPSTIFFNESS Z 1000                  -> "cart_stiffness"
  fri.cart_damping[0] 0.5             -> "cart_damping"
  friOpen(2), strategy 30 in a comment -> still agrees (exit 0)
  FRIHOST=rt-pc (not an address)      -> "FRIHOST"
  fri.yaml without cycle_time_s       -> "no fri.cycle_time_s"
  TS_PAD_LOAD M 0.3 (.dat)            -> "pad mass"
  pad.pad_com_m z 0.03 (sensor file)  -> "pad centre of mass"
  no $LOAD = TS_PAD_LOAD              -> "no $LOAD"
  no $STIFFNESS.MAXFORCE line         -> "MAXFORCE is not written"
  $STIFFNESS.FRAMETYPE = #TOOL        -> "task frame"
  fri.wrench_frame tool               -> "task frame"
  FRAMETYPE #TOOL and fri.wrench_frame tool -> agrees (exit 0)
  fri.wrench_frame flange             -> "fri.wrench_frame"
  $TOOL = TOOL_DATA[1]                -> "frames"
  MAXFORCE Z 4.0 (below the 5 N ceiling) -> "force cap"
  CPMAXDELTA X 5.0 (inside 10 mm of spring) -> "deviation stop"
  TS_START in the order A1, A2, E1, A3 -> "start pose order"
  TS_START all zeros                  -> "start pose:"
  no PTP $AXIS_ACT_MES at the end     -> "end of run"
  TS_REQ_STOP = 98                    -> "KRL exchange"
  TS_ST_STOPPING missing              -> "KRL exchange"

usage: test_krc_config.py SOURCE_DIR WORK_DIR
"""
import os
import re
import shutil
import subprocess
import sys

src_dir, work = sys.argv[1], sys.argv[2]
sensor = os.path.join(src_dir, "params", "sensors", "wts0614.yaml")
checker = os.path.join(src_dir, "krc", "check_krc_config.py")
krc_dir = os.path.join(src_dir, "krc")
fri_yaml = os.path.join(src_dir, "params", "sensors", "fri.yaml")
protocol = os.path.join(src_dir, "core", "fri", "include", "tactile_fri", "protocol.hpp")
failures = []


def run(krc, fri, sensor_file=sensor):
    p = subprocess.run(["/usr/bin/python3", checker, "--krc", krc, "--fri-yaml", fri, "--protocol", protocol,
                        "--sensor-params", sensor_file],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    return p.returncode, p.stdout


def copy_case(name):
    d = os.path.join(work, name)
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    for f in ("TactileServo.src", "TactileServo.dat", "dlrrc.ini"):
        shutil.copy(os.path.join(krc_dir, f), d)
    shutil.copy(fri_yaml, os.path.join(d, "fri.yaml"))
    shutil.copy(sensor, os.path.join(d, "sensor.yaml"))
    return d


def edit(path, old, new, count=1):
    text = open(path, encoding="latin-1").read()
    n = len(re.findall(old, text))
    if n < count:
        failures.append(f"mutation setup: '{old}' found {n} times in {path}")
    open(path, "w", encoding="latin-1").write(re.sub(old, new, text, count=count))


rc, out = run(krc_dir, fri_yaml)
print(out)
if rc != 0:
    failures.append(f"the shipped files disagree (exit {rc})")

# (name, file, pattern, replacement, expected text on a MISMATCH line)
cases = [
    ("friopen_2ms", "TactileServo.src", r"(?m)^TS_RET = friOpen\(1\)", "TS_RET = friOpen(2)", "cycle"),
    ("yaml_cycle_2ms", "fri.yaml", r"cycle_time_s: 0\.001", "cycle_time_s: 0.002", "cycle"),
    ("joint_impedance", "TactileServo.src", r"(?m)^\$STIFFNESS\.STRATEGY = 20", "$STIFFNESS.STRATEGY = 30",
     "control strategy"),
    ("strategy_after_fristart", "TactileServo.src",
     r"\$STIFFNESS\.STRATEGY = 20\n\$STIFFNESS\.COMMIT = TRUE\n", "", "control strategy"),
    ("frisock_49939", "dlrrc.ini", r"FRISOCK=49938", "FRISOCK=49939", "port"),
    ("yaml_port_49939", "fri.yaml", r"port: 49938", "port: 49939", "port"),
    ("stiffness_z", "TactileServo.src", r"Z 2000\.0", "Z 1000.0", "cart_stiffness"),
    ("yaml_damping", "fri.yaml", r"cart_damping: \[0\.7", "cart_damping: [0.5", "cart_damping"),
    # a comment is not the program: friOpen(2) and strategy 30 in comments change nothing
    ("comment_only", "TactileServo.src", r"(?m)^; (.*)friOpen\(1\)", r"; \1friOpen(2) $STIFFNESS.STRATEGY = 30", None),
    ("frihost_name", "dlrrc.ini", r"FRIHOST=[0-9.]+", "FRIHOST=rt-pc", "FRIHOST"),
    ("yaml_no_cycle", "fri.yaml", r"\n *cycle_time_s:[^\n]*", "", "no fri.cycle_time_s"),
    ("pad_mass", "TactileServo.dat", r"\{M 0\.2,", "{M 0.3,", "pad mass"),
    ("sensor_com", "sensor.yaml", r"pad_com_m: \[0\.0, 0\.0, 0\.02\]", "pad_com_m: [0.0, 0.0, 0.03]",
     "pad centre of mass"),
    ("no_load", "TactileServo.src", r"(?m)^\$LOAD = TS_PAD_LOAD\n", "", "no $LOAD"),
    ("no_maxforce", "TactileServo.src", r"(?m)^\$STIFFNESS\.MAXFORCE = [^\n]*\n", "", "MAXFORCE is not written"),
    ("frametype_tool", "TactileServo.src", r"(?m)^\$STIFFNESS\.FRAMETYPE = #BASE", "$STIFFNESS.FRAMETYPE = #TOOL",
     "task frame"),
    ("yaml_wrench_tool", "fri.yaml", r"wrench_frame: base", "wrench_frame: tool", "task frame"),
    ("both_tool", "TactileServo.src", r"(?m)^\$STIFFNESS\.FRAMETYPE = #BASE", "$STIFFNESS.FRAMETYPE = #TOOL", None),
    ("yaml_wrench_flange", "fri.yaml", r"wrench_frame: base", "wrench_frame: flange", "fri.wrench_frame"),
    ("tool_data", "TactileServo.src", r"(?m)^\$TOOL = \$NULLFRAME", "$TOOL = TOOL_DATA[1]", "frames"),
    ("maxforce_below_ceiling", "TactileServo.src", r"MAXFORCE = \{X 20\.0, Y 20\.0, Z 20\.0",
     "MAXFORCE = {X 20.0, Y 20.0, Z 4.0", "force cap"),
    ("cpmaxdelta_tight", "TactileServo.src", r"CPMAXDELTA = \{X 15\.0", "CPMAXDELTA = {X 5.0", "deviation stop"),
    ("start_order", "TactileServo.dat", r"TS_START = \{[^}]*\}",
     "TS_START = {A1 0.0, A2 56.6, E1 0.0, A3 41.3, A4 0.0, A5 82.1, A6 0.0}", "start pose order"),
    ("start_zeros", "TactileServo.dat", r"TS_START = \{[^}]*\}",
     "TS_START = {A1 0.0, A2 0.0, A3 0.0, A4 0.0, A5 0.0, A6 0.0, E1 0.0}", "start pose:"),
    ("no_end_ptp", "TactileServo.src", r"(?m)^BAS \(#VEL_PTP, TS_START_VEL \)\nPTP \$AXIS_ACT_MES\nIF \$FriState",
     "IF $FriState", "end of run"),
    ("req_stop_98", "TactileServo.dat", r"TS_REQ_STOP = 99", "TS_REQ_STOP = 98", "KRL exchange"),
    ("no_stopping_code", "TactileServo.dat", r"(?m)^DECL INT TS_ST_STOPPING = 25\n", "", "KRL exchange"),
]
for name, f, old, new, expect in cases:
    d = copy_case(name)
    path = os.path.join(d, f)
    if name == "strategy_after_fristart":
        # the strategy-20 lines moved to just after friStart: the KRC would
        # enter command mode in the strategy before (10, position control)
        text = open(path, encoding="latin-1").read()
        block = "$STIFFNESS.STRATEGY = 20\n$STIFFNESS.COMMIT = TRUE\n"
        if block not in text:
            failures.append(f"mutation setup: no strategy block in {path}")
        text = text.replace(block, "", 1)
        text = re.sub(r"(TS_RET = friStart\(1\.0\)\n)", r"\1" + block.replace("$", r"\$"), text, count=1)
        open(path, "w", encoding="latin-1").write(text)
    elif name == "both_tool":
        edit(path, old, new)  # the KRC's frame type and fri.yaml's frame changed together
        edit(os.path.join(d, "fri.yaml"), r"wrench_frame: base", "wrench_frame: tool")
    else:
        edit(path, old, new)
    rc, out = run(d, os.path.join(d, "fri.yaml"), os.path.join(d, "sensor.yaml"))
    bad = [l for l in out.splitlines() if l.startswith("MISMATCH")]
    ok = (rc == 0 and not bad) if expect is None else (rc == 1 and any(expect in l for l in bad))
    print(f"{'ok  ' if ok else 'FAIL'} {name}: exit {rc}, {bad[:2]}")
    if not ok:
        want = "exit 0" if expect is None else f"exit 1 with a MISMATCH line containing '{expect}'"
        failures.append(f"{name}: expected {want}, got exit {rc}:\n{out}")

for f in failures:
    print("FAIL:", f)
print(f"test_krc_config: {len(cases) + 1} cases, {len(failures)} failures")
sys.exit(1 if failures else 0)
