#!/usr/bin/env bash
# ctest lab_sim_load_data: the load-data check (fri_check --load-data,
# docs/bringup.md step 3d) on lab_sim's KRC, whose world carries the scene
# fault pad_mass (the load model's pad mass off: its weight at the pad's
# centre of mass, turning with the flange) and 0.5 N of wrench noise per axis.
# The bring-up scene without its bar (nothing touches the pad) rests in
# monitor mode in three orientations (flange down, tilted 60 deg about x,
# about y; initial_flange.rpy_deg), 500 packets recorded by fri_check
# --monitor --record in each, with the fault (0.3 kg) and without. Checked:
# without it `load data OK` (exit 0); with it `mass off by` (exit 3) and the
# fitted mass 0.5 kg (the sensor file's 0.2 + 0.3) within 0.01 kg (the noise,
# a function of the scene's seed and time, leaves 0.504 kg here: 0.5 N over
# 500 packets in 3 orientations is a few grams). fri_check listens on an
# ephemeral port.
#   run_lab_sim_load_data_test.sh SOURCE_DIR BUILD_DIR
set -uo pipefail
name=lab_sim_load_data
root="$1"
build="$2"
source "$root/tests/lab_sim/lab_record_common.sh"  # lab_record_init, lab_record
lab_record_init load_data
params="$root/params/sensors/fri.yaml"

# rest NAME RPY [LAB_SIM ARGS...]: lab_sim at rest in that orientation, recorded
rest() {
  local tag="$1" rpy="$2"
  shift 2
  lab_record "$tag" 500 "$root/krc/TactileServo.src" --duration 3 --set "objects=[]" \
    --set "initial_flange.rpy_deg=$rpy" --set "effects.wrench_error.noise_n=0.5" "$@"
}
orient=("[180, 0, 180]" "[120, 0, 180]" "[180, 60, 180]")
fault='faults=[{kind: pad_mass, mass_kg: 0.3}]'
for i in 0 1 2; do
  rest "ok_$i" "${orient[$i]}" || exit 1
  rest "heavy_$i" "${orient[$i]}" --set "$fault" || exit 1
done
check() {
  "$build/bin/fri_check" --load-data --params "$params" --sensor-params "$root/params/sensors/wts0614.yaml" \
    "$out/$1_0.csv" "$out/$1_1.csv" "$out/$1_2.csv"
}
ok_out=$(check ok)
ok_rc=$?
heavy_out=$(check heavy)
heavy_rc=$?
echo "$ok_out"
echo "exit $ok_rc"
echo "$heavy_out"
echo "exit $heavy_rc"
/usr/bin/python3 - "$ok_rc" "$heavy_rc" "$ok_out" "$heavy_out" <<'PY'
import re, sys
ok_rc, heavy_rc, ok_out, heavy_out = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3], sys.argv[4]
m = re.search(r"fit over 3 orientations .*?: mass ([0-9.]+) kg", heavy_out)
mass = float(m.group(1)) if m else float("nan")
checks = [
    (ok_rc == 0 and "verdict: load data OK" in ok_out, "without the fault: load data OK, exit 0"),
    (heavy_rc == 3 and "verdict: mass off by" in heavy_out, "with pad_mass 0.3 kg: mass off, exit 3"),
    (abs(mass - 0.5) <= 0.01, f"fitted mass {mass} kg = 0.5 kg within 0.01 kg"),
]
for good, what in checks:
    print(("ok   " if good else "FAIL ") + what)
sys.exit(0 if all(g for g, _ in checks) else 1)
PY
