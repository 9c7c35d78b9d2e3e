#!/usr/bin/env bash
# A screenshot of rviz during the simulated edge exploration, taken headless:
# Xvfb, a roscore of its own on 127.0.0.1, the ROS variant of the deployment
# (ros/tactile_ros/scripts/run_ros_deployment.sh), the arm (the URDF
# ros/tactile_ros/urdf/lwr4plus_wts.urdf as robot_description,
# robot_state_publisher on /tactile/joint_states, the adapter's own
# lwr_base -> lwr_flange -> wts0614 off, as the launch file has it), the
# scene's bar as markers, rviz with ros/tactile_ros/rviz/tactile.rviz; after
# AFTER_S seconds of the run the screen is written to OUT (PNG).
#   ros_screenshot.sh [OUT] [AFTER_S]   (default ros/doc/rviz_edge_exploration.png, 12)
# Needs rviz, xvfb and x11-apps (xwd) besides the ROS face (TACTILE_WITH_RVIZ=ON
# bash scripts/setup/setup_rtt_ros.sh installs them) and robot_state_publisher
# (ros-robot-state-publisher, installed with the ROS face); scripts/tools/xwd_to_png.py
# turns the XWD dump into PNG.
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
out="${1:-$root/ros/doc/rviz_edge_exploration.png}"
after="${2:-12}"
build="${BUILD:-$root/build}"
export PATH="/usr/bin:$PATH"
for t in Xvfb rviz xwd roscore rosrun; do
  command -v "$t" > /dev/null || { echo "ros_screenshot: $t not found" >&2; exit 2; }
done
set +u
# shellcheck disable=SC1091
source "$build/ros/devel/setup.bash"
set -u
export ROS_PACKAGE_PATH="$root/ros:$ROS_PACKAGE_PATH"
tmp="$(mktemp -d /tmp/tactile-ros-shot.XXXXXX)"
export ROS_HOME="$tmp" ROS_LOG_DIR="$tmp/log" ROS_IP=127.0.0.1
port=$(( 20000 + $$ % 20000 ))
while /usr/bin/python3 -c "import socket,sys; s=socket.socket(); sys.exit(s.connect_ex(('127.0.0.1', $port)) != 0)"; do
  port=$((port + 1))
done
export ROS_MASTER_URI="http://127.0.0.1:$port"
disp=$(( 90 + $$ % 100 ))
pids=()
cleanup() { for p in "${pids[@]}"; do kill -INT -- "-$p" 2>/dev/null; done; sleep 1; for p in "${pids[@]}"; do kill -KILL -- "-$p" 2>/dev/null; done; }
trap cleanup EXIT
setsid Xvfb ":$disp" -screen 0 1280x800x24 -nolisten tcp > "$tmp/xvfb.log" 2>&1 & pids+=($!)
export DISPLAY=":$disp"
setsid roscore -p "$port" > "$tmp/roscore.log" 2>&1 & pids+=($!)
for _ in $(seq 100); do
  /usr/bin/python3 -c "import rosgraph,sys; sys.exit(0 if rosgraph.is_master_online() else 1)" 2>/dev/null && break
  sleep 0.2
done
# The arm: robot_state_publisher draws the URDF from the adapter's joint states;
# the adapter leaves lwr_base -> lwr_flange -> wts0614 to it (ros_streams.ops
# reads /RosAdapter/publish_flange_tf).
rosparam set --textfile "$root/ros/tactile_ros/urdf/lwr4plus_wts.urdf" /robot_description \
  && rosparam set /RosAdapter/publish_flange_tf false \
  || { echo "ros_screenshot: rosparam set failed (logs in $tmp)" >&2; exit 1; }
setsid rosrun robot_state_publisher robot_state_publisher joint_states:=/tactile/joint_states _publish_frequency:=200 \
  > "$tmp/robot_state_publisher.log" 2>&1 & pids+=($!)
setsid /usr/bin/python3 "$root/ros/tactile_ros/scripts/scene_markers.py" "$root/params/scenes/edge_exploration.yaml" \
  > "$tmp/markers.log" 2>&1 & pids+=($!)
setsid rviz -d "$root/ros/tactile_ros/rviz/tactile.rviz" > "$tmp/rviz.log" 2>&1 & pids+=($!)
sleep 8   # rviz up before the run starts
setsid bash "$root/ros/tactile_ros/scripts/run_ros_deployment.sh" edge_exploration > "$tmp/deployer.log" 2>&1 & pids+=($!)
sleep "$after"
mkdir -p "$(dirname "$out")"
xwd -root -silent > "$tmp/screen.xwd" && /usr/bin/python3 "$root/scripts/tools/xwd_to_png.py" "$tmp/screen.xwd" "$out" \
  || { echo "ros_screenshot: capture failed (logs in $tmp)" >&2; exit 1; }
echo "ros_screenshot: $out (logs in $tmp)"
