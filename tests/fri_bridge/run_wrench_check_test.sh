#!/usr/bin/env bash
# ctest fri_check_wrench: the day-one wrench checks end to end, as on the
# arm: fri_sim_krc (the simulated KRC, reading the KRL program with --krl)
# sends, fri_check --monitor --record records (never commanding), then
# fri_check --wrench-check and --load-data give their verdicts against the
# shipped fri.yaml (wrench_frame: base) and wts0614.yaml (pad 0.2 kg at
# z 20 mm). Each case must end with its verdict line and exit code:
#   known weight 1 kg, pad sideways, KRC #BASE          -> frame correct (0)
#   the same, KRC #TOOL (a KRL copy)                    -> frame is tool not base (3)
#   the same, KRC #BASE, the force reversed             -> sign inverted (3)
#   the same, 1.25 kg reported for 1 kg                 -> magnitude off (3)
#   KRC #TOOL, the flange pointing down                 -> undetermined (3)
#   at rest in 3 orientations, the pad's true load      -> load data OK (0)
#   the same, a pad of 0.5 kg (the KRC compensates 0.2) -> mass off by +0.300 kg (3)
# fri_check listens on an ephemeral port of 127.0.0.1 (its first line names
# it); each recording is 300 packets of the 1 ms simulated KRC.
#   run_wrench_check_test.sh SOURCE_DIR BUILD_DIR
set -uo pipefail
name=fri_check_wrench
root="$1"
build="$2"
source "$root/tests/lab_sim/lab_record_common.sh"  # fri_check_port
out="$build/fri_check_wrench"
check="$build/bin/fri_check"
sim="$build/bin/fri_sim_krc"
params="$root/params/sensors/fri.yaml"
sensor="$root/params/sensors/wts0614.yaml"
for t in "$check" "$sim"; do [ -x "$t" ] || { echo "$name: $t missing" >&2; exit 1; }; done
rm -rf "$out"
mkdir -p "$out/krl_tool"
sed 's/^\$STIFFNESS\.FRAMETYPE = #BASE/$STIFFNESS.FRAMETYPE = #TOOL/' "$root/krc/TactileServo.src" >"$out/krl_tool/TactileServo.src"
cp "$root/krc/TactileServo.dat" "$out/krl_tool/"
grep -q '^\$STIFFNESS\.FRAMETYPE = #TOOL' "$out/krl_tool/TactileServo.src" || { echo "$name: no #TOOL copy" >&2; exit 1; }
base_krl="$root/krc/TactileServo.src"
tool_krl="$out/krl_tool/TactileServo.src"
failures=0

# record FILE SIM_ARGS...: fri_check --monitor --record FILE against fri_sim_krc SIM_ARGS
record() {
  local file="$1"
  shift
  "$check" --monitor --params "$params" --port 0 --bind 127.0.0.1 --cycles 300 --seconds 60 --idle-timeout 5 \
    --period-tolerance 0.9 --max-jitter-ms 1000 --record "$file" >"$file.log" 2>&1 &
  local pid=$! port
  port=$(fri_check_port "$file.log" "$pid")
  [ -n "$port" ] || return 1
  "$sim" --port "$port" --cycles 400 "$@" >"$file.sim.log" 2>&1
  wait "$pid"
  [ "$(wc -l <"$file")" -gt 100 ] || { cat "$file.log"; echo "$name: $file: too few lines" >&2; return 1; }
}

# expect CODE TEXT COMMAND...: the command's exit code and a line containing TEXT
expect() {
  local code="$1" text="$2"
  shift 2
  local o rc
  o=$("$@" 2>&1)
  rc=$?
  echo "$o"
  if [ "$rc" -ne "$code" ] || ! grep -qF -- "$text" <<<"$o"; then
    echo "FAIL: expected exit $code and '$text', got exit $rc" >&2
    failures=$((failures + 1))
  else
    echo "ok: exit $rc, '$text'"
  fi
}

side="500,0,400,0,90,180"  # the flange z horizontal (base -x): the pad faces sideways
down="500,0,400,0,0,180"
weigh="$check --wrench-check --mass 1 --params $params"
record "$out/tare.csv" --krl "$base_krl" --pose "$side" || exit 1
record "$out/loaded.csv" --krl "$base_krl" --pose "$side" --wrench 0,0,-9.80665 || exit 1
expect 0 "verdict: frame correct" $weigh --tare "$out/tare.csv" --loaded "$out/loaded.csv"
record "$out/tare_tool.csv" --krl "$tool_krl" --pose "$side" || exit 1
record "$out/loaded_tool.csv" --krl "$tool_krl" --pose "$side" --wrench 0,0,-9.80665 || exit 1
expect 3 "verdict: frame is tool not base" $weigh --tare "$out/tare_tool.csv" --loaded "$out/loaded_tool.csv"
record "$out/loaded_reversed.csv" --krl "$base_krl" --pose "$side" --wrench 0,0,9.80665 || exit 1
expect 3 "verdict: sign inverted" $weigh --tare "$out/tare.csv" --loaded "$out/loaded_reversed.csv"
record "$out/loaded_heavy.csv" --krl "$base_krl" --pose "$side" --wrench 0,0,-12.2583 || exit 1
expect 3 "verdict: magnitude off" $weigh --tare "$out/tare.csv" --loaded "$out/loaded_heavy.csv"
record "$out/tare_down.csv" --krl "$tool_krl" --pose "$down" || exit 1
record "$out/loaded_down.csv" --krl "$tool_krl" --pose "$down" --wrench 0,0,-9.80665 || exit 1
expect 3 "verdict: undetermined (in this pose two readings" $weigh --tare "$out/tare_down.csv" --loaded "$out/loaded_down.csv"

poses=("500,0,400,0,0,180" "500,0,400,0,0,120" "500,0,400,0,60,180")
ok=() heavy=()
for i in 0 1 2; do
  record "$out/rest_$i.csv" --krl "$base_krl" --pose "${poses[$i]}" --pad-load 0.2,0,0,20 || exit 1
  record "$out/rest_heavy_$i.csv" --krl "$base_krl" --pose "${poses[$i]}" --pad-load 0.5,0,0,20 || exit 1
  ok+=("$out/rest_$i.csv")
  heavy+=("$out/rest_heavy_$i.csv")
done
load="$check --load-data --params $params --sensor-params $sensor"
expect 0 "verdict: load data OK" $load "${ok[@]}"
expect 3 "verdict: mass off by +0.300 kg" $load "${heavy[@]}"
expect 3 "pad_mass_kg: 0.500" $load "${heavy[@]}"

echo "$name: $failures failure(s)"
[ "$failures" -eq 0 ]
