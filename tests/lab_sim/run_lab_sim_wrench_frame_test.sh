#!/usr/bin/env bash
# ctest lab_sim_wrench_frame: lab_sim's KRC sends estExtTcpFT in the axes
# its KRL program's $STIFFNESS.FRAMETYPE says (lab_sim --krl). The bring-up
# scene (the pad pressed on a bar from the start, flange pointing down) runs
# twice in monitor mode, with krc/TactileServo.src (#BASE) and with a copy
# set to #TOOL; fri_check --monitor --record records 300 packets of each.
# Checked on the last packet of each: the pressed force is over 1 N, and the
# #TOOL recording's force is the #BASE recording's turned into the flange's
# axes (R^T f, R from msrCartPos) within 0.01 N (float32 packets, the same
# world and press in both runs). fri_check listens on an ephemeral port.
#   run_lab_sim_wrench_frame_test.sh SOURCE_DIR BUILD_DIR
set -uo pipefail
name=lab_sim_wrench_frame
root="$1"
build="$2"
source "$root/tests/lab_sim/lab_record_common.sh"  # lab_record_init, lab_record
lab_record_init wrench_frame
mkdir -p "$out/krl_tool"
sed 's/^\$STIFFNESS\.FRAMETYPE = #BASE/$STIFFNESS.FRAMETYPE = #TOOL/' "$root/krc/TactileServo.src" >"$out/krl_tool/TactileServo.src"
cp "$root/krc/TactileServo.dat" "$out/krl_tool/"

# run NAME KRL: lab_sim --krl KRL in monitor mode, recorded by fri_check
run() {
  lab_record "$1" 300 "$2" --duration 2 || return 1
  cat "$out/$1.csv.log" "$out/$1.lab.log"
}
run base "$root/krc/TactileServo.src" || exit 1
run tool "$out/krl_tool/TactileServo.src" || exit 1
grep -q "estExtTcpFT in tool axes" "$out/tool.lab.log" || { echo "$name: lab_sim did not read #TOOL" >&2; exit 1; }
/usr/bin/python3 - "$out/base.csv" "$out/tool.csv" <<'PY'
import sys
def last(path):
    rows = [l.split(",") for l in open(path) if l[0].isdigit()]
    assert len(rows) >= 100, f"{path}: {len(rows)} packets"
    v = [float(x) for x in rows[-1]]
    R = [[v[3], v[4], v[5]], [v[7], v[8], v[9]], [v[11], v[12], v[13]]]
    return R, v[15:18]
Rb, fb = last(sys.argv[1])
Rt, ft = last(sys.argv[2])
turned = [sum(Rt[i][k] * fb[i] for i in range(3)) for k in range(3)]  # R^T f
err = max(abs(a - b) for a, b in zip(turned, ft))
norm = sum(x * x for x in fb) ** 0.5
print(f"base {fb}, tool {ft}, base turned into the flange's axes {turned}: max difference {err:.5f} N, |f| {norm:.3f} N")
ok = norm > 1.0 and err < 0.01
print("lab_sim_wrench_frame:", "PASS" if ok else "FAIL")
sys.exit(0 if ok else 1)
PY
