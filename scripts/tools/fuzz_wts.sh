#!/usr/bin/env bash
# Build the WTS libFuzzer targets with clang (ASan + UBSan) into build-fuzz-wts
# and run each of them.
#
#   scripts/tools/fuzz_wts.sh [RUNS] [MAX_SECONDS]      defaults: 10000000 runs, 1800 s guard
#
# Targets (core/wts/fuzz/):
#   fuzz_wts_parser  arbitrary bytes in arbitrary chunks -> Parser -> FrameDecoder
#   fuzz_wts_frame   arbitrary payloads straight into FrameDecoder + packet round trip
# The seed corpus (valid plain/RLE frames and commands) is written by this script.
# Exit status is non-zero if a fuzzer finds a crash / sanitizer report.
set -euo pipefail
RUNS=${1:-10000000}
MAXT=${2:-1800}
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
SRC=${TACTILE_SRC:-$ROOT}
BUILD=${TACTILE_FUZZ_BUILD:-$ROOT/build-fuzz-wts}
command -v clang++ >/dev/null || { echo "fuzz_wts.sh: clang++ not found (apt-get install clang)" >&2; exit 2; }

cmake -S "$SRC" -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DTACTILE_BUILD_FUZZERS=ON -DTACTILE_BUILD_TESTS=OFF -DTACTILE_BUILD_BENCHMARKS=OFF -DTACTILE_WITH_RTT=OFF >/dev/null
cmake --build "$BUILD" -j2 --target fuzz_wts_parser fuzz_wts_frame

CORPUS="$BUILD/wts_corpus"
mkdir -p "$CORPUS/parser" "$CORPUS/frame"
/usr/bin/python3 - "$CORPUS" <<'PY'
import os, struct, sys
root = sys.argv[1]
T = []
for i in range(256):
    c = i << 8
    for _ in range(8):
        c = ((c << 1) ^ 0x1021) if c & 0x8000 else (c << 1)
    T.append(c & 0xFFFF)
def crc(b, c=0xFFFF):
    for x in b:
        c = T[(c ^ x) & 0xFF] ^ (c >> 8)
    return c
def pkt(i, p):
    h = bytes([0xAA, 0xAA, 0xAA, i]) + struct.pack('<H', len(p)) + p
    return h + struct.pack('<H', crc(h))
assert pkt(0x20, b'\x00')[-2:] == bytes([0x8F, 0x83])
cells = [0] * 84; cells[37] = 1000; cells[38] = 500
plain = struct.pack('<IB', 1234, 0) + b''.join(struct.pack('<H', v) for v in cells)
rle, i = b'', 0
while i < 84:
    run = 1
    while i + run < 84 and run < 15 and cells[i + run] == cells[i]: run += 1
    rle += struct.pack('<H', cells[i] | (run << 12)); i += run
rlep = struct.pack('<IB', 1234, 1) + rle
seeds = {
  'frame_plain': pkt(0x00, plain), 'frame_rle': pkt(0x00, rlep),
  'single_plain': pkt(0x20, b'\x00\x00' + plain), 'single_rle': pkt(0x20, b'\x00\x00' + rlep),
  'matrix': pkt(0x30, struct.pack('<HHHHHH', 0, 6, 14, 340, 340, 4095)),
  'error': pkt(0x20, struct.pack('<H', 2)),
  'stream': pkt(0x00, plain) + b'\xAA\x00\xAA\xAA' + pkt(0x00, rlep) + pkt(0x21, b'\x00\x00'),
}
for k, v in seeds.items():
    open(os.path.join(root, 'parser', k), 'wb').write(b'\x10' + v)  # first byte: chunk size
frames = {'plain0': b'\x00' + plain, 'rle0': b'\x00' + rlep, 'plain20': b'\x01\x00\x00' + plain,
          'rle20': b'\x01\x00\x00' + rlep}
for k, v in frames.items():
    open(os.path.join(root, 'frame', k), 'wb').write(v)
PY

status=0
for t in parser frame; do
  echo "== fuzz_wts_$t: -runs=$RUNS -max_total_time=$MAXT"
  (cd "$BUILD" && ./core/wts/fuzz_wts_$t -runs="$RUNS" -max_total_time="$MAXT" -max_len=${MAXLEN:-2048} \
      -print_final_stats=1 "$CORPUS/$t" 2>&1 | tee "$BUILD/fuzz_wts_$t.log" | grep -E "^(INFO: seed|#[0-9]+ *DONE|Done|stat::number_of_executed_units|==[0-9]+==ERROR|SUMMARY)" ) || status=1
  grep -q "stat::number_of_executed_units" "$BUILD/fuzz_wts_$t.log" || status=1
done
exit $status
