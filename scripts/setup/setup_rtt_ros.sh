#!/usr/bin/env bash
# Installs Debian 12's ROS 1 packages and builds the rtt_ros_integration
# packages the project's ROS face needs (rtt_ros, rtt_rosnode, rtt_roscomm,
# rtt_rosparam; no message typekit: the project generates its own for the few
# message types it streams, ros/rtt_tactile_foreign_msgs) with catkin against
# Debian's ROS 1 and the
# Orocos toolchain in $OROCOS_PREFIX, into $OROCOS_PREFIX/ros (a catkin
# install space: source $OROCOS_PREFIX/ros/setup.sh). rtt_ros_integration is not packaged by Debian;
# it is a dependency, never part of this repository.
#
# Sources, in this order:
#   1. $OROCOS_SOURCE_DIR/rtt_ros_integration-toolchain-2.10-<short>.tar.gz,
#      checked against $OROCOS_SOURCE_DIR/SHA256SUMS;
#   2. otherwise ../shared/third_party beside the repository, when it holds
#      SHA256SUMS (the same archive, checked the same way);
#   3. otherwise a git clone of upstream at the pinned commit.
#
# Idempotent: $OROCOS_PREFIX/ros/share/tactile_servo/rtt_ros.stamp names the
# commit and the package list; a second run with the same stamp does nothing.
# Called by scripts/setup/setup_orocos.sh after Orocos. Opt out with
# TACTILE_WITH_ROS=OFF (the project then builds without its ROS face).
#
# Environment:
#   OROCOS_PREFIX       Orocos prefix (default /opt/orocos); install into $OROCOS_PREFIX/ros
#   OROCOS_SOURCE_DIR   folder holding the archive and SHA256SUMS (optional)
#   RTT_ROS_BUILD_DIR   scratch folder (default /tmp/tactile-rtt-ros-build)
#   TACTILE_JOBS        parallel jobs (default: nproc)
#   TACTILE_WITH_RVIZ=ON            also apt-install rviz, xvfb, x11-apps (scripts/tools/ros_screenshot.sh)
set -euo pipefail
# shellcheck source=progress.sh
source "$(dirname "${BASH_SOURCE[0]}")/progress.sh"

main() {

if [ "${TACTILE_WITH_ROS:-AUTO}" = "OFF" ] || [ "${TACTILE_WITH_RTT:-AUTO}" = "OFF" ]; then
  echo "setup_rtt_ros: TACTILE_WITH_ROS=OFF (or TACTILE_WITH_RTT=OFF), ROS face skipped"
  exit 0
fi

prefix="${OROCOS_PREFIX:-/opt/orocos}"
ros_prefix="$prefix/ros"
jobs="${TACTILE_JOBS:-$(nproc)}"
work="${RTT_ROS_BUILD_DIR:-/tmp/tactile-rtt-ros-build}"
commit=454c86f56a817453f7ee65a95e38e69533234b1e
url=https://github.com/orocos/rtt_ros_integration.git
# Folders of the repository, one catkin package each: what the deployments
# import (ros.import of rtt_rosnode, rtt_rosparam; rtt_roscomm through
# tactile_ros) and what those need (rtt_ros; rtt_roscomm loads rtt_rosnode).
# No whole-package message typekit (rtt_std_msgs, rtt_sensor_msgs,
# rtt_geometry_msgs: 96 compilation units): ros/rtt_tactile_foreign_msgs
# generates typekit and ROS transport of the five foreign messages used.
# rtt_rospack and rtt_rosclock (with rtt_rosgraph_msgs) are used by none.
PKGS=(rtt_ros rtt_rosnode rtt_roscomm rtt_rosparam)

stamp_dir="$ros_prefix/share/tactile_servo"
stamp="$stamp_dir/rtt_ros.stamp"
want_stamp="rtt_ros_integration=$commit packages=${PKGS[*]}"

# ---- Debian's ROS 1 ----------------------------------------------------------
# ros-core-dev: catkin, roscpp, rospy, message generation, the common message
# packages, rosbag, roslaunch, roscore; ros-robot-state-publisher: the arm's
# TF from the URDF and /tactile/joint_states (launch file, ros_screenshot.sh).
# rviz is optional (TACTILE_WITH_RVIZ=ON).
DEB=(ros-core-dev rosbash python3-rospy python3-rosbag libtf2-ros-dev libtf2-msgs-dev
     python3-tf2-ros python3-sensor-msgs python3-geometry-msgs python3-std-msgs
     libstd-srvs-dev ros-robot-state-publisher)
if [ "${TACTILE_WITH_RVIZ:-OFF}" = "ON" ]; then DEB+=(rviz xvfb x11-apps python3-visualization-msgs); fi
missing=()
for p in "${DEB[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup_rtt_ros: [1/5] installing Debian's ROS 1 packages ${missing[*]} ($(progress_about rtt_ros_apt); log: /tmp/tactile-ros-apt.log)"
  progress_run "setup_rtt_ros:   apt" rtt_ros_apt /tmp/tactile-ros-apt.log apt_install "${missing[@]}" \
    || { echo "setup_rtt_ros: FAILED at step 'apt-get install'. Log: /tmp/tactile-ros-apt.log" >&2; tail -n 30 /tmp/tactile-ros-apt.log >&2; exit 1; }
  echo "setup_rtt_ros:   apt done in $PROGRESS_WALL s"
else
  echo "setup_rtt_ros: [1/5] Debian's ROS 1 packages present (${#DEB[@]})"
fi

if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want_stamp" ] && [ -f "$ros_prefix/setup.sh" ]; then
  echo "setup_rtt_ros: rtt_ros_integration already in $ros_prefix ($stamp matches)"
  exit 0
fi
[ -f "$prefix/lib/cmake/orocos-rtt/orocos-rtt-config.cmake" ] \
  || { echo "setup_rtt_ros: no Orocos RTT in $prefix (run scripts/setup/setup_orocos.sh first)" >&2; exit 1; }

rm -rf "$work"
mkdir -p "$work/src" "$work/logs"
log_dir="$work/logs"
step=""
fail() {
  echo "setup_rtt_ros: FAILED at step '$step'. Log: $1" >&2
  [ -f "$1" ] && tail -n 30 "$1" >&2
  exit 1
}

# ---- sources -------------------------------------------------------------------
unpacked="$work/unpacked"
mkdir -p "$unpacked"
# The pinned archives beside the repository (../shared/third_party) serve
# when OROCOS_SOURCE_DIR is not given, so the set-up needs no internet there.
sibling="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)/../shared/third_party"
if [ -z "${OROCOS_SOURCE_DIR:-}" ] && [ -f "$sibling/SHA256SUMS" ]; then
  OROCOS_SOURCE_DIR="$sibling"
fi
if [ -n "${OROCOS_SOURCE_DIR:-}" ]; then
  src_dir="$(cd "$OROCOS_SOURCE_DIR" && pwd)"
  archive="$src_dir/rtt_ros_integration-toolchain-2.10-${commit:0:10}.tar.gz"
  step="checksum"
  echo "setup_rtt_ros: [2/5] checking $archive against SHA256SUMS"
  [ -f "$archive" ] || { echo "$archive missing (want commit $commit)" > "$log_dir/checksum.log"; fail "$log_dir/checksum.log"; }
  (cd "$src_dir" && grep " $(basename "$archive")\$" SHA256SUMS | sha256sum --quiet -c -) > "$log_dir/checksum.log" 2>&1 \
    || fail "$log_dir/checksum.log"
  step="unpack"
  tar -xzf "$archive" -C "$unpacked" > "$log_dir/unpack.log" 2>&1 || fail "$log_dir/unpack.log"
else
  echo "setup_rtt_ros: [2/5] cloning upstream at the pinned commit (no OROCOS_SOURCE_DIR)"
  step="clone"
  {
    git init -q "$unpacked/rtt_ros_integration"
    git -C "$unpacked/rtt_ros_integration" fetch -q --depth 1 "$url" "$commit"
    git -C "$unpacked/rtt_ros_integration" checkout -q FETCH_HEAD
  } > "$log_dir/clone.log" 2>&1 || fail "$log_dir/clone.log"
fi
for p in "${PKGS[@]}"; do
  cp -r "$unpacked/rtt_ros_integration/$p" "$work/src/"
done
ln -s /usr/share/catkin/cmake/toplevel.cmake "$work/src/CMakeLists.txt"

# ---- build (one catkin workspace, Debian's catkin, Debian's python3) -----------
# rtt_roscomm's generator runs as `#!/usr/bin/env python`; Debian 12 has no
# `python`, and the first python on PATH may not be Debian's (no rospy,
# genmsg): a `python` -> /usr/bin/python3 link first on PATH, for this build.
mkdir -p "$work/bin"
ln -sf /usr/bin/python3 "$work/bin/python"
export PATH="$work/bin:/usr/bin:$PATH"
$SUDO mkdir -p "$ros_prefix"
launcher=()
if command -v ccache > /dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
step="configure"
t0=$SECONDS
echo "setup_rtt_ros: [3/5] configuring ${#PKGS[@]} packages (log: $log_dir/configure.log)"
cmake -S "$work/src" -B "$work/build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_INSTALL_PREFIX="$ros_prefix" -DCMAKE_PREFIX_PATH="$prefix" \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCATKIN_ENABLE_TESTING=OFF -DCMAKE_CXX_FLAGS="-w" "${launcher[@]}" \
  > "$log_dir/configure.log" 2>&1 || fail "$log_dir/configure.log"
echo "setup_rtt_ros:   configured in $((SECONDS - t0)) s"
step="build"
echo "setup_rtt_ros: [4/5] building with -j$jobs ($(progress_about rtt_ros); log: $log_dir/build.log)"
progress_run "setup_rtt_ros:   build" rtt_ros "$log_dir/build.log" cmake --build "$work/build" -j"$jobs" \
  || fail "$log_dir/build.log"
echo "setup_rtt_ros:   built in $PROGRESS_WALL s (CPU user+sys $PROGRESS_CPU s)"
step="install"
echo "setup_rtt_ros: [5/5] installing into $ros_prefix"
$SUDO cmake --install "$work/build" > "$log_dir/install.log" 2>&1 || fail "$log_dir/install.log"

$SUDO mkdir -p "$stamp_dir"
echo "$want_stamp" | $SUDO tee "$stamp" > /dev/null
echo "setup_rtt_ros: rtt_ros_integration installed in $ros_prefix (source $ros_prefix/setup.sh)"
rm -rf "$work/build" "$unpacked"
}

main "$@"
