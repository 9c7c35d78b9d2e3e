#!/usr/bin/python3
"""The bag of ctest ros_bag_replay: /tactile/image and /tactile/features,
recorded as rosbag's recorder would (receive time) but without its fixed
100-message subscriber queue, which drops messages when the recorder is held
off the CPU for 0.7 s of frames: every message received is written. Runs
until SIGINT, then writes the bag.

usage: record_bag.py BAG   (the node's name: __name:=... as for any ROS node)
"""
import sys
import threading

import rosbag
import rospy
from sensor_msgs.msg import Image
from tactile_msgs.msg import ContactFeatures

QUEUE = 100000  # no drop: the run is about 3000 frames


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    rospy.init_node("tactile_test_bag", disable_signals=False)
    got, lock = [], threading.Lock()

    def keep(topic):
        def cb(msg):
            t = rospy.Time.now()
            with lock:
                got.append((topic, msg, t))
        return cb

    subs = [rospy.Subscriber(t, c, keep(t), queue_size=QUEUE)
            for t, c in (("/tactile/image", Image), ("/tactile/features", ContactFeatures))]
    rospy.spin()  # until SIGINT
    for s in subs:
        s.unregister()
    with lock, rosbag.Bag(rospy.myargv()[1], "w") as bag:
        for topic, msg, t in got:
            bag.write(topic, msg, t)
    print(f"record_bag: {len(got)} messages -> {rospy.myargv()[1]}")


if __name__ == "__main__":
    main()
