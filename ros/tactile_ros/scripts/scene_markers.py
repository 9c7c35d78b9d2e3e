#!/usr/bin/python3
"""Publishes the objects of a simulator scene (params/scenes/*.yaml) as a latched
visualization_msgs/MarkerArray on /tactile/scene_markers, in the base frame
{g} (lwr_base), for rviz: a bar as a line of its diameter between its two
vertices. roslaunch's own arguments (name:=value) are ignored.

usage: scene_markers.py SCENE_YAML [BASE_FRAME]
"""
import sys

import rospy
import yaml
from geometry_msgs.msg import Point
from visualization_msgs.msg import Marker, MarkerArray


def main():
    args = [a for a in sys.argv[1:] if ":=" not in a]
    scene = yaml.safe_load(open(args[0]))
    base = args[1] if len(args) > 1 else "lwr_base"
    rospy.init_node("tactile_scene_markers")
    pub = rospy.Publisher("/tactile/scene_markers", MarkerArray, queue_size=1, latch=True)
    out = MarkerArray()
    for i, obj in enumerate(scene.get("objects", [])):
        if obj.get("type") != "bar":
            continue
        m = Marker()
        m.header.frame_id = base
        m.header.stamp = rospy.Time.now()
        m.ns, m.id, m.type, m.action = "scene", i, Marker.LINE_STRIP, Marker.ADD
        m.pose.orientation.w = 1.0
        m.scale.x = 2.0 * float(obj.get("radius", 0.003))
        m.color.r, m.color.g, m.color.b, m.color.a = 0.8, 0.5, 0.2, 1.0
        m.points = [Point(*v) for v in obj["vertices"]]
        out.markers.append(m)
    pub.publish(out)
    rospy.loginfo("scene_markers: %d objects of %s on /tactile/scene_markers", len(out.markers), args[0])
    rospy.spin()


if __name__ == "__main__":
    main()
