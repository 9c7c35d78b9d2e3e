#!/usr/bin/env bash
# Builds the parts of the Orocos toolchain 2.10 the deployments use into
# $OROCOS_PREFIX (default /opt/orocos), unless a matching install is already
# there: RTT (gnulinux target, CORBA and MQ off, its typekit, marshalling and
# scripting plugins) and OCL's deployer, TaskBrowser, DeploymentComponent,
# reporting components and print/os services (OCL's Lua, logging, timer and
# helloworld off, so log4cpp is not needed). Orocos is not packaged by Debian;
# it is a dependency, never part of this repository.
#
# Sources, in this order:
#   1. $OROCOS_SOURCE_DIR: a folder of the upstream `git archive` snapshots
#      (rtt-*.tar.gz, ocl-*.tar.gz; log4cpp-*.tar.gz beside them is not used)
#      with a SHA256SUMS file, checked before use;
#   2. otherwise ../shared/third_party beside the repository, when it holds
#      SHA256SUMS (the same archives, checked the same way);
#   3. otherwise a git clone of the upstream repositories at the pinned commits.
#
# Idempotent: $OROCOS_PREFIX/share/tactile_servo/orocos.stamp names the commits,
# the target and the build options; a second run with the same stamp does
# nothing; a different stamp (e.g. an install with the former options)
# rebuilds, after removing what the former install put into the prefix.
# Prints each stage with its reference time (scripts/setup/progress.sh) and,
# during a compile, a progress line about every 45 s.
# Opt out of the whole RTT layer with TACTILE_WITH_RTT=OFF.
# Then runs scripts/setup/setup_rtt_ros.sh (ROS 1 and rtt_ros_integration).
#
# Environment:
#   OROCOS_PREFIX       install prefix (default /opt/orocos)
#   OROCOS_SOURCE_DIR   folder holding the archives and SHA256SUMS (optional)
#   OROCOS_BUILD_DIR    scratch folder for the build (default /tmp/tactile-orocos-build)
#   TACTILE_JOBS        parallel jobs (default: nproc)
set -euo pipefail
# shellcheck source=progress.sh
source "$(dirname "${BASH_SOURCE[0]}")/progress.sh"

main() {

if [ "${TACTILE_WITH_RTT:-AUTO}" = "OFF" ]; then
  echo "setup_orocos: TACTILE_WITH_RTT=OFF, nothing to do"
  exit 0
fi

prefix="${OROCOS_PREFIX:-/opt/orocos}"
jobs="${TACTILE_JOBS:-$(nproc)}"
work="${OROCOS_BUILD_DIR:-/tmp/tactile-orocos-build}"
target=gnulinux

# The pinned upstream commits (branch toolchain-2.10); the same as in
# ../shared/third_party/README.md. log4cpp is only needed by OCL's logging,
# which is off.
local -A COMMIT=(
  [rtt]=b499bd93a44a8971e1ad8aac3c787d0eba6dd95b
  [ocl]=7d42a742c2bf9b3235a33809dfcb71de0c15344b
)
local -A URL=(
  [rtt]=https://github.com/orocos-toolchain/rtt.git
  [ocl]=https://github.com/orocos-toolchain/ocl.git
)
ORDER=(rtt ocl)

# Both packages: CMake's Release (-O3 -DNDEBUG; -O2 saved 2 % of RTT's CPU
# seconds, within the noise, so the libraries the 1 kHz loop calls keep the
# code they were measured with); catkin (Debian's ROS 1, once setup_rtt_ros.sh
# has installed it) not looked for, so a rebuild on a machine with ROS installs
# the same files as a fresh one (catkin only adds env hooks).
local -a COMMON=(-DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS="-w" -DCMAKE_DISABLE_FIND_PACKAGE_catkin=ON)
# RTT: the library with its typekit, marshalling and scripting plugins (all
# three used: loadService marshalling/scripting, the typekit's types); no
# CORBA, no MQ transport, no tests, no docs.
local -a RTT_OPTS=(-DOROCOS_TARGET=$target -DENABLE_CORBA=OFF -DENABLE_MQ=OFF -DENABLE_TESTS=OFF
  -DBUILD_DOCS=OFF)
# OCL: deployer-gnulinux (needs the TaskBrowser and the DeploymentComponent),
# OCL::FileReporting (reporting), the print service and the ocl typekit
# (always built). Off: Lua (rttlua, .lua scripts), the log4cpp logging
# service, the timer component, helloworld, NetCDF reporting, tests, docs.
local -a OCL_OPTS=(-DOROCOS_TARGET=$target -DBUILD_TASKBROWSER=ON -DBUILD_DEPLOYMENT=ON
  -DBUILD_REPORTING=ON -DBUILD_REPORTING_NETCDF=OFF -DBUILD_LUA_RTT=OFF -DBUILD_LOGGING=OFF
  -DBUILD_TIMER=OFF -DBUILD_HELLOWORLD=OFF -DBUILD_TESTS=OFF -DDOC_BUILD_DOCS=OFF)

stamp_dir="$prefix/share/tactile_servo"
stamp="$stamp_dir/orocos.stamp"
want_stamp="target=$target corba=off mq=off ocl_parts=deployer,taskbrowser,deployment,reporting"
for r in "${ORDER[@]}"; do want_stamp+=" $r=${COMMIT[$r]}"; done

if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want_stamp" ] \
   && [ -x "$prefix/bin/deployer-$target" ]; then
  echo "setup_orocos: Orocos toolchain 2.10 already in $prefix ($stamp matches)"
  exit 0
fi

# ---- Debian build dependencies ---------------------------------------------
PKGS=(build-essential cmake pkg-config git
      libboost-dev libboost-filesystem-dev libboost-system-dev libboost-thread-dev
      libboost-serialization-dev libboost-program-options-dev libboost-regex-dev
      libboost-test-dev
      libxml2-dev libreadline-dev libncurses-dev)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup_orocos: installing Debian packages ${missing[*]} ($(progress_about orocos_apt); log: /tmp/tactile-orocos-apt.log)"
  progress_run "setup_orocos:   apt" orocos_apt /tmp/tactile-orocos-apt.log apt_install "${missing[@]}" \
    || { echo "setup_orocos: FAILED at step 'apt-get install'. Log: /tmp/tactile-orocos-apt.log" >&2; tail -n 30 /tmp/tactile-orocos-apt.log >&2; exit 1; }
fi

SUDO=""
if [ "$(id -u)" -ne 0 ] && ! mkdir -p "$prefix" 2>/dev/null; then SUDO="sudo"; fi
$SUDO mkdir -p "$prefix"

rm -rf "$work"
mkdir -p "$work/src" "$work/logs"
log_dir="$work/logs"
step=""
fail() {
  echo "setup_orocos: FAILED at step '$step'. Log: $1" >&2
  [ -f "$1" ] && tail -n 30 "$1" >&2
  exit 1
}

# ---- sources ---------------------------------------------------------------
# The pinned archives beside the repository (../shared/third_party) serve
# when OROCOS_SOURCE_DIR is not given, so the set-up needs no internet there.
sibling="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)/../shared/third_party"
if [ -z "${OROCOS_SOURCE_DIR:-}" ] && [ -f "$sibling/SHA256SUMS" ]; then
  OROCOS_SOURCE_DIR="$sibling"
fi
if [ -n "${OROCOS_SOURCE_DIR:-}" ]; then
  src_dir="$(cd "$OROCOS_SOURCE_DIR" && pwd)"
  step="checksums"
  echo "setup_orocos: [1/3] checking archives in $src_dir against SHA256SUMS"
  (cd "$src_dir" && sha256sum --quiet -c SHA256SUMS) > "$log_dir/checksums.log" 2>&1 \
    || fail "$log_dir/checksums.log"
  for r in "${ORDER[@]}"; do
    step="unpack $r"
    short="${COMMIT[$r]:0:10}"
    archive="$src_dir/$r-toolchain-2.10-$short.tar.gz"
    [ -f "$archive" ] || { echo "setup_orocos: $archive missing (want commit ${COMMIT[$r]})" > "$log_dir/unpack.log"; fail "$log_dir/unpack.log"; }
    tar -xzf "$archive" -C "$work/src" > "$log_dir/unpack.log" 2>&1 || fail "$log_dir/unpack.log"
  done
else
  echo "setup_orocos: [1/3] cloning upstream at the pinned commits (no OROCOS_SOURCE_DIR)"
  for r in "${ORDER[@]}"; do
    step="clone $r"
    {
      git init -q "$work/src/$r"
      git -C "$work/src/$r" fetch -q --depth 1 "${URL[$r]}" "${COMMIT[$r]}"
      git -C "$work/src/$r" checkout -q FETCH_HEAD
    } > "$log_dir/clone-$r.log" 2>&1 || fail "$log_dir/clone-$r.log"
  done
fi

# ---- the former install -------------------------------------------------------
# A stamp that does not match is an install with other options or commits:
# remove the files it installed (the manifests kept beside the stamp), so the
# prefix holds what a fresh install holds (import("ocl") loads every library
# in lib/orocos/<target>/ocl).
remove_former() {
  local m f found=0
  for m in "$stamp_dir"/orocos-*.manifest; do
    [ -f "$m" ] || continue
    found=1
    while IFS= read -r f; do
      case "$f" in "$prefix"/*) $SUDO rm -f "$f" ;; esac
    done < "$m"
    $SUDO rm -f "$m"
  done
  [ "$found" = 1 ] && return 0
  # Installed before the manifests were kept (the former options): what an
  # install with them has and one with the present options has not (OCL's
  # Lua, logging, timer and helloworld, log4cpp, RTT's docs), and OCL's
  # component folder, which the new install fills again.
  local h
  for h in Appender Category CategoryStream FileAppender GenerationalFileAppender Log4cxxAppender \
           LoggingEvent LoggingService LuaComponent LuaService LuaStateHandle OstreamAppender \
           RollingFileAppender TimerComponent; do
    $SUDO rm -f "$prefix/include/orocos/ocl/$h.hpp"
  done
  $SUDO rm -rf "$prefix/lib/orocos/$target/ocl" "$prefix"/lib/liborocos-log4cpp.* \
    "$prefix"/lib/liborocos-ocl-log4cpp-* "$prefix"/include/orocos/log4cpp \
    "$prefix"/lib/pkgconfig/ocl-{logging,lua,timer}-"$target".pc "$prefix"/lib/pkgconfig/orocos-log4cpp.pc \
    "$prefix"/bin/rttlua* "$prefix"/bin/helloworld* "$prefix"/etc/orocos/profile.d/00.ocl-lua.sh \
    "$prefix"/share/lua "$prefix"/share/log4cpp "$prefix"/share/doc/liborocos-rtt
}
if [ -f "$stamp" ]; then
  step="remove former install"
  echo "setup_orocos: removing the former install from $prefix (its stamp: $(cat "$stamp"))"
  remove_former > "$log_dir/remove.log" 2>&1 || fail "$log_dir/remove.log"
  $SUDO rm -f "$stamp"
fi

# ---- build -----------------------------------------------------------------
build_steps() {  # NAME [cmake args]: configure, compile, install
  local r="$1"; shift
  cmake -S "$work/src/$r" -B "$work/build/$r" \
    -DCMAKE_INSTALL_PREFIX="$prefix" -DCMAKE_PREFIX_PATH="$prefix" "$@" &&
  cmake --build "$work/build/$r" -j"$jobs" &&
  $SUDO cmake --install "$work/build/$r"
}
build() {  # build NAME [cmake args]
  local r="$1"; shift
  step="build $r"
  local log="$log_dir/$r.log"
  echo "setup_orocos: building $r with -j$jobs ($(progress_about "$r"); log: $log)"
  progress_run "setup_orocos:   $r" "$r" "$log" build_steps "$r" "$@" || fail "$log"
  $SUDO mkdir -p "$stamp_dir"
  $SUDO cp "$work/build/$r/install_manifest.txt" "$stamp_dir/orocos-$r.manifest"
  echo "setup_orocos:   $r done in $PROGRESS_WALL s (CPU user+sys $PROGRESS_CPU s)"
}

echo "setup_orocos: [2/3] RTT ($target, CORBA and MQ off)"
build rtt "${COMMON[@]}" "${RTT_OPTS[@]}"
echo "setup_orocos: [3/3] OCL (deployer, TaskBrowser, deployment, reporting)"
build ocl "${COMMON[@]}" "${OCL_OPTS[@]}"

step="stamp"
$SUDO mkdir -p "$stamp_dir"
echo "$want_stamp" | $SUDO tee "$stamp" > /dev/null
[ -x "$prefix/bin/deployer-$target" ] || { echo "no $prefix/bin/deployer-$target after install" > "$log_dir/stamp.log"; fail "$log_dir/stamp.log"; }
echo "setup_orocos: Orocos toolchain 2.10 installed in $prefix"
rm -rf "$work/build"
}

# In a subshell: main's early `exit 0` (already installed) must not skip the
# ROS part, rtt_ros_integration against Debian's ROS 1 (its own stamp; off
# with TACTILE_WITH_ROS=OFF).
(main "$@")
bash "$(dirname "${BASH_SOURCE[0]}")/setup_rtt_ros.sh"
