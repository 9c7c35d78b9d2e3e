#!/usr/bin/python3
"""ctest ros_sim_streams, the ROS side: subscribes to the topics of
deployments/ros_streams.ops while the simulated edge exploration runs
(tests/ros/ops/edge_exploration_ros.ops), calls the phase service, looks up
TF, and, once the deployer has ended (DONE_FILE exists), compares the topics
with the deployment's own ports as its reporter logged them (REPORT: OCL
FileReporting of Servo.phase, Servo.pose_command, Robot.flange_pose,
Features.features).

usage: check_topics.py REPORT DONE_FILE SCENE_YAML PROGRAM_YAML

Checks (each printed; exit 1 when one fails):
  - every topic arrives, at its configured rate within 10 % (the scene's
    rates: image and features at wts, phase and pose_command at servo,
    flange_pose and wrench at sim), counted over the messages' stamps;
  - the image is 6 x 14 32FC1 in the sensor frame;
  - features: force, CoP and contact of every reported sample (matched by seq)
    equal the message's (the report's 6 significant digits);
  - phase: every reported (index, entry time) has a message, with the
    program's name of that index;
  - TF resolves lwr_base -> contact while the features report a contact;
  - /tactile/joint_states (at the adapter's joint_state_period, 100 Hz) names
    lwr_a1_joint..lwr_a7_joint, and the URDF
    (ros/tactile_ros/urdf/lwr4plus_wts.urdf, tests/ros/urdf_fk.py) puts
    lwr_flange where /tactile/flange_pose of the same stamp says the simulated
    arm is, within FK_POS_TOL / FK_ROT_TOL; /tactile/robot_state says
    commandable in command mode for most of the run;
  - /tactile/switch_phase refuses an unknown phase and switches to `done`
    (the phase topic then says so).
"""
import math
import os
import sys
import threading
import time

import numpy as np
import rospy
import tf2_ros
import yaml
from geometry_msgs.msg import PoseStamped, WrenchStamped
from sensor_msgs.msg import Image, JointState
from tactile_msgs.msg import ContactFeatures, Phase, RobotState
from tactile_msgs.srv import SwitchPhase

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import urdf_fk  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "tools"))
import program_yaml  # noqa: E402  (a program as the servo merges it: tactile_sim program)

URDF = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "ros", "tactile_ros", "urdf",
                    "lwr4plus_wts.urdf")
# The simulated arm's flange pose is its forward kinematics of the joints it
# reports (tactile::sim::LwrArm), which the URDF reproduces to ~1e-15 (ctest
# urdf_fk); the tolerances of that test.
# The phase service is called (and the run ends) once this many features
# messages in contact have arrived: ctest ros_bag_replay needs more than 50
# contact frames in the bag, on a fast machine and under a sanitizer alike.
MIN_CONTACT_FRAMES = 120
FK_POS_TOL = 1e-6  # m
FK_ROT_TOL = 1e-6  # rad
JOINT_STATE_RATE = 100.0  # Hz: RosAdapter.joint_state_period 0.01 s
JOINT_NAMES = ["lwr_a%d_joint" % k for k in range(1, 8)]

failures = []


def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what, flush=True)
    if not ok:
        failures.append(what)


def read_report(path):
    with open(path) as f:
        lines = [l.split() for l in f if l.strip()]
    head = lines[0]
    if head and head[0] == "#":
        head = head[1:]
    return head, [r for r in lines[1:] if len(r) == len(head)]


def close(a, b):
    return abs(a - b) <= 2e-5 * max(abs(a), abs(b)) + 1e-9


def main():
    report, done_file, scene_file, program_file = sys.argv[1:5]
    rates = yaml.safe_load(open(scene_file))["rates"]
    program = program_yaml.load(program_file)
    names = [p["name"] for p in program["phases"]]
    expected = {"image": rates["wts"], "features": rates["wts"], "phase": rates["servo"],
                "pose_command": rates["servo"], "flange_pose": rates["sim"], "wrench": rates["sim"],
                "joint_states": JOINT_STATE_RATE, "robot_state": JOINT_STATE_RATE}

    rospy.init_node("tactile_check_topics", anonymous=True, disable_signals=True)
    lock = threading.Lock()
    got = {k: [] for k in expected}

    def keep(key):
        def cb(msg):
            with lock:
                got[key].append((time.monotonic(), msg))
        return cb

    types = {"image": Image, "features": ContactFeatures, "phase": Phase, "pose_command": PoseStamped,
             "flange_pose": PoseStamped, "wrench": WrenchStamped, "joint_states": JointState,
             "robot_state": RobotState}
    subs = [rospy.Subscriber("/tactile/" + k, types[k], keep(k), queue_size=5000) for k in expected]
    tf_buffer = tf2_ros.Buffer(cache_time=rospy.Duration(60))
    tf2_ros.TransformListener(tf_buffer)

    # Wait for the deployment, then watch it; the phase service once the servo is in contact.
    t_start = time.monotonic()
    tf_ok = tf_tries = 0
    switched = None
    service_checked = False
    while not os.path.exists(done_file) and time.monotonic() - t_start < 200:
        time.sleep(0.1)
        with lock:
            feats = [m for _, m in got["features"][-1:]]
            n_phase = len(got["phase"])
            n_contact = sum(1 for _, m in got["features"] if m.contact != 0)
        if feats and feats[0].contact != 0 and feats[0].status < 10:
            tf_tries += 1
            try:
                tf_buffer.lookup_transform("lwr_base", "contact", rospy.Time(0), rospy.Duration(0.05))
                tf_ok += 1
            except (tf2_ros.LookupException, tf2_ros.ConnectivityException, tf2_ros.ExtrapolationException):
                pass
        if not service_checked and n_phase > 0 and tf_ok >= 5 and n_contact >= MIN_CONTACT_FRAMES:
            service_checked = True
            rospy.wait_for_service("/tactile/switch_phase", timeout=5)
            call = rospy.ServiceProxy("/tactile/switch_phase", SwitchPhase)
            r = call("no_such_phase")
            check(not r.ok, "switch_phase('no_such_phase') refused: ok=%s '%s'" % (r.ok, r.message))
            r = call("done")
            check(r.ok, "switch_phase('done') accepted: ok=%s '%s'" % (r.ok, r.message))
            switched = time.monotonic()
    check(os.path.exists(done_file), "the deployment ended within 200 s")
    time.sleep(1.0)
    for s in subs:
        s.unregister()

    # Rates over the stamps (the deployment's time base).
    for k, rate in expected.items():
        msgs = [m for _, m in got[k]]
        n = len(msgs)
        if n < 3:
            check(False, "/tactile/%s: %d messages" % (k, n))
            continue
        span = (msgs[-1].header.stamp - msgs[0].header.stamp).to_sec()
        wall = got[k][-1][0] - got[k][0][0]
        r = (n - 1) / span if span > 0 else float("nan")
        check(abs(r - rate) <= 0.1 * rate,
              "/tactile/%s: %d messages, %.1f Hz over the stamps (configured %g Hz; %.1f Hz wall)" %
              (k, n, r, rate, (n - 1) / wall if wall > 0 else float("nan")))

    imgs = [m for _, m in got["image"]]
    if imgs:
        m = imgs[-1]
        check(m.height == 6 and m.width == 14 and m.encoding == "32FC1" and m.step == 56 and len(m.data) == 336
              and m.header.frame_id == "wts0614",
              "image %dx%d %s step %d, %d bytes, frame %s" % (m.height, m.width, m.encoding, m.step, len(m.data),
                                                               m.header.frame_id))

    # Content against the report.
    head, rows = read_report(report)
    col = {h: i for i, h in enumerate(head)}
    ft, ph = "Features.features.", "Servo.phase."
    by_seq = {m.seq: m for _, m in got["features"]}
    matched = mismatched = 0
    seqs = set()
    contact_names = {"none": 0, "point": 1, "edge": 2, "multiple": 3}  # the typekit's enum names
    for r in rows:
        if float(r[col[ft + "time_s"]]) <= 0:
            continue
        seq = int(float(r[col[ft + "seq"]]))
        if seq in seqs:
            continue
        seqs.add(seq)
        m = by_seq.get(seq)
        if m is None:
            continue
        matched += 1
        c = r[col[ft + "contact"]]
        c = contact_names.get(c.lower(), int(c) if c.lstrip("-").isdigit() else -1)
        if not (close(m.force, float(r[col[ft + "force"]])) and close(m.cop_x, float(r[col[ft + "cop_x"]]))
                and close(m.cop_y, float(r[col[ft + "cop_y"]])) and m.contact == c):
            mismatched += 1
            if mismatched <= 3:
                print("      seq %d: topic force %.9g cop (%.9g, %.9g) contact %d; report %s %s %s %s" %
                      (seq, m.force, m.cop_x, m.cop_y, m.contact, r[col[ft + "force"]], r[col[ft + "cop_x"]],
                       r[col[ft + "cop_y"]], r[col[ft + "contact"]]))
    in_contact = sum(1 for _, m in got["features"] if m.contact != 0 and m.force > 0)
    check(len(seqs) > 0 and matched >= 0.9 * len(seqs) and mismatched == 0 and in_contact > 0,
          "features: %d of %d reported samples found by seq, %d differ in force/CoP/contact; %d messages in contact"
          % (matched, len(seqs), mismatched, in_contact))

    phase_msgs = [m for _, m in got["phase"]]
    entries = {(m.index, m.t_enter) for m in phase_msgs}
    reported = set()
    for r in rows:
        if float(r[col[ph + "time_s"]]) <= 0:
            continue
        reported.add((int(float(r[col[ph + "index"]])), float(r[col[ph + "t_enter_s"]])))
    missing = [e for e in reported if not any(i == e[0] and close(t, e[1]) for i, t in entries)]
    wrong_names = [m for m in phase_msgs if not (0 <= m.index < len(names) and names[m.index] == m.name)]
    check(len(reported) >= 2 and not missing and not wrong_names,
          "phase: %d reported (index, t_enter) pairs, %d without a message; %d messages with a name not the program's"
          % (len(reported), len(missing), len(wrong_names)))
    seen = []
    for m in phase_msgs:
        if not seen or seen[-1] != m.name:
            seen.append(m.name)
    print("      phases on /tactile/phase: " + " -> ".join(seen))
    # The joint states through the URDF against the arm's own flange pose.
    model = urdf_fk.Urdf(URDF)
    poses = {m.header.stamp: m.pose for _, m in got["flange_pose"]}
    joints = [m for _, m in got["joint_states"]]
    names_ok = all(list(m.name) == JOINT_NAMES and len(m.position) == 7 for m in joints)
    matched, worst_p, worst_r = 0, 0.0, 0.0
    for m in joints if names_ok else []:
        p = poses.get(m.header.stamp)
        if p is None:
            continue
        matched += 1
        t = model.fk("lwr_flange", dict(zip(m.name, m.position)))
        x, y, z, w = p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w
        r = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                      [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                      [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
        worst_p = max(worst_p, float(np.linalg.norm(t[:3, 3] - [p.position.x, p.position.y, p.position.z])))
        worst_r = max(worst_r, urdf_fk.rotation_angle(t[:3, :3].T @ r))
    check(names_ok and len(joints) > 0 and matched >= 0.9 * len(joints) and worst_p <= FK_POS_TOL
          and worst_r <= FK_ROT_TOL,
          "joint_states: names %s; %d of %d matched a flange pose by stamp; URDF FK of the joints vs the flange pose: "
          "largest %.2g m, %.2g rad" % ("lwr_a1_joint..lwr_a7_joint" if names_ok else "WRONG", matched, len(joints),
                                        worst_p, worst_r))
    krc = [m for _, m in got["robot_state"]]
    commanding = sum(1 for m in krc if m.commandable and m.mode == RobotState.MODE_COMMAND and m.mode_name == "command")
    check(len(krc) > 0 and commanding >= 0.5 * len(krc),
          "robot_state: %d of %d messages commandable in command mode" % (commanding, len(krc)))
    check(tf_ok > 0, "TF lwr_base -> contact resolved %d of %d times in contact" % (tf_ok, tf_tries))
    check(switched is not None and seen and seen[-1] == "done",
          "after the service call the phase topic says 'done' (last phase %s)" % (seen[-1] if seen else "none"))
    print("check_topics: %d failed" % len(failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
