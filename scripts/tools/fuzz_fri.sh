#!/usr/bin/env bash
# Build the FRI libFuzzer target with clang (ASan + UBSan) into build-fuzz-fri
# and run it. Usage: scripts/tools/fuzz_fri.sh [RUNS] [extra libFuzzer args...]
#   RUNS defaults to 10000000 (the acceptance run); e.g. scripts/tools/fuzz_fri.sh 100000
# Needs: clang (Debian package "clang"), which ships libFuzzer.
# Exit status is non-zero on a finding (crash, sanitizer report, invariant trap).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
SRC=${TACTILE_SRC:-$ROOT}
BUILD=${TACTILE_FUZZ_BUILD:-$ROOT/build-fuzz-fri}
RUNS=${1:-10000000}
[ $# -gt 0 ] && shift
CXX=$(command -v clang++ || command -v clang++-14 || true)
[ -n "$CXX" ] || { echo "fuzz_fri.sh: clang++ not found (apt-get install clang)" >&2; exit 1; }
cmake -S "$SRC" -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER="$CXX" \
  -DTACTILE_BUILD_FUZZERS=ON -DTACTILE_BUILD_TESTS=OFF -DTACTILE_BUILD_BENCHMARKS=OFF -DTACTILE_WITH_RTT=OFF >/dev/null
cmake --build "$BUILD" -j2 --target fuzz_fri_decode

# Seed corpus: well-formed measurement datagrams (MON/CMD, several qualities),
# framed as the target expects ([flags][len u16][datagram]...).
CORPUS="$BUILD/corpus_fri"
mkdir -p "$CORPUS"
/usr/bin/python3 - "$CORPUS" <<'PY'
import struct, sys, os
out = sys.argv[1]
def msr(seq, state, quality, power=0x7F, refl=0):
    b = bytearray(916)
    struct.pack_into('<HHHH', b, 0, seq, refl, 916, 0x2006)
    struct.pack_into('<HH', b, 144, state, quality)
    struct.pack_into('<ff', b, 148, 0.001, 0.001)
    struct.pack_into('<HH', b, 180, power, 2)
    pose = [1,0,0,0.5, 0,-1,0,0.0, 0,0,-1,0.4]
    struct.pack_into('<12f', b, 244, *pose)
    return bytes(b)
def framed(flags, dgs):
    return bytes([flags]) + b''.join(struct.pack('<H', len(d)) + d for d in dgs)
seeds = {
  'mon': framed(0, [msr(1, 1, 3), msr(2, 1, 3)]),
  'cmd': framed(0, [msr(1, 1, 3), msr(2, 2, 3, refl=1), msr(3, 2, 2, refl=2), msr(4, 2, 1, refl=3), msr(5, 1, 3, refl=4)]),
  'dup': framed(0, [msr(7, 2, 3), msr(7, 2, 3), msr(6, 2, 3), msr(9, 2, 3, power=0)]),
  'desired': bytes([1]) + struct.pack('<7d', 0.5, 0.1, 0.4, 1, 0, 0, 0) + framed(0, [msr(1, 2, 3), msr(2, 2, 3, refl=1)])[1:],
}
for k, v in seeds.items():
    open(os.path.join(out, 'seed_' + k), 'wb').write(v)
PY
# Past findings stay in the corpus as regression inputs.
cp "$ROOT"/core/fri/fuzz/regressions/* "$CORPUS"/ 2>/dev/null || true
FUZZER=$(find "$BUILD" -type f -name fuzz_fri_decode -perm -u+x | head -1)
echo "== fuzz_fri_decode: -runs=$RUNS"
cd "$BUILD"
status=0
"$FUZZER" -runs="$RUNS" -max_len=8192 -print_final_stats=1 "$@" "$CORPUS" > "$BUILD/fuzz_fri_decode.log" 2>&1 || status=1
grep -E "^(INFO: seed|#[0-9]+ *DONE|Done|stat::number_of_executed_units|==[0-9]+==ERROR|SUMMARY)" "$BUILD/fuzz_fri_decode.log" || true
grep -q "stat::number_of_executed_units" "$BUILD/fuzz_fri_decode.log" || status=1
exit $status
