#!/usr/bin/env bash
# ctest lab_sim_faults: the scene's pad faults through lab_sim's WTS device
# (a PTY), read by wts_read (the robot's driver, tactile::wts::WtsDriver).
# lab_sim runs the bring-up scene (the pad pressed on a bar, row 3 firing)
# for 6 s with
#   disconnect 1.0-2.0 s   the device unplugged (the PTY closed) and plugged
#                          back behind the same link: the driver must see the
#                          hangup and reconnect;
#   stuck from 2.5 s       taxels (0, 0) and (0, 1) read 3000 counts;
#   stale 3.5-4.0 s        the device sends no frame (commands answered).
# wts_read reads raw frames until it is stopped. Checked: the driver logged
# Disconnected then Reconnected, frames arrived after the reconnection, the
# last frames carry the stuck taxels and the press, the first do not;
# lab_sim logged each window and counted held frames. Wall clock (about 7 s),
# counts only. UDP port 49972 (nothing listens: no remote is needed).
#   run_lab_sim_faults_test.sh SOURCE_DIR BUILD_DIR
set -uo pipefail
name=lab_sim_faults
root="$1"
build="$2"
source "$root/tests/lab_sim/lab_record_common.sh"  # lab_record_init
lab_record_init faults lab_sim wts_read
faults='faults=[{kind: disconnect, start_s: 1.0, duration_s: 1.0}, {kind: stuck, start_s: 2.5, rows: [0, 0], cols: [0, 1], counts: 3000}, {kind: stale, start_s: 3.5, duration_s: 0.5}]'
"$build/bin/lab_sim" "$root/params/lab_scenes/bringup_press.yaml" --fri-port 49972 --wts-link "$out/wts0" \
  --duration 6 --set "$faults" >"$out/lab_sim.log" 2>&1 &
lab=$!
trap 'kill $lab 2>/dev/null || true' EXIT
for _ in $(seq 100); do [ -e "$out/wts0" ] && break; sleep 0.05; done
[ -e "$out/wts0" ] || { cat "$out/lab_sim.log"; echo "$name: lab_sim's PTY did not appear" >&2; exit 1; }
timeout -s INT 5.5 "$build/bin/wts_read" --device "$out/wts0" --periodic-ms 10 --raw >"$out/frames.csv" 2>"$out/wts_read.log"
lab_rc=0
wait "$lab" || lab_rc=$?
cat "$out/lab_sim.log" "$out/wts_read.log"
/usr/bin/python3 - "$out" "$lab_rc" <<'PY'
import re, sys
out, lab_rc = sys.argv[1], int(sys.argv[2])
lab = open(f"{out}/lab_sim.log").read()
drv = open(f"{out}/wts_read.log").read()
frames = [[int(v) for v in l.split(",")] for l in open(f"{out}/frames.csv") if l.strip()]
err = []
if lab_rc != 0:
    err.append(f"lab_sim exit {lab_rc}")
for w in ("WTS unplugged (faults: disconnect)", "WTS plugged back (faults: disconnect)",
          "WTS stream stalled (faults: stale)", "WTS stream resumed (faults: stale)"):
    if w not in lab:
        err.append(f"lab_sim did not log '{w}'")
m = re.search(r"device frames sent (\d+) held (\d+) unplugged (\d+)", lab)
if not m or int(m.group(2)) == 0 or int(m.group(3)) != 1:
    err.append(f"lab_sim's counts: {m.group(0) if m else 'missing'} (held > 0, unplugged 1 expected)")
i_dis, i_rec = drv.find("link Disconnected"), drv.find("link Reconnected")
if i_dis < 0 or i_rec < i_dis:
    err.append("wts_read did not log Disconnected, then Reconnected")
press = lambda f: max(f[3 * 14:4 * 14]) > 0
stuck = lambda f: f[0] == 3000 and f[1] == 3000
if len(frames) < 150:
    err.append(f"{len(frames)} frames (at least 150 expected in ~4.4 s of streaming)")
else:
    if stuck(frames[0]) or not press(frames[0]):
        err.append(f"first frame: stuck taxels or no press: {frames[0][:16]}")
    if not all(stuck(f) and press(f) for f in frames[-20:]):
        err.append(f"last frames: not the stuck taxels (3000) and the press: {frames[-1][:16]}")
print(f"lab_sim_faults: {len(frames)} frames, {'PASS' if not err else 'FAIL: ' + '; '.join(err)}")
sys.exit(1 if err else 0)
PY
