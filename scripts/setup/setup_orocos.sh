#!/usr/bin/env bash
# Builds the Orocos toolchain 2.10 (log4cpp, RTT, OCL; gnulinux target, CORBA
# off) into $OROCOS_PREFIX (default /opt/orocos), unless a matching install is
# already there. Orocos is not packaged by Debian; it is a dependency, never
# part of this repository.
#
# Sources, in this order:
#   1. $OROCOS_SOURCE_DIR: a folder of the upstream `git archive` snapshots
#      (log4cpp-*.tar.gz, rtt-*.tar.gz, ocl-*.tar.gz) with a SHA256SUMS file,
#      checked before use;
#   2. otherwise ../shared/third_party beside the repository, when it holds
#      SHA256SUMS (the same archives, checked the same way);
#   3. otherwise a git clone of the upstream repositories at the pinned commits.
#
# Idempotent: $OROCOS_PREFIX/share/tactile_servo/orocos.stamp names the commits
# and the target; a second run with the same stamp does nothing.
# Opt out of the whole RTT layer with TACTILE_WITH_RTT=OFF.
# Then runs scripts/setup/setup_rtt_ros.sh (ROS 1 and rtt_ros_integration).
#
# Environment:
#   OROCOS_PREFIX       install prefix (default /opt/orocos)
#   OROCOS_SOURCE_DIR   folder holding the archives and SHA256SUMS (optional)
#   OROCOS_BUILD_DIR    scratch folder for the build (default /tmp/tactile-orocos-build)
#   TACTILE_JOBS        parallel jobs (default: nproc)
set -euo pipefail

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
# ../shared/third_party/README.md.
local -A COMMIT=(
  [log4cpp]=3c5b5ff323da1eea0762e5eebc32229ad981c8c9
  [rtt]=b499bd93a44a8971e1ad8aac3c787d0eba6dd95b
  [ocl]=7d42a742c2bf9b3235a33809dfcb71de0c15344b
)
local -A URL=(
  [log4cpp]=https://github.com/orocos-toolchain/log4cpp.git
  [rtt]=https://github.com/orocos-toolchain/rtt.git
  [ocl]=https://github.com/orocos-toolchain/ocl.git
)
ORDER=(log4cpp rtt ocl)

stamp_dir="$prefix/share/tactile_servo"
stamp="$stamp_dir/orocos.stamp"
want_stamp="target=$target corba=off"
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
      libxml2-dev libreadline-dev libncurses-dev liblua5.1-0-dev lua5.1)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  echo "setup_orocos: installing Debian packages ${missing[*]} (log: /tmp/tactile-orocos-apt.log)"
  { $SUDO apt-get update -qq &&
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"; } \
    > /tmp/tactile-orocos-apt.log 2>&1 || { echo "setup_orocos: FAILED at step 'apt-get install'. Log: /tmp/tactile-orocos-apt.log" >&2; tail -n 30 /tmp/tactile-orocos-apt.log >&2; exit 1; }
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
  echo "setup_orocos: [1/4] checking archives in $src_dir against SHA256SUMS"
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
  echo "setup_orocos: [1/4] cloning upstream at the pinned commits (no OROCOS_SOURCE_DIR)"
  for r in "${ORDER[@]}"; do
    step="clone $r"
    {
      git init -q "$work/src/$r"
      git -C "$work/src/$r" fetch -q --depth 1 "${URL[$r]}" "${COMMIT[$r]}"
      git -C "$work/src/$r" checkout -q FETCH_HEAD
    } > "$log_dir/clone-$r.log" 2>&1 || fail "$log_dir/clone-$r.log"
  done
fi

# ---- build -----------------------------------------------------------------
build() {  # build NAME [cmake args]
  local r="$1"; shift
  step="build $r"
  local log="$log_dir/$r.log"
  local t0=$SECONDS
  echo "setup_orocos: building $r (log: $log)"
  {
    cmake -S "$work/src/$r" -B "$work/build/$r" -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_INSTALL_PREFIX="$prefix" -DCMAKE_PREFIX_PATH="$prefix" "$@" &&
    cmake --build "$work/build/$r" -j"$jobs" &&
    $SUDO cmake --install "$work/build/$r"
  } > "$log" 2>&1 || fail "$log"
  echo "setup_orocos:   $r done in $((SECONDS - t0)) s"
}

echo "setup_orocos: [2/4] log4cpp"
# GCC 12 no longer includes <ctime> transitively; log4cpp relies on it.
build log4cpp -DCMAKE_CXX_FLAGS="-include ctime -w" -DBUILD_TESTING=OFF
echo "setup_orocos: [3/4] RTT ($target, CORBA off)"
build rtt -DOROCOS_TARGET=$target -DENABLE_CORBA=OFF -DENABLE_TESTS=OFF -DENABLE_MQ=OFF \
  -DCMAKE_CXX_FLAGS="-w"
echo "setup_orocos: [4/4] OCL"
build ocl -DOROCOS_TARGET=$target -DBUILD_TESTS=OFF -DCMAKE_CXX_FLAGS="-w"

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
