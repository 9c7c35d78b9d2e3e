#!/usr/bin/env bash
# wts_sim (simulated WTS0614 on a PTY, separate process) -> wts_read -> checks.
#   wts_tools_e2e.sh BIN_DIR
# 1. ramp pattern, plain periodic: 5 CSV lines of 84 raw counts, each line a ramp
#    with step 40 counts between consecutive {s} cells (mod 4096);
# 2. same with RLE, single-frame polling and garbage between packets (--garbage 0.3);
# 3. the frames of (1) as a recording served by wts_sim come back byte-identical;
# 4. newtons piped into tactile_features: one JSON object per frame.
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
echo "wts tools e2e: ok"
