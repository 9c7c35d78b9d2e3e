#!/usr/bin/env bash
# ctest rtt_deployment_<run>: scripts/run_deployment.sh EXPERIMENT [--controller C]
# (the simulated deployment under the OCL deployer) and `tactile_sim run` of
# the same scene, then tests/deploy/check_deployment.py: the experiment's
# criteria and the same summary.
#   run_deployment_test.sh SOURCE_DIR BUILD_DIR EXPERIMENT CONTROLLER
set -uo pipefail
src="$1"; build="$2"; exp="$3"; controller="$4"
run="$exp"; [ "$controller" = proposed ] || run="${exp}_${controller}"
headless="$build/deploy_test/$run"
rm -rf "$headless"; mkdir -p "$headless"
BUILD="$build" DEPLOY_OUT="$build/deploy_out" bash "$src/scripts/run_deployment.sh" "$exp" --controller "$controller"
rc=$?
[ "$rc" -eq 0 ] || { echo "run_deployment.sh exit $rc"; exit 1; }
"$build/bin/tactile_sim" run "$src/params/scenes/$exp.yaml" --controller "$controller" --out "$headless" --no-plots
/usr/bin/python3 "$src/tests/deploy/check_deployment.py" "$exp" "$controller" "$build/deploy_out/$run" "$headless"
