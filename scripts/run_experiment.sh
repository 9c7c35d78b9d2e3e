#!/usr/bin/env bash
# The main job: installs what is missing, builds, runs the headless experiment.
# (Until the simulator lands this runs the feature extractor on the shipped
# sample recording and compares it with the recording's analytic truth.)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/setup_deps.sh"
bash "$root/scripts/build.sh"
out="$root/out/sample"
mkdir -p "$out"
"$root/build/bin/tactile_features" "$root/data/sample_recording.csv" > "$out/features.jsonl"
/usr/bin/python3 "$root/scripts/feature_summary.py" "$out/features.jsonl" "$root/data/sample_recording_truth.csv"
echo "features: $out/features.jsonl"
echo "tactile_features tool: $root/build/bin/tactile_features"
