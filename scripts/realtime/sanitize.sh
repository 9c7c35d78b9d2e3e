#!/usr/bin/env bash
# The whole test suite (unit, integration, RTT components in-process and the
# OCL deployer running deployments/) under the sanitizers, in separate build
# directories, with the build and test times reported.
#
#   scripts/realtime/sanitize.sh [asan|tsan|all] [ctest args...]     default: asan
#
#   asan  ASan + UBSan (-fsanitize=address,undefined, UBSan not recoverable:
#         a finding fails its test), build-asan/
#   tsan  TSan (-fsanitize=thread: the components' activities are threads),
#         build-tsan/
# Orocos (RTT, OCL, the deployer) is not instrumented: the deployer tests run
# it through a wrapper that preloads the sanitizer runtime (it must come first
# in the process). Suppressions, each justified in its file:
# scripts/realtime/sanitizers/lsan.supp, ubsan.supp, tsan.supp.
# Benchmarks are not built (timing under a sanitizer means nothing).
# Environment: TACTILE_JOBS (default 2), TACTILE_SAN_BUILD_<MODE> (build dir),
# TACTILE_SAN_TARGETS (build only these targets, with ctest args selecting
# their tests, e.g. TACTILE_SAN_TARGETS="test_fri_bridge_component"
# scripts/realtime/sanitize.sh tsan -R FriBridgeComponent; default: everything).
# Exit status non-zero if the build fails or any test fails (any finding).
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
mode=${1:-asan}
shift || true
jobs=${TACTILE_JOBS:-2}
supp="$root/scripts/realtime/sanitizers"
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$root}
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)

run_mode() {
  local m=$1 flags rt build t0 t_build t_test rc
  case "$m" in
    asan) flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
          rt=$(gcc -print-file-name=libasan.so)
          build=${TACTILE_SAN_BUILD_ASAN:-$root/build-asan} ;;
    tsan) flags="-fsanitize=thread -fno-omit-frame-pointer"
          rt=$(gcc -print-file-name=libtsan.so)
          build=${TACTILE_SAN_BUILD_TSAN:-$root/build-tsan} ;;
    *) echo "sanitize.sh: unknown mode '$m' (asan, tsan, all)" >&2; return 2 ;;
  esac
  mkdir -p "$build"
  # Also while building: gtest_discover_tests runs each test binary to list its tests.
  # detect_odr_violation=1 (not 2): the static cores (e.g. tactile_servo_core)
  # are linked into each component library and into the test executables that
  # load those libraries, so the same global (the same definition, same size:
  # e.g. kControllerModeNames of control_law.cpp) exists once per module; level
  # 1 still reports a global defined twice with different sizes (a real ODR
  # conflict). Found by this script (level 2); see the report in README.md.
  export ASAN_OPTIONS="detect_leaks=1:halt_on_error=1:detect_stack_use_after_return=1:detect_odr_violation=1"
  export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$supp/ubsan.supp"
  export TSAN_OPTIONS="halt_on_error=0:exitcode=66:second_deadlock_stack=1:suppressions=$supp/tsan.supp"
  # RtSoakSim's "nothing grows" bound: the sanitizer's allocator keeps freed
  # blocks (ASan's quarantine, up to 256 MB) and its own metadata, so the
  # deployer's per-minute script strings raise its RSS by about 1.2 MB a
  # minute here without a leak (LSan checks the leaks).
  export RT_SOAK_RSS_GROWTH_KB=16384
  # The uninstrumented deployer with the sanitizer runtime first in the process.
  local deployer
  deployer=$(command -v deployer-gnulinux || echo /opt/orocos/bin/deployer-gnulinux)
  # Leak detection is off in the deployer process only: OCL's deployer and
  # RTT (uninstrumented, third party) leave their one-time allocations
  # (plugin loader, type registry, logger) at exit, and a stack-based LSan
  # suppression of those libraries would also hide leaks of our components,
  # which RTT's factories construct. Our components' leaks are checked
  # in-process by tests/rtt/test_*_component (leak detection on); memory
  # errors (ASan) and UBSan stay on in the deployer tests.
  # TSan in the deployer: ignore_noninstrumented_modules=1, the mode TSan has
  # for a process of mostly uninstrumented libraries (here RTT, OCL, roscpp
  # and rtt_roscomm's generated ROS transports): the accesses that
  # uninstrumented code makes through the runtime's interceptors (memcpy,
  # close, ...) are not checked, everything our instrumented code does is.
  # Found necessary by the ROS tests: rtt_roscomm's transports copy a
  # message's strings (libstdc++, called from their uninstrumented code) in
  # the component's thread and in the RosPublishActivity's, handed over by
  # RTT's uninstrumented lock-free buffer; no frame of theirs is in the stack
  # for a suppression to name. What it costs: a race in a libstdc++ routine
  # that our component calls out of line (a std::string copy) is not seen in
  # the deployer tests; the in-process component tests keep the full check.
  # The deployer's reports go to files (log_path): the deployer tests run it
  # through scripts that keep its output in logs of their own or not at all
  # (the ROS tests); the script counts the files' reports after ctest.
  rm -rf "$build/san_reports"
  mkdir -p "$build/san_reports"
  cat > "$build/deployer-san" <<EOF
#!/bin/sh
ASAN_OPTIONS="\${ASAN_OPTIONS:+\$ASAN_OPTIONS:}detect_leaks=0:log_path=$build/san_reports/deployer" \\
UBSAN_OPTIONS="\${UBSAN_OPTIONS:+\$UBSAN_OPTIONS:}log_path=$build/san_reports/deployer" \\
TSAN_OPTIONS="\${TSAN_OPTIONS:+\$TSAN_OPTIONS:}ignore_noninstrumented_modules=1:log_path=$build/san_reports/deployer" \\
LD_PRELOAD="$rt\${LD_PRELOAD:+:\$LD_PRELOAD}" exec "$deployer" "\$@"
EOF
  chmod +x "$build/deployer-san"
  t0=$SECONDS
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_PREFIX_PATH=/opt/orocos \
    "${launcher[@]}" -DTACTILE_WITH_RTT=ON -DTACTILE_BUILD_BENCHMARKS=OFF \
    -DCMAKE_C_FLAGS="$flags" -DCMAKE_CXX_FLAGS="$flags" \
    -DCMAKE_EXE_LINKER_FLAGS="$flags" -DCMAKE_SHARED_LINKER_FLAGS="$flags" \
    -DTACTILE_DEPLOYER="$build/deployer-san" >"$build/sanitize_cmake.log" 2>&1 \
    || { echo "sanitize.sh[$m]: cmake failed, see $build/sanitize_cmake.log" >&2; return 1; }
  local targets=()
  for t in ${TACTILE_SAN_TARGETS:-}; do targets+=(--target "$t"); done
  if ! cmake --build "$build" -j"$jobs" "${targets[@]}" >"$build/sanitize_build.log" 2>&1; then
    echo "sanitize.sh[$m]: build failed, see $build/sanitize_build.log" >&2
    return 1
  fi
  t_build=$((SECONDS - t0))
  t0=$SECONDS
  (
    cd "$build" || exit 1
    # (options above) halt_on_error / exitcode: a report fails the test that produced it.
    ctest -j"$jobs" --timeout 1800 --output-on-failure "$@" >"$build/sanitize_ctest.log" 2>&1
  )
  rc=$?
  t_test=$((SECONDS - t0))
  local summary
  summary=$(grep -E "tests passed|tests failed out of" "$build/sanitize_ctest.log" | tail -1)
  echo "sanitize.sh[$m]: build ${t_build} s, ctest ${t_test} s: ${summary:-no summary} (log: $build/sanitize_ctest.log)"
  grep -E "^\s+[0-9]+ - .*\(Failed|Timeout|SEGFAULT|Subprocess" "$build/sanitize_ctest.log" || true
  # The reports: in the test output (in-process tests) and in the deployer
  # processes' report files (san_reports/deployer.<pid>).
  local n logs
  mapfile -t logs < <(find "$build/san_reports" -type f 2>/dev/null)
  n=$(cat "$build/sanitize_ctest.log" "${logs[@]}" |
      grep -cE "ERROR: (AddressSanitizer|LeakSanitizer)|runtime error:|WARNING: ThreadSanitizer")
  echo "sanitize.sh[$m]: sanitizer reports: $n (the test output and ${#logs[@]} deployer report files in $build/san_reports)"
  return $rc
}

status=0
if [ "$mode" = all ]; then
  run_mode asan "$@" || status=1
  run_mode tsan "$@" || status=1
else
  run_mode "$mode" "$@" || status=1
fi
exit $status
