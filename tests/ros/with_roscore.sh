#!/usr/bin/env bash
# Runs a command against a roscore of its own on the loopback address (a free
# port below the ephemeral range), with the environment of the ROS
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

# The port: below the kernel's ephemeral range (ip_local_port_range), where no
# outgoing connection can hold it, from this script's PID on, the first one a
# bind() succeeds on (a connect() test misses a port held by an outgoing
# connection or bound and not yet listening). If roscore still loses a race
# for it, the next port is tried.
first_ephemeral=$(cut -f1 /proc/sys/net/ipv4/ip_local_port_range 2>/dev/null || echo 32768)
span=$(( first_ephemeral - 20000 ))
[ "$span" -gt 1000 ] || span=12000
free_port() {  # free_port START: prints the first port >= START that binds
  /usr/bin/python3 - "$1" "$first_ephemeral" <<'PY'
import socket, sys
port, top = int(sys.argv[1]), int(sys.argv[2])
for p in list(range(port, top)) + list(range(20000, port)):
    s = socket.socket()
    try:
        s.bind(("127.0.0.1", p))
    except OSError:
        continue
    finally:
        s.close()
    print(p)
    sys.exit(0)
sys.exit(1)
PY
}
master_online() {
  /usr/bin/python3 -c "import rosgraph,sys; sys.exit(0 if rosgraph.is_master_online() else 1)" 2>/dev/null
}
core=""
stop_core() {
  [ -n "$core" ] || return 0
  kill -INT -- "-$core" 2>/dev/null
  for _ in $(seq 50); do kill -0 "$core" 2>/dev/null || break; sleep 0.1; done
  kill -KILL -- "-$core" 2>/dev/null
  wait "$core" 2>/dev/null
  core=""
}
cleanup() {
  stop_core
  [ "${TACTILE_ROS_KEEP:-0}" = 1 ] || rm -rf "$tmp"
}
trap cleanup EXIT
start=$(( 20000 + $$ % span ))
for attempt in 1 2 3; do
  port=$(free_port "$start") || { echo "with_roscore: no free port below $first_ephemeral"; exit 1; }
  export ROS_MASTER_URI="http://127.0.0.1:$port"
  echo "with_roscore: roscore on $ROS_MASTER_URI (folder $tmp, attempt $attempt)"
  setsid roscore -p "$port" > "$tmp/roscore.log" 2>&1 &
  core=$!
  for _ in $(seq 100); do
    master_online && break
    kill -0 "$core" 2>/dev/null || break   # roscore gave up (port taken)
    sleep 0.2
  done
  master_online && break
  grep -q "already in use" "$tmp/roscore.log" || { echo "with_roscore: roscore did not come up"; cat "$tmp/roscore.log"; exit 1; }
  echo "with_roscore: port $port was taken before roscore bound it; next port"
  stop_core
  start=$(( port + 1 ))
done
master_online || { echo "with_roscore: roscore did not come up"; cat "$tmp/roscore.log"; exit 1; }
"$@"
rc=$?
echo "with_roscore: '$1' exit $rc"
exit "$rc"
