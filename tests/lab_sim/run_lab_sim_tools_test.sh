#!/usr/bin/env bash
# ctest lab_sim_tools: lab_sim alone against the bench tools, over loopback
# UDP and a PTY. lab_sim runs the bring-up scene (params/lab_scenes/
# bringup_press.yaml: the pad pressed on a bar from the start) with the KRC
# script "0:friOpen,1.0:friStart" (MON for 1 s, then CMD); fri_check (the FRI
# bridge core over UDP) holds the pose where CMD is entered until it has
# taken 3000 packets; wts_read reads 50 raw frames from lab_sim's PTY
# meanwhile. Then lab_sim is stopped with SIGTERM (its clean exit and
# summary) and check_lab_sim_tools.py checks that packets flowed, frames
# arrived and carried the press, the arm did not move in MON and held
# fri_check's pose in CMD. Wall clock (about 3 s of KRC cycles) but no timing
# asserted: counts and bounds only. The KRC's link held at PERFECT
# (--quality-rule off): the test is of the tools' plumbing, and on a loaded
# machine a late answer would rightly end command mode (the rating from the
# answers' timing: fri_check_monitor's burst cases, the rehearsals).
#   run_lab_sim_tools_test.sh SOURCE_DIR BUILD_DIR
# UDP port 49970 (fri.yaml's 49938 and the FRI burst test's 49958 stay free).
set -uo pipefail
name=lab_sim_tools
root="$1"
build="$2"
port=49970
out="$build/lab_sim_test/tools"
py=/usr/bin/python3
for t in lab_sim fri_check wts_read; do
  [ -x "$build/bin/$t" ] || { echo "$name: $build/bin/$t missing" >&2; exit 1; }
done
rm -rf "$out"
mkdir -p "$out"
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; }
trap cleanup EXIT

"$build/bin/fri_check" --port $port --bind 127.0.0.1 --cycles 3000 --motion hold --idle-timeout 30 \
  >"$out/fri_check.log" 2>&1 &
fri=$!
pids+=($fri)
for _ in $(seq 100); do grep -q "listening" "$out/fri_check.log" 2>/dev/null && break; sleep 0.05; done
"$build/bin/lab_sim" "$root/params/lab_scenes/bringup_press.yaml" --fri-port $port --wts-link "$out/wts0" \
  --krc "0:friOpen,1.0:friStart" --quality-rule off --truth-out "$out/truth.csv" --truth-period-ms 1 \
  >"$out/lab_sim.log" 2>&1 &
lab=$!
pids+=($lab)
for _ in $(seq 100); do [ -e "$out/wts0" ] && break; sleep 0.05; done
[ -e "$out/wts0" ] || { cat "$out/lab_sim.log"; echo "$name: lab_sim's PTY did not appear" >&2; exit 1; }
timeout 30 "$build/bin/wts_read" --device "$out/wts0" --periodic-ms 10 --count 50 --raw >"$out/frames.csv" 2>"$out/wts_read.log"
wts_rc=$?
fri_rc=0
wait "$fri" || fri_rc=$?
kill -TERM "$lab" 2>/dev/null
lab_rc=0
wait "$lab" || lab_rc=$?
cat "$out/lab_sim.log"
grep -E "state|summary" "$out/fri_check.log"
"$py" "$root/tests/lab_sim/check_lab_sim_tools.py" "$out" "$lab_rc" "$fri_rc" "$wts_rc" \
  "$root/params/lab_scenes/bringup_press.yaml"
