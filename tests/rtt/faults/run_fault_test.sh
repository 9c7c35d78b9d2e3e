#!/usr/bin/env bash
# ctest rtt_fault_<name>: one fault while the arm slides the bent bar at the
# fastest speed the controller supports, through the simulated deployment
# (the OCL deployer, tactile::SimClock as fast as possible: deterministic,
# not a timed test), then the time-series checks of check_fault_run.py.
#   run_fault_test.sh SOURCE_DIR BUILD_DIR NAME     NAME: none|contact_lost|stale|disconnect|nan|saturated
# The deployer runs tests/rtt/faults/fault_<name>.ops from deployments/ (its
# own checks: the steps, the end status); its report file is moved to
# BUILD_DIR/fault_test/<name>/. Environment: OROCOS (default /opt/orocos),
# DEPLOYER (default $OROCOS/bin/deployer-gnulinux; the sanitizer builds: their wrapper).
set -uo pipefail
src="$1"; build="$2"; name="$3"
orocos="${OROCOS:-/opt/orocos}"
out="$build/fault_test/$name"
rm -rf "$out"; mkdir -p "$out"
dep="$src/deployments"
rm -f "$dep/fault_$name.dat"
(cd "$dep" && RTT_COMPONENT_PATH="$build/lib/orocos:$orocos/lib/orocos" \
   "${DEPLOYER:-$orocos/bin/deployer-gnulinux}" --check -lwarning -s "../tests/rtt/faults/fault_$name.ops" < /dev/null) \
   > "$out/deployer.log" 2>&1
rc=$?
grep -E "^\[(PASS|FAIL)\]|ops checks|deployment step failed|\[TimedPhaseExperiment\] finished" "$out/deployer.log"
[ "$rc" -eq 0 ] || { echo "deployer exit $rc (see $out/deployer.log)"; exit 1; }
grep -qE "ops checks: [1-9][0-9]* run, 0 failed" "$out/deployer.log" || { echo "the deployment's checks failed"; exit 1; }
[ -s "$dep/fault_$name.dat" ] || { echo "no report file deployments/fault_$name.dat"; exit 1; }
mv "$dep/fault_$name.dat" "$out/report.dat"
prog=bent_bar_fast.yaml
[ "$name" = contact_lost ] && prog=bent_bar_fast_contact_loss.yaml
/usr/bin/python3 "$src/tests/rtt/faults/check_fault_run.py" "$name" "$out/report.dat" \
  "$src/tests/rtt/faults/fault_$name.ops" "$src/tests/rtt/faults/$prog"
