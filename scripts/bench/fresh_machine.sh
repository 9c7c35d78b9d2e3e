#!/usr/bin/env bash
# Benchmark (not a test): the first hour on a fresh machine, against budgets.
#
# A fresh Debian 12 (bookworm) root is made with debootstrap from the host's
# apt mirror; a clone of the repository at a given commit and the pinned
# third-party archives (../shared/third_party, where .ci/run finds them) are
# laid into it, and inside `chroot`:
#   1. the main job: `bash scripts/run_experiment.sh --quick` (budget: its
#      first `results:` line within 20 min of the start);
#   2. in another fresh root, the test command as CI runs it:
#      `CI=true bash .ci/run` (budget: green within 30 min, set-up and build
#      included).
# Every line of both is timestamped into a log; the host's load is sampled
# each minute, because any other process on the machine inflates the times.
# The result goes to docs/first_hour.md and docs/results/first_hour.json
# (scripts/bench/first_hour_report.py); exit code 1 when a budget is missed
# or the test command failed.
#
# The fresh machine = debootstrap's default bookworm system plus what a new
# machine of the project's kind has before the project (the "On a new machine"
# list of the machine description: g++ with cmake/CTest, GoogleTest,
# GoogleMock, Google Benchmark, clang-format, clang-tidy, cppcheck, clangd,
# bear, gdb, valgrind, heaptrack; and make, git, python3, ca-certificates).
# Nothing of the project: no Orocos, no rtt_ros, no ROS packages, no build
# tree, no ccache. The apt lists are emptied, so the set-up runs apt-get
# update itself. Override the list with FRESH_MACHINE_PKGS="...".
# That base is made once and kept as a tarball (--base-dir); every run starts
# from a bare copy of it (a minute or two), one for each of the two.
#
# usage: sudo bash scripts/bench/fresh_machine.sh [options]
#   --root DIR        the fresh root (default /var/tmp/tactile-fresh); emptied first
#   --base-dir DIR    where the base tarball is kept (default /var/tmp)
#   --logs DIR        the logs (default ROOT.logs, outside the root)
#   --commit REV      the commit to clone (default HEAD of this repository)
#   --jobs N          parallel jobs (TACTILE_JOBS; default nproc)
#   --stop-after deps|setup|build   a quick check: run only the set-up scripts
#                     (setup_deps.sh; then setup_orocos.sh; then build.sh), not
#                     the test command; the report goes only to the logs folder
#   --udp-lock FILE   run the chroot commands under `flock FILE` (the tests use
#                     UDP ports of the host's network, shared with other checkouts)
#   --keep            leave the root (unmounted) for inspection
# Needs root (debootstrap, mount, chroot). Installs Debian's debootstrap and
# time on the host when missing.
set -euo pipefail
export LC_ALL=C TZ=UTC

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
SUITE=bookworm
PROJECT_IN_ROOT=/srv/fresh/tactile_servo
THIRD_PARTY_IN_ROOT=/srv/fresh/shared/third_party
MARKER=.tactile-fresh-root
MACHINE_PKGS=(g++ make cmake git python3 ca-certificates
  libgtest-dev libgmock-dev libbenchmark-dev
  clang-format clang-tidy clangd cppcheck bear gdb valgrind heaptrack)
if [ -n "${FRESH_MACHINE_PKGS:-}" ]; then read -ra MACHINE_PKGS <<< "$FRESH_MACHINE_PKGS"; fi

root=/var/tmp/tactile-fresh
base_dir=/var/tmp
logs=""
commit=HEAD
jobs="$(nproc)"
stop_after=""
udp_lock=""
keep=0
sampler_pid=""
stage_pid=""

say() { echo "fresh_machine: $*"; }
die() { echo "fresh_machine: error: $*" >&2; exit 2; }

usage() {
  sed -n '/^# usage:/,/^# Needs root/p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'
}

parse_args() {
  while [ $# -gt 0 ]; do
    case "$1" in
      --root) root="${2:?--root needs a folder}"; shift 2 ;;
      --base-dir) base_dir="${2:?--base-dir needs a folder}"; shift 2 ;;
      --logs) logs="${2:?--logs needs a folder}"; shift 2 ;;
      --commit) commit="${2:?--commit needs a revision}"; shift 2 ;;
      --jobs) jobs="${2:?--jobs needs a number}"; shift 2 ;;
      --stop-after) stop_after="${2:?--stop-after needs deps, setup or build}"; shift 2 ;;
      --udp-lock) udp_lock="${2:?--udp-lock needs a file}"; shift 2 ;;
      --keep) keep=1; shift ;;
      -h|--help) usage; exit 0 ;;
      *) usage >&2; die "unknown option '$1'" ;;
    esac
  done
  [ "$(id -u)" -eq 0 ] || die "needs root (debootstrap, mount, chroot)"
  case "$root" in
    /*/*) ;;
    *) die "--root '$root': give an absolute path at least two levels deep (it is emptied)" ;;
  esac
  case "$root$base_dir$logs" in *[[:space:]]*) die "--root, --base-dir and --logs must not contain spaces" ;; esac
  root="${root%/}"
  [[ "$jobs" =~ ^[1-9][0-9]*$ ]] || die "--jobs '$jobs': a positive whole number"
  case "$stop_after" in ""|deps|setup|build) ;; *) die "--stop-after '$stop_after': one of deps, setup, build" ;; esac
  logs="${logs:-$root.logs}"
  commit="$(git -C "$repo" rev-parse --verify "$commit^{commit}" 2>/dev/null)" \
    || die "--commit: no such commit in $repo"
}

# Debian packages the host needs for this script, installed only when missing.
ensure_host_tools() {
  local missing=() p
  for p in debootstrap time; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  say "installing on the host: ${missing[*]} (log $logs/host-apt.log)"
  { apt-get update -qq &&
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"; } \
    > "$logs/host-apt.log" 2>&1 || { tail -n 20 "$logs/host-apt.log" >&2; die "apt-get install ${missing[*]} failed"; }
}

# The host's mirror for the suite (deb822 debian.sources), else deb.debian.org.
host_mirror() {
  local f=/etc/apt/sources.list.d/debian.sources
  if [ -f "$f" ]; then
    awk -v s="$SUITE" '/^URIs:/ {u=$2} /^Suites:/ {for (i=2;i<=NF;i++) if ($i==s) {print u; exit}}' "$f"
  fi | grep . || echo http://deb.debian.org/debian
}

base_tarball() {
  local key
  key="$(printf '%s\n' "$SUITE" "$(host_mirror)" "${MACHINE_PKGS[@]}" | sha256sum | cut -c1-12)"
  echo "$base_dir/tactile-fresh-base-$SUITE-$key.tar"
}

# Everything mounted below DIR, deepest first.
mounts_below() {
  awk -v d="$1/" 'index($2, d) == 1 {print $2}' /proc/mounts | sort -r
}

umount_all() {
  local m
  for m in $(mounts_below "$1"); do
    umount "$m" 2>/dev/null || umount -l "$m" || echo "fresh_machine: could not unmount $m" >&2
  done
}

mount_all() {
  local r="$1"
  mkdir -p "$r/proc" "$r/sys" "$r/dev" "$r/etc"
  mount -t proc proc "$r/proc"
  mount -t sysfs sysfs "$r/sys"
  mount --bind /dev "$r/dev"
  mount --bind /dev/pts "$r/dev/pts"   # the tests open PTYs
  if mountpoint -q /dev/shm; then mount --bind /dev/shm "$r/dev/shm"; fi
  cp -L --remove-destination /etc/resolv.conf "$r/etc/resolv.conf"
}

# Empties DIR, only when nothing is mounted below it and it is a root this
# script made (its marker) or a folder that does not exist yet.
clear_root() {
  local r="$1"
  [ -e "$r" ] || return 0
  umount_all "$r"
  [ -z "$(mounts_below "$r")" ] || die "$r still has mounts below it: $(mounts_below "$r" | tr '\n' ' ')"
  [ -f "$r/$MARKER" ] || [ -z "$(ls -A "$r")" ] \
    || die "$r exists and was not made by this script (no $r/$MARKER): remove it yourself or give another --root"
  rm -rf --one-file-system "$r"
}

# The bare base, made once: debootstrap + the machine's packages, apt lists emptied.
make_base() {
  local tarball="$1" tmp="$root.base"
  if [ -f "$tarball" ]; then say "base: $tarball (cached)"; return 0; fi
  local mirror t0=$SECONDS
  mirror="$(host_mirror)"
  say "base: debootstrap $SUITE from $mirror into $tmp (once; kept as $tarball)"
  clear_root "$tmp"
  mkdir -p "$tmp" "$base_dir"
  touch "$tmp/$MARKER"
  debootstrap "$SUITE" "$tmp" "$mirror" > "$logs/base-debootstrap.log" 2>&1 \
    || { tail -n 20 "$logs/base-debootstrap.log" >&2; die "debootstrap failed (log $logs/base-debootstrap.log)"; }
  if [ -f /etc/apt/sources.list.d/debian.sources ]; then
    cp /etc/apt/sources.list.d/debian.sources "$tmp/etc/apt/sources.list.d/debian.sources"
    rm -f "$tmp/etc/apt/sources.list"
  fi
  mount_all "$tmp"
  say "base: installing the machine's packages: ${MACHINE_PKGS[*]}"
  if ! chroot "$tmp" /usr/bin/env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin DEBIAN_FRONTEND=noninteractive \
      sh -c "apt-get update -qq && apt-get install -y -qq ${MACHINE_PKGS[*]} && apt-get clean" \
      > "$logs/base-packages.log" 2>&1; then
    umount_all "$tmp"; tail -n 20 "$logs/base-packages.log" >&2
    die "installing the machine's packages failed (log $logs/base-packages.log)"
  fi
  umount_all "$tmp"
  rm -rf "$tmp/var/lib/apt/lists/"* "$tmp/etc/resolv.conf"
  tar -C "$tmp" --numeric-owner -cpf "$tarball.partial" . && mv "$tarball.partial" "$tarball"
  rm -rf --one-file-system "$tmp"
  say "base: made in $((SECONDS - t0)) s ($(du -h "$tarball" | cut -f1))"
}

fresh_root() {
  local t0=$SECONDS
  clear_root "$root"
  mkdir -p "$root"
  tar -C "$root" --numeric-owner -xpf "$1"
  touch "$root/$MARKER"
  say "fresh root $root from the base in $((SECONDS - t0)) s"
}

# A fresh root from the base tarball, mounted, with the project laid in.
new_machine() {
  umount_all "$root"
  fresh_root "$1"
  mount_all "$root"
  lay_project
}

# A clone at the commit, and the pinned archives beside it as .ci/run expects.
lay_project() {
  local dest="$root$PROJECT_IN_ROOT" tp="$repo/../shared/third_party"
  git clone -q --no-hardlinks "$repo" "$dest"
  git -C "$dest" checkout -q --detach "$commit"
  if [ -d "$tp" ]; then
    mkdir -p "$root$THIRD_PARTY_IN_ROOT"
    cp -a "$tp/." "$root$THIRD_PARTY_IN_ROOT/"
    say "cloned $commit; pinned archives from $(cd "$tp" && pwd)"
  else
    say "cloned $commit; no $tp: Orocos and rtt_ros will be cloned from upstream"
  fi
}

# Prefixes each line with the UTC time and the seconds since START_US (µs).
stamp_lines() {
  local t0="$1" line now ms
  trap '' INT
  while IFS= read -r line || [ -n "$line" ]; do
    now="${EPOCHREALTIME/./}"
    ms=$(( (now - t0) / 1000 ))
    printf '%(%H:%M:%S)T %7d.%03d %s\n' "${now:0:10}" $((ms / 1000)) $((ms % 1000)) "$line"
  done
}

# run_stage NAME COMMAND [WHAT]: COMMAND in the root, in the clone, with a clean environment;
# its lines timestamped into LOGS/NAME.log, its wall/user/sys seconds and exit
# code into LOGS/NAME.time ("wall user sys rc").
run_stage() {
  local name="$1" cmd="$2" what="${3:-$2}" t0 rc=0
  local lock=(); [ -n "$udp_lock" ] && lock=(flock "$udp_lock")
  say "[$name] $what (log $logs/$name.log)"
  t0="${EPOCHREALTIME/./}"
  # In the background, so that an interrupt's trap runs at once (`wait`
  # returns on a trapped signal); pipefail: the exit code is the command's.
  ( "${lock[@]}" /usr/bin/time -f '%e %U %S' -o "$logs/$name.rusage" \
      chroot "$root" /usr/bin/env -i HOME=/root LANG=C.UTF-8 TERM=dumb \
        PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
        TACTILE_JOBS="$jobs" bash -c "cd $PROJECT_IN_ROOT && $cmd" < /dev/null 2>&1 \
      | stamp_lines "$t0" > "$logs/$name.log" ) &
  stage_pid=$!
  wait "$stage_pid" || rc=$?
  stage_pid=""
  echo "$(tail -n 1 "$logs/$name.rusage") $rc" > "$logs/$name.time"
  say "[$name] exit code $rc; wall/user/sys s: $(tail -n 1 "$logs/$name.rusage")"
  return 0
}

# The set-up scripts one by one, for --stop-after (not the test command).
partial_command() {
  local c="set -e; export OROCOS_SOURCE_DIR=$THIRD_PARTY_IN_ROOT TACTILE_WITH_RTT=ON TACTILE_WITH_ROS=ON"
  c+="; step() { local t=\$SECONDS; bash \"\$1\"; echo \"fresh_machine: \$1 done in \$((SECONDS - t)) s\"; }"
  c+="; step scripts/setup/setup_deps.sh"
  [ "$stop_after" = deps ] && { echo "$c"; return; }
  c+="; step scripts/setup/setup_orocos.sh"
  [ "$stop_after" = setup ] && { echo "$c"; return; }
  echo "$c; step scripts/setup/build.sh"
}

start_load_sampler() {
  uptime > "$logs/uptime-start.txt"
  ( while :; do echo "$(date -u +%H:%M:%S) $(cat /proc/loadavg)"; sleep 60; done ) > "$logs/loadavg.log" &
  sampler_pid=$!
}

# The processes running inside DIR (their root is DIR): this benchmark's own.
root_pids() {
  local p r
  for p in /proc/[0-9]*; do
    r="$(readlink "$p/root" 2>/dev/null)" || continue
    [ "$r" = "$1" ] && echo "${p#/proc/}"
  done
  return 0
}

# On an interrupt: end what runs in the root (apt and dpkg ignore SIGINT), so
# that the pipeline returns and the EXIT trap can unmount.
stop_root_processes() {
  local pids=()
  if [ -n "$stage_pid" ]; then  # flock or time waiting outside the root, then the stage's subshell
    mapfile -t pids < <(ps -o pid= --ppid "$stage_pid" | tr -d ' ')
    kill -TERM "${pids[@]}" "$stage_pid" 2>/dev/null || true
  fi
  mapfile -t pids < <(root_pids "$root"; root_pids "$root.base")
  [ ${#pids[@]} -eq 0 ] && return 0
  say "interrupted: ending the processes in $root: ${pids[*]}"
  kill -TERM "${pids[@]}" 2>/dev/null || true
  for _ in 1 2 3 4 5; do
    sleep 1
    mapfile -t pids < <(root_pids "$root"; root_pids "$root.base")
    [ ${#pids[@]} -eq 0 ] && return 0
  done
  kill -KILL "${pids[@]}" 2>/dev/null || true
}

cleanup() {
  local rc=$?
  [ -n "$sampler_pid" ] && kill "$sampler_pid" 2>/dev/null && wait "$sampler_pid" 2>/dev/null
  sampler_pid=""
  [ -d "$logs" ] && uptime > "$logs/uptime-end.txt"
  [ -d "$root.base" ] && umount_all "$root.base"
  if [ -d "$root" ]; then
    umount_all "$root"
    if [ "$keep" -eq 0 ] && [ -z "$(mounts_below "$root")" ] && [ -f "$root/$MARKER" ]; then
      rm -rf --one-file-system "$root"
    elif [ "$keep" -eq 1 ]; then
      say "root kept (unmounted): $root"
    fi
  fi
  exit "$rc"
}

# An empty logs folder, or one this script made before (its marker).
prepare_logs() {
  if [ -d "$logs" ] && [ -n "$(ls -A "$logs")" ]; then
    [ -f "$logs/.fresh-machine-logs" ] || die "--logs $logs is not empty and was not made by this script"
    rm -rf "$logs"
  fi
  mkdir -p "$logs"
  touch "$logs/.fresh-machine-logs"
}

write_report() {
  local args=(--logs "$logs" --commit "$commit" --jobs "$jobs")
  if [ -n "$stop_after" ]; then
    args+=(--stop-after "$stop_after" --md "$logs/first_hour.md" --json "$logs/first_hour.json")
  else
    args+=(--md "$repo/docs/first_hour.md" --json "$repo/docs/results/first_hour.json")
  fi
  /usr/bin/python3 "$here/first_hour_report.py" "${args[@]}"
}

main() {
  parse_args "$@"
  prepare_logs
  ensure_host_tools
  local tarball; tarball="$(base_tarball)"
  trap cleanup EXIT
  trap 'stop_root_processes; exit 130' INT TERM
  make_base "$tarball"
  start_load_sampler
  if [ -n "$stop_after" ]; then
    new_machine "$tarball"
    run_stage setup_only "$(partial_command)" "the set-up scripts up to --stop-after $stop_after"
  else
    new_machine "$tarball"
    run_stage main_job "bash scripts/run_experiment.sh --quick"
    new_machine "$tarball"
    run_stage test_command "CI=true bash .ci/run"
  fi
  kill "$sampler_pid" 2>/dev/null; wait "$sampler_pid" 2>/dev/null || true; sampler_pid=""
  uptime > "$logs/uptime-end.txt"
  write_report
}

# Sourced (tests/bench), only the functions are defined.
if [ "${BASH_SOURCE[0]}" = "$0" ]; then main "$@"; exit $?; fi
