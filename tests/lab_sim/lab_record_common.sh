# Shared by the bring-up check tests (run_lab_sim_known_weight_test.sh,
# run_lab_sim_load_data_test.sh, run_lab_sim_wrench_frame_test.sh): their
# output folder and one recording of lab_sim's KRC in monitor mode by
# fri_check. Sourced; needs name, root and build set.
#
#   lab_record_init DIR [TOOL...]
# out=BUILD/lab_sim_test/DIR, emptied; exits when one of the tools (default
# lab_sim and fri_check) is not built.
lab_record_init() {
  out="$build/lab_sim_test/$1"
  shift
  [ $# -gt 0 ] || set -- lab_sim fri_check
  for t in "$@"; do
    [ -x "$build/bin/$t" ] || { echo "$name: $build/bin/$t missing" >&2; exit 1; }
  done
  rm -rf "$out"
  mkdir -p "$out"
}
#
#   fri_check_port LOG PID
# The port fri_check (started in the background as PID, its console in LOG)
# listens on, once it says so (up to 4 s); empty, LOG shown and PID killed
# when it never does.
fri_check_port() {
  local log="$1" pid="$2" port=""
  for _ in $(seq 200); do
    port=$(sed -n 's/^fri_check: listening on 127\.0\.0\.1:\([0-9]*\),.*/\1/p' "$log")
    [ -n "$port" ] && break
    sleep 0.02
  done
  [ -n "$port" ] || { cat "$log" >&2; echo "$name: fri_check did not listen" >&2; kill "$pid"; }
  echo "$port"
}
#
#   lab_record TAG CYCLES KRL [LAB_SIM ARGS...]
# fri_check --monitor --record OUT/TAG.csv (CYCLES packets, fri.yaml, an
# ephemeral port on loopback; its console in OUT/TAG.csv.log), then lab_sim on
# the bring-up scene against it (friOpen at 0, the KRL program KRL, the
# given arguments; its console in OUT/TAG.lab.log); returns when fri_check has
# its packets, lab_sim stopped. Non-zero when fri_check never listened.
lab_record() {
  local tag="$1" cycles="$2" krl="$3"
  shift 3
  local rec="$out/$tag.csv"
  "$build/bin/fri_check" --monitor --params "$root/params/sensors/fri.yaml" --port 0 --bind 127.0.0.1 \
    --cycles "$cycles" --seconds 60 --idle-timeout 10 --period-tolerance 0.9 --max-jitter-ms 1000 --record "$rec" \
    >"$rec.log" 2>&1 &
  local pid=$! port
  port=$(fri_check_port "$rec.log" "$pid")
  [ -n "$port" ] || return 1
  "$build/bin/lab_sim" "$root/params/lab_scenes/bringup_press.yaml" --fri-port "$port" --wts-link "$out/wts_$tag" \
    --krc "0:friOpen" --krl "$krl" "$@" >"$out/$tag.lab.log" 2>&1 &
  local lab=$!
  wait "$pid"
  kill -INT "$lab" 2>/dev/null
  wait "$lab"
}
