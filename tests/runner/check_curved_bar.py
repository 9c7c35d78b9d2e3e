#!/usr/bin/python3
"""One wavy-bar run (params/scenes/curved, scripts/tools/make_curved_bars.py): its
status is the expected one and the true force (timeseries.csv, every cycle of
the run) never exceeded --max-force; with --criteria its scene's criteria
passed (summary.json). Exits 1 otherwise. Usage:
  check_curved_bar.py RUN_DIR --status servo_surface_too_curved --max-force 7 [--criteria]
"""
import argparse
import csv
import json
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run")
    ap.add_argument("--status", required=True, help="expected summary.json status")
    ap.add_argument("--max-force", type=float, required=True, help="N: largest true force allowed")
    ap.add_argument("--criteria", action="store_true", help="the scene's criteria must pass")
    a = ap.parse_args()
    s = json.load(open(f"{a.run}/summary.json"))
    with open(f"{a.run}/timeseries.csv", newline="") as fh:
        peak = max(float(r["force_true"]) for r in csv.DictReader(fh))
    print(f"{a.run}: status {s['status']}, true force peak {peak:.2f} N, "
          f"criteria {'passed' if s['criteria_passed'] else 'failed: ' + '; '.join(s['criteria_failed'])}")
    ok = s["status"] == a.status and peak <= a.max_force and (s["criteria_passed"] or not a.criteria)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
