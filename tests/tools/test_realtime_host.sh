#!/usr/bin/env bash
# scripts/setup/realtime_host.sh against files of the test's own: autogroup
# 1 -> 0 with the setting kept in the sysctl file, idempotent on a second run,
# left as it is with TACTILE_HOST_SETTINGS=keep, nothing to do without the
# setting. Root only (the script writes only as root); otherwise it checks the
# warning path.
set -uo pipefail
script="$1/scripts/setup/realtime_host.sh"
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
export TACTILE_AUTOGROUP_FILE="$tmp/autogroup" TACTILE_SYSCTL_CONF="$tmp/sysctl.d/60-tactile-servo.conf"
mkdir -p "$tmp/sysctl.d"
fails=0
check() { if eval "$2"; then echo "ok    $1"; else echo "FAIL  $1"; fails=$((fails + 1)); fi; }
echo 1 > "$TACTILE_AUTOGROUP_FILE"
out="$(TACTILE_HOST_SETTINGS=keep bash "$script" 2>&1)"
check "keep: left at 1 ($out)" '[ "$(cat "$TACTILE_AUTOGROUP_FILE")" = 1 ] && [ ! -e "$TACTILE_SYSCTL_CONF" ]'
out="$(bash "$script" 2>&1)"
if [ "$(id -u)" -eq 0 ]; then
  check "1 -> 0 ($out)" '[ "$(cat "$TACTILE_AUTOGROUP_FILE")" = 0 ] && [[ "$out" == *"1 -> 0"* ]]'
  check "kept in the sysctl file" 'grep -qx "kernel.sched_autogroup_enabled = 0" "$TACTILE_SYSCTL_CONF"'
  before="$(stat -c %Y "$TACTILE_SYSCTL_CONF")"; sleep 1
  out="$(bash "$script" 2>&1)"
  check "second run: nothing changed ($out)" '[[ "$out" == *"= 0" ]] && [ "$(stat -c %Y "$TACTILE_SYSCTL_CONF")" = "$before" ]'
else
  check "not root: a warning, the setting as it was ($out)" '[[ "$out" == *WARNING* ]]'
fi
rm -f "$TACTILE_AUTOGROUP_FILE"
out="$(bash "$script" 2>&1)"
check "no such setting: nothing to set ($out)" '[[ "$out" == *"nothing to set"* ]]'
[ "$fails" -eq 0 ]
