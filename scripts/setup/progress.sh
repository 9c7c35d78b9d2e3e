# Progress of the set-up stages, sourced by setup_deps.sh, setup_orocos.sh,
# setup_rtt_ros.sh and build.sh (not run on its own).
#
# progress_run TAG KEY LOG CMD... runs CMD in the foreground with its output in
# LOG and, every $TACTILE_PROGRESS_INTERVAL seconds (default 45), prints one
# line: the build's last [NN%] (make) or [n/N] (ninja) from LOG, the time so
# far and the stage's reference time. It returns CMD's exit status and leaves
# the failure message to the caller.

# How long each stage took on a fresh 2-core machine (Debian 12, nothing
# installed before), in seconds; empty: not measured yet. The one place these
# numbers live; update a number after a fresh run of its stage.
#   The test command's fresh run of docs/first_hour.md (each stage's own
#   "done in"/"built in"/"compiled in" line); build_cores: the main job's first
#   build there (tactile_sim and the cores it links). orocos_apt: an earlier
#   fresh run (its packages have not changed since).
declare -A TACTILE_REF_SECONDS=(
  [deps_apt]=62
  [orocos_apt]=48
  [rtt]=216
  [ocl]=65
  [rtt_ros_apt]=20
  [rtt_ros]=166
  [build]=661
  [build_cores]=66
)

# apt_install PKG...: Debian packages, non-interactive (sudo where not root);
# the set-up scripts run it under progress_run.
apt_install() {
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq &&
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "$@"
}

# "about 8 min on a fresh 2-core machine", or "no reference time yet".
progress_about() {
  local s="${TACTILE_REF_SECONDS[$1]:-}"
  if [ -z "$s" ]; then echo "no reference time yet"; return; fi
  echo "about $(progress_fmt "$s") on a fresh 2-core machine"
}

# 75 -> "1m15s", 40 -> "40s".
progress_fmt() {
  local s="$1"
  if [ "$s" -ge 60 ]; then printf '%dm%02ds' $((s / 60)) $((s % 60)); else printf '%ds' "$s"; fi
}

# The last [NN%] or [n/N] at the start of a line in the end of LOG, or nothing.
progress_last_mark() {
  [ -f "$1" ] || return 0
  tail -c 65536 "$1" 2>/dev/null | grep -aoE '^\[ *[0-9]+%\]|^\[[0-9]+/[0-9]+\]' | tail -n 1 | tr -d '[] '
}

# Sets PROGRESS_CHILD_CPU to the user+sys seconds of this shell's finished
# children (bash `times`; in this shell, not in a command substitution, whose
# children would be its own).
progress_child_cpu() {
  local f
  f="$(mktemp)"
  times > "$f"
  PROGRESS_CHILD_CPU="$(sed -n 2p "$f" | awk '{
    n = 0
    for (i = 1; i <= 2; i++) { split($i, a, "m"); sub("s", "", a[2]); n += a[1] * 60 + a[2] }
    printf "%d", n + 0.5 }')"
  rm -f "$f"
}

_progress_watch() {  # TAG KEY LOG START OWNER
  local tag="$1" key="$2" log="$3" t0="$4" owner="$5"
  local every="${TACTILE_PROGRESS_INTERVAL:-45}" n=0 mark
  while kill -0 "$owner" 2>/dev/null; do
    sleep 1
    n=$((n + 1))
    [ "$n" -ge "$every" ] || continue
    n=0
    mark="$(progress_last_mark "$log")"
    echo "$tag: ${mark:-working}, $(progress_fmt $((SECONDS - t0))) so far ($(progress_about "$key"))"
  done
}

# progress_run TAG KEY LOG CMD...: CMD's exit status; sets PROGRESS_WALL and
# PROGRESS_CPU (seconds of wall clock and user+sys of CMD).
progress_run() {
  local tag="$1" key="$2" log="$3"
  shift 3
  local t0=$SECONDS cpu0 rc=0 watcher
  progress_child_cpu
  cpu0=$PROGRESS_CHILD_CPU
  _progress_watch "$tag" "$key" "$log" "$t0" "$BASHPID" &
  watcher=$!
  "$@" > "$log" 2>&1 || rc=$?
  kill "$watcher" 2>/dev/null || true
  wait "$watcher" 2>/dev/null || true
  PROGRESS_WALL=$((SECONDS - t0))
  progress_child_cpu
  PROGRESS_CPU=$((PROGRESS_CHILD_CPU - cpu0))
  return "$rc"
}
