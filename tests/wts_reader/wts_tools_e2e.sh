#!/usr/bin/env bash
# wts_sim (simulated WTS0614 on a PTY, separate process) -> wts_read -> checks.
#   wts_tools_e2e.sh BIN_DIR
# 1. ramp pattern, plain periodic: 5 CSV lines of 84 raw counts, each line a ramp
#    with step 40 counts between consecutive {s} cells (mod 4096);
# 2. same with RLE, single-frame polling and garbage between packets (--garbage 0.3);
# 3. the frames of (1) as a recording served by wts_sim come back byte-identical;
# 4. newtons piped into tactile_features: one JSON object per frame;
# 5. scheduled faults (--fault): two taxels stuck at 3000 counts from the
#    start, the device unplugged at 0.5-1.0 s: every frame carries the stuck
#    taxels, the driver logs Disconnected then Reconnected and reads on; a
#    fault that needs a force model, or out of range, is refused (exit 2,
#    the entry and the key named).
set -euo pipefail
BIN=$1
TMP=$(mktemp -d)
SIM_PID=
cleanup() { [ -n "$SIM_PID" ] && kill "$SIM_PID" 2>/dev/null; wait 2>/dev/null || true; rm -rf "$TMP"; }
trap cleanup EXIT

start_sim() {
  "$BIN/wts_sim" --link "$TMP/wts0" --duration 30 "$@" > "$TMP/sim.out" 2> "$TMP/sim.err" &
  SIM_PID=$!
  for _ in $(seq 100); do [ -e "$TMP/wts0" ] && return 0; sleep 0.05; done
  echo "FAIL: wts_sim did not create $TMP/wts0"; cat "$TMP/sim.err"; exit 1
}
stop_sim() { kill "$SIM_PID"; wait "$SIM_PID" || true; SIM_PID=; }

check_ramp() {  # file
  /usr/bin/python3 - "$1" <<'PY'
import sys
lines = [l for l in open(sys.argv[1]).read().splitlines() if l]
assert len(lines) == 5, f"expected 5 lines, got {len(lines)}"
for l in lines:
    v = [int(x) for x in l.split(',')]
    assert len(v) == 84, f"expected 84 values, got {len(v)}"
    for i in range(1, 84):
        assert (v[i] - v[i - 1]) % 4096 == 40, f"cell {i}: {v[i-1]} -> {v[i]} is not a 40-count ramp step"
print("ramp ok:", len(lines), "frames")
PY
}

start_sim --pattern ramp
grep -q "^device: $TMP/wts0" "$TMP/sim.out"
"$BIN/wts_read" --device "$TMP/wts0" --periodic-ms 5 --count 5 --raw > "$TMP/a.csv"
check_ramp "$TMP/a.csv"
stop_sim

start_sim --pattern ramp --garbage 0.3 --seed 5
"$BIN/wts_read" --device "$TMP/wts0" --rle --count 5 --raw > "$TMP/b.csv" 2> "$TMP/b.err"
check_ramp "$TMP/b.csv"
stop_sim

# 3. a recording: what `wts_read --raw` printed is what `wts_sim --recording` serves
start_sim --recording "$TMP/a.csv"
"$BIN/wts_read" --device "$TMP/wts0" --count 5 --raw > "$TMP/r.csv"   # single-frame polling: none skipped
cmp "$TMP/a.csv" "$TMP/r.csv" || { echo "FAIL: recording round trip"; diff "$TMP/a.csv" "$TMP/r.csv" | head; exit 1; }
stop_sim

start_sim --pattern blob
"$BIN/wts_read" --device "$TMP/wts0" --periodic-ms 5 --count 4 | "$BIN/tactile_features" - > "$TMP/c.json"
[ "$(grep -c '"status":"ok"' "$TMP/c.json")" -eq 4 ] || { echo "FAIL: features"; cat "$TMP/c.json"; exit 1; }
stop_sim
# 5. scheduled faults
start_sim --pattern zero --fault '{kind: stuck, rows: 0, cols: [0, 1], counts: 3000}' \
  --fault '{kind: disconnect, start_s: 0.5, duration_s: 0.5}'
"$BIN/wts_read" --device "$TMP/wts0" --periodic-ms 10 --count 100 --raw > "$TMP/f.csv" 2> "$TMP/f.err"
/usr/bin/python3 - "$TMP/f.csv" "$TMP/f.err" <<'PY'
import sys
lines = [l for l in open(sys.argv[1]).read().splitlines() if l]
err = open(sys.argv[2]).read()
assert len(lines) == 100, f"expected 100 frames, got {len(lines)}"
for l in lines:
    v = [int(x) for x in l.split(',')]
    assert v[:2] == [3000, 3000] and not any(v[2:]), f"not the stuck taxels on a zero pad: {v[:6]}"
i, j = err.find("link Disconnected"), err.find("link Reconnected")
assert 0 <= i < j, f"no Disconnected then Reconnected in: {err}"
print("faults ok:", len(lines), "frames, reconnected")
PY
stop_sim
grep -q "unplugged (--fault disconnect)" "$TMP/sim.err" && grep -q "plugged back" "$TMP/sim.err" \
  || { echo "FAIL: wts_sim did not log the unplug"; cat "$TMP/sim.err"; exit 1; }
for bad in "{kind: calibration, scale: 2}|calibration needs a force model" \
           "{kind: dead, rows: [0, 9]}|faults[0].rows = [0, 9]: must be [first, last] within [0, 5]"; do
  rc=0
  "$BIN/wts_sim" --fault "${bad%%|*}" > /dev/null 2> "$TMP/bad.err" || rc=$?
  [ "$rc" -eq 2 ] && grep -qF "${bad#*|}" "$TMP/bad.err" || { echo "FAIL: --fault '${bad%%|*}'"; cat "$TMP/bad.err"; exit 1; }
done
echo "wts tools e2e: ok"
