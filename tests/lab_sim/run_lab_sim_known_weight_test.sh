#!/usr/bin/env bash
# ctest lab_sim_known_weight: the known-weight check (fri_check
# --wrench-check, docs/bringup.md step 3c) on lab_sim's KRC, the weight and
# the KRC's errors made by the world's own wrench faults (core/sim/lwr
# sensor_faults.hpp), with 0.5 N of wrench noise per axis. The bring-up scene
# without its bar rests in monitor mode with the pad facing sideways
# (initial_flange.rpy_deg [90, 0, 180]: the flange's z horizontal); fri_check
# --monitor --record records 500 packets of each:
#   tare            nothing
#   loaded          wrench_bias [0, 0, -9.80665] N ({g}): a 1 kg weight      -> frame correct (exit 0)
#   loaded_flange   the same with wrench_frame axes: flange (reported in the
#                   flange's axes as if base axes)                          -> frame is tool not base (3)
#   loaded_sign     the same with wrench_sign (reported reversed)           -> sign inverted (3)
# A cross-check of the check's readings against the world's independent
# model of the same errors. fri_check listens on an ephemeral port.
#   run_lab_sim_known_weight_test.sh SOURCE_DIR BUILD_DIR
set -uo pipefail
name=lab_sim_known_weight
root="$1"
build="$2"
source "$root/tests/lab_sim/lab_record_common.sh"  # lab_record_init, lab_record
lab_record_init known_weight
params="$root/params/sensors/fri.yaml"

# rest NAME FAULTS: lab_sim at rest, the pad sideways, with these faults, recorded
rest() {
  lab_record "$1" 500 "$root/krc/TactileServo.src" --duration 3 --set "objects=[]" \
    --set "initial_flange.rpy_deg=[90, 0, 180]" --set "effects.wrench_error.noise_n=0.5" --set "faults=$2"
}
weight='{kind: wrench_bias, bias_n: [0, 0, -9.80665]}'
rest tare "[]" || exit 1
rest loaded "[$weight]" || exit 1
rest loaded_flange "[$weight, {kind: wrench_frame, axes: flange}]" || exit 1
rest loaded_sign "[$weight, {kind: wrench_sign}]" || exit 1
failures=0
expect() {
  local code="$1" text="$2" loaded="$3" o rc
  o=$("$build/bin/fri_check" --wrench-check --mass 1 --params "$params" --tare "$out/tare.csv" --loaded "$out/$loaded.csv" 2>&1)
  rc=$?
  echo "$o"
  if [ "$rc" -ne "$code" ] || ! grep -qF -- "$text" <<<"$o"; then
    echo "FAIL $loaded: expected exit $code and '$text', got exit $rc"
    failures=$((failures + 1))
  else
    echo "ok   $loaded: exit $rc, '$text'"
  fi
}
expect 0 "verdict: frame correct" loaded
expect 3 "verdict: frame is tool not base" loaded_flange
expect 3 "verdict: sign inverted" loaded_sign
echo "$name: $failures failure(s)"
[ "$failures" -eq 0 ]
