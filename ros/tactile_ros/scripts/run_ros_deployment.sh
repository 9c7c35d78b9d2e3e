#!/usr/bin/env bash
# Runs a ROS variant of a deployment (deployments/<experiment>_sim_ros.ops)
# under the OCL deployer from deployments/, with the environment the ROS face
# needs: Debian's python3 first, the ROS workspace's devel space, the
# project's, the ROS workspace's and rtt_ros_integration's components on
# RTT_COMPONENT_PATH. Needs a roscore (ROS_MASTER_URI). Also a roslaunch node
# (launch/edge_exploration_sim.launch): roslaunch's own arguments (name:=value)
# are ignored.
#   run_ros_deployment.sh [EXPERIMENT]   (default edge_exploration)
# Environment: BUILD (default <repo>/build), OROCOS (default /opt/orocos),
# ROS_PREFIX (default $OROCOS/ros).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../../.." && pwd)"
build="${BUILD:-$root/build}"
orocos="${OROCOS:-/opt/orocos}"
ros_prefix="${ROS_PREFIX:-$orocos/ros}"
exp=edge_exploration
for a in "$@"; do
  case "$a" in *:=*) ;; *) exp="$a" ;; esac
done
script="$root/deployments/${exp}_sim_ros.ops"
[ -f "$script" ] || { echo "run_ros_deployment: no $script" >&2; exit 2; }
export PATH="/usr/bin:$PATH"
set +u
# shellcheck disable=SC1091
source "$build/ros/devel/setup.bash"
set -u
export ROS_PACKAGE_PATH="$root/ros:$ROS_PACKAGE_PATH"
export RTT_COMPONENT_PATH="$build/lib/orocos:$build/ros/devel/lib/orocos:$ros_prefix/lib/orocos:$orocos/lib/orocos"
cd "$root/deployments"
exec "$orocos/bin/deployer-gnulinux" --check -lwarning -s "$script"
