#!/usr/bin/env bash
# Runs a ROS variant of a deployment (deployments/sim_ros.ops or robot_ros.ops
# with TACTILE_EXPERIMENT=<experiment>, a name of experiments.yaml)
# under the OCL deployer from deployments/, with the environment the ROS face
# needs: Debian's python3 first, the ROS workspace's devel space, the
# project's, the ROS workspace's and rtt_ros_integration's components on
# RTT_COMPONENT_PATH. Needs a roscore (ROS_MASTER_URI). Also a roslaunch node
# (launch/edge_exploration_sim.launch): roslaunch's own arguments (name:=value)
# are ignored.
#   run_ros_deployment.sh [EXPERIMENT] [sim|robot]   (default edge_exploration sim)
#     sim: sim_ros.ops, run to its end (--check);
#     robot: robot_ros.ops, the deployer then waits at its prompt.
# Environment: BUILD (default <repo>/build), OROCOS (default /opt/orocos),
# ROS_PREFIX (default $OROCOS/ros).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../../.." && pwd)"
build="${BUILD:-$root/build}"
orocos="${OROCOS:-/opt/orocos}"
ros_prefix="${ROS_PREFIX:-$orocos/ros}"
exp=edge_exploration
side=sim
n=0
for a in "$@"; do
  case "$a" in
    *:=*) ;;
    *) n=$((n + 1)); if [ $n -eq 1 ]; then exp="$a"; else side="$a"; fi ;;
  esac
done
case "$side" in sim|robot) ;; *) echo "run_ros_deployment: sim or robot, not '$side'" >&2; exit 2 ;; esac
script="$root/deployments/${side}_ros.ops"
export TACTILE_EXPERIMENT="$exp"
[ -f "$script" ] || { echo "run_ros_deployment: no $script" >&2; exit 2; }
export PATH="/usr/bin:$PATH"
set +u
# shellcheck disable=SC1091
source "$build/ros/devel/setup.bash"
set -u
export ROS_PACKAGE_PATH="$root/ros:$ROS_PACKAGE_PATH"
export RTT_COMPONENT_PATH="$build/lib/orocos:$build/ros/devel/lib/orocos:$ros_prefix/lib/orocos:$orocos/lib/orocos"
cd "$root/deployments"
if [ "$side" = sim ]; then
  exec "$orocos/bin/deployer-gnulinux" --check -lwarning -s "$script"
fi
exec "$orocos/bin/deployer-gnulinux" -lwarning -s "$script"
