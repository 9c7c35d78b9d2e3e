#!/usr/bin/env bash
# Runs a command against a roscore of its own on the loopback address (port
# from this script's PID, the next free one), with the environment of the ROS
# workspace and of the Orocos component path; the roscore is stopped at the
# end, whatever happened. The command's exit status is this script's.
#   with_roscore.sh SOURCE_DIR BUILD_DIR OROCOS_PREFIX ROS_PREFIX -- COMMAND [ARGS...]
# In the command's environment: ROS_MASTER_URI, TACTILE_ROS_TMP (a temporary
# folder, removed at the end unless TACTILE_ROS_KEEP=1), RTT_COMPONENT_PATH.
set -o pipefail
src="$1"; build="$2"; orocos="$3"; ros_prefix="$4"
shift 4
[ "${1:-}" = "--" ] && shift
[ $# -gt 0 ] || { echo "usage: with_roscore.sh SOURCE_DIR BUILD_DIR OROCOS_PREFIX ROS_PREFIX -- COMMAND..."; exit 2; }
export PATH="/usr/bin:$PATH"   # Debian's python3 for roscore and rospy
[ -f "$build/ros/devel/setup.bash" ] || { echo "no $build/ros/devel/setup.bash (the ROS workspace is not built)"; exit 1; }
# shellcheck disable=SC1091
source "$build/ros/devel/setup.bash"   # (its hooks read unset variables: no `set -u` here)
export ROS_PACKAGE_PATH="$src/ros:$ROS_PACKAGE_PATH"
export RTT_COMPONENT_PATH="$build/lib/orocos:$build/ros/devel/lib/orocos:$ros_prefix/lib/orocos:$orocos/lib/orocos"
tmp="$(mktemp -d /tmp/tactile-ros.XXXXXX)"
export TACTILE_ROS_TMP="$tmp" ROS_HOME="$tmp" ROS_LOG_DIR="$tmp/log" ROS_IP=127.0.0.1
unset ROS_HOSTNAME

port=$(( 20000 + $$ % 20000 ))
while /usr/bin/python3 -c "import socket,sys; s=socket.socket(); sys.exit(s.connect_ex(('127.0.0.1', $port)) != 0)"; do
  port=$((port + 1))
done
export ROS_MASTER_URI="http://127.0.0.1:$port"
echo "with_roscore: roscore on $ROS_MASTER_URI (folder $tmp)"
setsid roscore -p "$port" > "$tmp/roscore.log" 2>&1 &
core=$!
cleanup() {
  kill -INT -- "-$core" 2>/dev/null
  for _ in $(seq 50); do kill -0 "$core" 2>/dev/null || break; sleep 0.1; done
  kill -KILL -- "-$core" 2>/dev/null
  [ "${TACTILE_ROS_KEEP:-0}" = 1 ] || rm -rf "$tmp"
}
trap cleanup EXIT
for _ in $(seq 100); do
  /usr/bin/python3 -c "import rosgraph,sys; sys.exit(0 if rosgraph.is_master_online() else 1)" 2>/dev/null && break
  sleep 0.2
done
/usr/bin/python3 -c "import rosgraph,sys; sys.exit(0 if rosgraph.is_master_online() else 1)" \
  || { echo "with_roscore: roscore did not come up"; cat "$tmp/roscore.log"; exit 1; }
"$@"
rc=$?
echo "with_roscore: '$1' exit $rc"
exit "$rc"
