#!/usr/bin/env bash
# The kernel setting the deployments rely on, applied when missing
# (idempotent) and kept across reboots in /etc/sysctl.d:
#
#   kernel.sched_autogroup_enabled = 0
#     The WTS0614's bytes (its USB-serial port, or the simulated sensor's PTY)
#     reach the Sensor thread through a SCHED_OTHER kernel worker, the tty's
#     flip-buffer work. With autogroup on, a CPU-bound load held that worker
#     off its CPU for seconds and the servo got a few frames a second
#     (docs/realtime.md, "The sensor's tty under CPU load").
#
# Not root, or /proc/sys read-only (a container): says what it could not set
# and goes on; the deployments' RealtimeCheck warns again when they start.
# TACTILE_HOST_SETTINGS=keep leaves the host as it is. The test
# (tests/tools/test_realtime_host.sh) points TACTILE_AUTOGROUP_FILE and
# TACTILE_SYSCTL_CONF at files of its own.
set -euo pipefail
key=kernel.sched_autogroup_enabled
proc="${TACTILE_AUTOGROUP_FILE:-/proc/sys/kernel/sched_autogroup_enabled}"
conf="${TACTILE_SYSCTL_CONF:-/etc/sysctl.d/60-tactile-servo.conf}"
if [ ! -r "$proc" ]; then
  echo "realtime_host: $key: not in this kernel, nothing to set"
  exit 0
fi
now="$(cat "$proc")"
if [ "${TACTILE_HOST_SETTINGS:-apply}" = keep ]; then
  echo "realtime_host: TACTILE_HOST_SETTINGS=keep: $key left at $now"
  exit 0
fi
if [ "$(id -u)" -eq 0 ] && [ -d "$(dirname "$conf")" ] && ! grep -qsx "$key = 0" "$conf"; then
  printf '# tactile_servo: the sensor tty worker must not be starved (scripts/setup/realtime_host.sh)\n%s = 0\n' \
    "$key" > "$conf"
fi
if [ "$now" = 0 ]; then
  echo "realtime_host: $key = 0"
elif (echo 0 > "$proc") 2> /dev/null; then
  echo "realtime_host: $key $now -> 0 (kept in $conf)"
else
  echo "realtime_host: WARNING: cannot set $key = 0 (not root, or /proc/sys read-only): a CPU-bound load" \
    "can starve the sensor's tty worker; the robot-path tests can then fail under load" >&2
fi
