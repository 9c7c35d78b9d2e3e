#!/usr/bin/python3
"""ctest ros_robot_streams, the ROS side: subscribes to the topics of
deployments/ros_streams.ops while the robot deployment's ROS variant
(deployments/robot_ros.ops, TACTILE_EXPERIMENT=edge_exploration) runs against the simulated KRC
(fri_sim_krc, FRI over UDP) and the simulated WTS0614 (wts_sim on a PTY).

usage: check_robot_topics.py READY_FILE WINDOW_S

Waits (up to 120 s) until every topic has carried a message, touches
READY_FILE, then waits for a count of messages on every topic: WINDOW_S s
worth at a quarter of its nominal rate (KRC 1 kHz: flange_pose, wrench; servo
100 Hz: pose_command, phase; the simulated WTS's frames: image, features),
for at most 15 times WINDOW_S. Then checks (each printed; exit 1 when one
fails):
  - every topic arrives and carries its count: a topic that stops or a wrong
    connection is what it catches. A count, not a rate in a wall-clock window:
    on a loaded machine the kernel's tty worker can hold the sensor's bytes
    for hundreds of milliseconds (docs/suite_under_load.md), which slows the
    image and features topics without anything being wrong in the
    deployment; the rates are printed;
  - the image is 6 x 14 32FC1 in wts0614; features in wts0614 with a usable
    status (< 10); the flange pose in lwr_base with a unit quaternion; the
    wrench in lwr_flange;
  - TF resolves lwr_base -> wts0614 (flange pose and sensor mount);
  - /tactile/switch_phase, as soon as the topics arrive, refuses an unknown
    phase and accepts the phase the program is in; at the end it switches to
    `done` (then seen on /tactile/phase), unless the program got there first.
"""
import math
import sys
import threading
import time

import rospy
import tf2_ros
from geometry_msgs.msg import PoseStamped, WrenchStamped
from sensor_msgs.msg import Image
from tactile_msgs.msg import ContactFeatures, Phase
from tactile_msgs.srv import SwitchPhase

failures = []


def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what, flush=True)
    if not ok:
        failures.append(what)


def main():
    ready_file, window = sys.argv[1], float(sys.argv[2])
    # Nominal rates (Hz); the WTS's is the simulated device's frame rate, at least 100 Hz.
    nominal = {"flange_pose": 1000.0, "wrench": 1000.0, "pose_command": 100.0, "phase": 100.0,
               "image": 100.0, "features": 100.0}
    types = {"image": Image, "features": ContactFeatures, "phase": Phase, "pose_command": PoseStamped,
             "flange_pose": PoseStamped, "wrench": WrenchStamped}
    rospy.init_node("tactile_check_robot_topics", anonymous=True, disable_signals=True)
    lock = threading.Lock()
    counting = [False]
    counts = {k: 0 for k in types}
    last = {}

    def keep(key):
        def cb(msg):
            with lock:
                last[key] = msg
                if counting[0]:
                    counts[key] += 1
        return cb

    subs = [rospy.Subscriber("/tactile/" + k, t, keep(k), queue_size=5000) for k, t in types.items()]
    tf_buffer = tf2_ros.Buffer()
    tf2_ros.TransformListener(tf_buffer)
    t0 = time.monotonic()
    while time.monotonic() - t0 < 120.0:
        with lock:
            if len(last) == len(types):
                break
        time.sleep(0.1)
    with lock:
        missing = sorted(set(types) - set(last))
    check(not missing, "every topic arrives (missing: %s) after %.1f s" % (missing, time.monotonic() - t0))
    open(ready_file, "w").close()
    if missing:
        return 1
    # The phase service while the program surely runs: an unknown phase refused, the
    # phase it is in accepted (an event, before the count below lets the program end).
    call = None
    try:
        rospy.wait_for_service("/tactile/switch_phase", timeout=10)
        call = rospy.ServiceProxy("/tactile/switch_phase", SwitchPhase)
        r = call("no_such_phase")
        check(not r.ok, "switch_phase('no_such_phase') refused: ok=%s '%s'" % (r.ok, r.message))
        with lock:
            current = last["phase"].name
        r = call(current)
        check(r.ok, "switch_phase('%s') (the phase it is in) accepted: ok=%s '%s'" % (current, r.ok, r.message))
    except Exception as e:  # noqa: BLE001
        check(False, "phase service (%s)" % e)
    want = {k: int(math.ceil(0.25 * nominal[k] * window)) for k in types}
    with lock:
        counting[0] = True
    start = time.monotonic()
    while time.monotonic() - start < 15.0 * window:
        with lock:
            if all(counts[k] >= want[k] for k in types):
                break
        time.sleep(0.05)
    with lock:
        counting[0] = False
        elapsed = time.monotonic() - start
        got = dict(counts)
        seen = dict(last)
    for k, n in got.items():
        check(n >= want[k], "/tactile/%s: %d messages (count %d) in %.2f s (%.0f Hz)"
              % (k, n, want[k], elapsed, n / elapsed))
    im = seen["image"]
    check(im.height == 6 and im.width == 14 and im.encoding == "32FC1" and im.header.frame_id == "wts0614"
          and len(im.data) == 6 * 14 * 4, "image 6 x 14 32FC1 in wts0614 (%d x %d %s %s)"
          % (im.height, im.width, im.encoding, im.header.frame_id))
    f = seen["features"]
    check(f.header.frame_id == "wts0614" and f.status < 10, "features in wts0614, usable status (%d)" % f.status)
    p = seen["flange_pose"]
    q = p.pose.orientation
    norm = math.sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w)
    check(p.header.frame_id == "lwr_base" and abs(norm - 1.0) < 1e-6,
          "flange pose in lwr_base, unit quaternion (|q| = %.9f)" % norm)
    w = seen["wrench"]
    check(w.header.frame_id == "lwr_flange", "wrench in lwr_flange (%s)" % w.header.frame_id)
    try:
        tf_buffer.lookup_transform("lwr_base", "wts0614", rospy.Time(0), rospy.Duration(2.0))
        check(True, "TF lwr_base -> wts0614 resolves")
    except Exception as e:  # noqa: BLE001 (any tf2 failure is the finding)
        check(False, "TF lwr_base -> wts0614 resolves (%s)" % e)
    # The end: switched to `done`, unless the program already got there by itself.
    with lock:
        ended = last["phase"].name == "done"
    if ended:
        print("ok    the program reached 'done' by itself; no switch needed", flush=True)
    elif call is not None:
        try:
            r = call("done")
            check(r.ok, "switch_phase('done') accepted: ok=%s '%s'" % (r.ok, r.message))
        except Exception as e:  # noqa: BLE001
            check(False, "phase service (%s)" % e)
    t1 = time.monotonic()
    name = ""
    while time.monotonic() - t1 < 10.0:
        with lock:
            name = last["phase"].name
        if name == "done":
            break
        time.sleep(0.05)
    check(name == "done", "/tactile/phase says 'done' after the switch ('%s')" % name)
    for s in subs:
        s.unregister()
    print("check_robot_topics: %s" % ("passed" if not failures else "%d check(s) failed" % len(failures)))
    return 0 if not failures else 1


if __name__ == "__main__":
    sys.exit(main())
